"""The local Beta-spline's basis (docs/local-beta.md) with every joint's bias and tension equal,
derived symbolically from the G2 conditions, and shown to be the memo's B_{b1,b2}.

Run with `python3 scripts/local-beta-derivation.py` (needs SymPy); it prints the middle joint's
solution (A = 1), the four scales, and the difference from the memo's matrix (all zeros).
"""
import sympy as sp
b1,b2,u,w=sp.symbols('beta1 beta2 u w',positive=True)
A,e1,Dt,e2=sp.symbols('A e1 Dt e2')
# Joints a, b, c of one basis function, all (beta1, beta2).
a1,a2,c1,c2=b1,b2,b1,b2
# Its second and third pieces, from the conditions at a and at c (w = 1 - u).
s1=A*(1+3*a1*u+(3*a1**2+sp.Rational(3,2)*a2)*u**2)+e1*u**3
s2w=Dt*(c1**3+3*c1**2*w+(3*c1+sp.Rational(3,2)*c2)*w**2)+e2*w**3
s2=s2w.subs(w,1-u)
# The three conditions at the middle joint b.
eqs=[sp.Eq(s2.subs(u,0),s1.subs(u,1)),
     sp.Eq(sp.diff(s2,u).subs(u,0),b1*sp.diff(s1,u).subs(u,1)),
     sp.Eq(sp.diff(s2,u,2).subs(u,0),b1**2*sp.diff(s1,u,2).subs(u,1)+b2*sp.diff(s1,u).subs(u,1))]
sol=sp.solve(eqs,[e1,Dt,e2],dict=True)[0]
print({k:sp.factor(v.subs(A,1)) for k,v in sol.items()})
S1=sp.expand(s1.subs(sol).subs(A,1)); S2=sp.expand(s2.subs(sol).subs(A,1))
# The segment's basis: c0 (1-u)^3 + c1 S2 + c2 S1 + c3 u^3 = 1
C=sp.symbols('c0:4')
tot=sp.expand(C[0]*(1-u)**3+C[1]*S2+C[2]*S1+C[3]*u**3-1)
cs=sp.solve([tot.coeff(u,k) for k in range(4)],C,dict=True)[0]
print({k:sp.factor(v) for k,v in cs.items()})
d=b2+2*b1**3+4*b1**2+4*b1+2
cols=[sp.expand(cs[C[0]]*(1-u)**3),sp.expand(cs[C[1]]*S2),sp.expand(cs[C[2]]*S1),sp.expand(cs[C[3]]*u**3)]
M=sp.Matrix(4,4,lambda r,c: sp.factor(cols[c].coeff(u,3-r)))
memo=sp.Matrix([[-2*b1**3,2*(b2+b1**3+b1**2+b1),-2*(b2+b1**2+b1+1),2],[6*b1**3,-3*(b2+2*b1**3+2*b1**2),3*(b2+2*b1**2),0],[-6*b1**3,6*(b1**3-b1),6*b1,0],[2*b1**3,b2+4*(b1**2+b1),2,0]])/d
print(sp.simplify(M-memo))
