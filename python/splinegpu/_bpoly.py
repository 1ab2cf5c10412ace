"""`BPoly`: SciPy's piecewise polynomial in the Bernstein basis, any degree, in NumPy (float64
or complex128) on the CPU, with SciPy's semantics and the same checks and construction as
`PPoly` (the two share `Piecewise`), so that SciPy's code meets this package's classes.

Piece i between x_i and x_{i+1} (h = x_{i+1} - x_i, which is negative where x decreases) is
    B(v) = sum_{a=0}^{k} c[a, i] b_{a,k}(s),   s = (v - x_i) / h,
    b_{a,k}(s) = C(k, a) s^a (1 - s)^(k - a).
The identities used below: d/dv B = k / h sum_{a<k} (c_{a+1} - c_a) b_{a,k-1}(s);
int_{x_i}^{v} B = h / (k + 1) sum_{a=1}^{k+1} (c_0 + ... + c_{a-1}) b_{a,k+1}(s);
b_{a,k} = sum_j C(k, a) C(d, j) / C(k + d, a + j) b_{a+j,k+d} (degree raised by d); and the
Bernstein basis sums to 1.
"""

from __future__ import annotations

import math

import numpy as np

from ._helpers import _extrapolate, _is_named
from ._ppoly import Piecewise


def _bernstein(c: np.ndarray, x: np.ndarray, i: np.ndarray, flat: np.ndarray,
               nu: int) -> np.ndarray:
    """Derivative nu of the pieces c (k + 1, m, columns) at flat (in pieces i): (len,
    columns), by de Casteljau's recurrence on each point's piece (differenced nu times
    first)."""
    k = c.shape[0] - 1
    dtype = np.result_type(c, np.float64)
    if nu > k:
        return np.zeros((len(flat), c.shape[2]), dtype=dtype)
    h = x[i + 1] - x[i]
    s = ((flat - x[i]) / h)[None, :, None]
    local = c[:, i, :]
    if nu:
        local = np.diff(local, n=nu, axis=0) * (math.perm(k, nu) / h ** nu)[None, :, None]
    for _ in range(local.shape[0] - 1):
        local = local[:-1] * (1.0 - s) + local[1:] * s
    return local[0].astype(dtype, copy=False)


def _raised(c: np.ndarray, d: int) -> np.ndarray:
    """The coefficients c (k + 1, ...) of the same polynomials written in degree k + d."""
    if d == 0:
        return c
    k = c.shape[0] - 1
    out = np.zeros((k + 1 + d, *c.shape[1:]), dtype=c.dtype)
    for a in range(k + 1):
        for j in range(d + 1):
            out[a + j] += c[a] * (math.comb(k, a) * math.comb(d, j) / math.comb(k + d, a + j))
    return out


class BPoly(Piecewise):
    """`scipy.interpolate.BPoly(c, x, extrapolate=None, axis=0)`: c of shape (k, m, ...)
    Bernstein coefficients (with `axis` a: k and m at c's axes a and a + 1), x of m + 1
    strictly increasing or decreasing breakpoints; calls with nu >= 0, `derivative`,
    `antiderivative`, `integrate`, `extend` (raising the degree of the lower), and the
    constructors `from_power_basis`, `from_derivatives` and `construct_fast`, as SciPy's."""

    def _values(self, c: np.ndarray, flat: np.ndarray, nu: int) -> np.ndarray:
        return _bernstein(c, self.x, self._piece_of(flat), flat, nu)

    def _widths(self) -> np.ndarray:
        """Each piece's signed width, shaped to multiply c[a] (m, ...)."""
        return np.diff(self.x).reshape((-1,) + (1,) * (self.c.ndim - 2))

    def derivative(self, nu: int = 1) -> BPoly:
        """The nu-th derivative as a BPoly of degree k - nu (nu < 0: the antiderivative)."""
        if nu < 0:
            return self.antiderivative(-nu)
        c = self.c
        for _ in range(nu):
            k = c.shape[0] - 1
            c = k * np.diff(c, axis=0) / self._widths()
        if c.shape[0] == 0:
            c = np.zeros((1, *self.c.shape[1:]), dtype=self.c.dtype)
        return self._like(c, self.x, self.extrapolate)

    def antiderivative(self, nu: int = 1) -> BPoly:
        """The nu-th antiderivative, zero at x[0] and continuous, as a BPoly of degree k + nu;
        a periodic extrapolation becomes False, as SciPy's."""
        if nu <= 0:
            return self.derivative(-nu)
        c = self.c
        widths = self._widths()
        for _ in range(nu):
            k1 = c.shape[0]
            integral = np.zeros((k1 + 1, *c.shape[1:]), dtype=c.dtype)
            integral[1:] = np.cumsum(c, axis=0) / k1 * widths
            # Each piece starts at the sum of the whole pieces before it (its last coefficient
            # is its value at its far end: the basis sums to 1 and only b_{k+1,k+1} is 1 there).
            integral[:, 1:] += np.cumsum(integral[-1], axis=0)[:-1]
            c = integral
        extrapolate = False if self.extrapolate == "periodic" else self.extrapolate
        return self._like(c, self.x, extrapolate)

    def integrate(self, a, b, extrapolate=None) -> np.ndarray:
        """The integral from a to b (b < a: its negative), shape c.shape[2:], as SciPy's:
        `extrapolate` None (the polynomial's), True, False (NaN outside the breakpoints) or
        "periodic" (whole periods and the rest, wrapped)."""
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        primitive = self.antiderivative()
        if mode != "periodic":
            primitive.extrapolate = mode
            return primitive(b) - primitive(a)
        sign = 1.0
        a, b = float(a), float(b)
        if a > b:
            a, b, sign = b, a, -1.0
        start, end = self.x[0], self.x[-1]
        period = end - start
        whole, rest = divmod(b - a, period)
        total = whole * (primitive(end) - primitive(start))
        a = start + (a - start) % period
        if a + rest <= end:
            total = total + primitive(a + rest) - primitive(a)
        else:
            total = total + primitive(end) - primitive(a) + primitive(start + a + rest - end) \
                - primitive(start)
        # An array, as SciPy's periodic integral (its other integrals are NumPy scalars).
        return np.asarray(sign * total)

    def extend(self, c, x) -> None:
        """Adds pieces c (k', m', ...) with breakpoints x past either end, as SciPy's: the
        lower of the two degrees raised to the other."""
        c = np.asarray(c)
        k = max(self.c.shape[0], c.shape[0])
        self.c = _raised(self.c, k - self.c.shape[0])
        super().extend(_raised(c, k - c.shape[0]), x)

    @staticmethod
    def _raise_degree(c, d: int) -> np.ndarray:
        """SciPy's private `_raise_degree`: c (k + 1, ...) written in degree k + d."""
        return _raised(np.asarray(c), d)

    @classmethod
    def from_power_basis(cls, pp, extrapolate=None) -> BPoly:
        """The PPoly `pp` (this package's or SciPy's) in the Bernstein basis: on a piece of
        width h, (v - x_i)^d = h^d sum_{j >= d} C(j, d) / C(k, d) b_{j,k}(s)."""
        if not _is_named(pp, "PPoly") or _is_named(pp, "BPoly"):
            raise TypeError(f".from_power_basis only accepts PPoly instances. Got {type(pp)} "
                            f"instead.")
        power = np.asarray(pp.c)
        k = power.shape[0] - 1
        widths = np.diff(np.asarray(pp.x, dtype=np.float64)).reshape(
            (-1,) + (1,) * (power.ndim - 2))
        c = np.zeros_like(power, dtype=np.result_type(power, np.float64))
        for m in range(k + 1):
            d = k - m
            scaled = power[m] * widths ** d / math.comb(k, d)
            for j in range(d, k + 1):
                c[j] += scaled * math.comb(j, d)
        if extrapolate is None:
            extrapolate = pp.extrapolate
        return cls.construct_fast(c, np.asarray(pp.x, dtype=np.float64), extrapolate, pp.axis)

    @staticmethod
    def _construct_from_derivatives(xa, xb, ya, yb) -> np.ndarray:
        """SciPy's private `_construct_from_derivatives`: the Bernstein coefficients (n, ...),
        n = len(ya) + len(yb), of the polynomial on [xa, xb] with derivatives ya[q] at xa and
        yb[q] at xb. At s = 0 the q-th derivative is (n - 1)! / (n - 1 - q)! / h^q times
        sum_{j<=q} (-1)^(q-j) C(q, j) c_j, which gives c_q from those before it; at s = 1
        sum_{i<=q} (-1)^(q-i) C(q, i) c_{n-1-q+i}, which gives c_{n-1-q} from those after."""
        ya, yb = np.asarray(ya), np.asarray(yb)
        if ya.shape[1:] != yb.shape[1:]:
            raise ValueError(f"Shapes of ya {ya.shape} and yb {yb.shape} are incompatible")
        complex_ = np.iscomplexobj(ya) or np.iscomplexobj(yb)
        na, nb = len(ya), len(yb)
        n = na + nb
        h = xb - xa
        c = np.empty((n, *ya.shape[1:]), dtype=np.complex128 if complex_ else np.float64)
        for q in range(na):
            value = ya[q] * h ** q / math.perm(n - 1, q)
            for j in range(q):
                value = value - (-1) ** (q - j) * math.comb(q, j) * c[j]
            c[q] = value
        for q in range(nb):
            value = yb[q] * (-h) ** q / math.perm(n - 1, q)
            for i in range(1, q + 1):
                value = value - (-1) ** i * math.comb(q, i) * c[n - 1 - q + i]
            c[n - 1 - q] = value
        return c

    @classmethod
    def from_derivatives(cls, xi, yi, orders=None, extrapolate=None) -> BPoly:
        """SciPy's `BPoly.from_derivatives`: the piecewise polynomial with yi[i][q] as its q-th
        derivative at xi[i] (each piece of the degree its two ends' counts need, or `orders`'
        order, raised to the highest), as SciPy's, its checks and messages included."""
        xi = np.asarray(xi)
        if len(xi) != len(yi):
            raise ValueError("xi and yi need to have the same length")
        # As SciPy's (which compares every breakpoint with the first).
        if np.any(xi[1:] - xi[:1] <= 0):
            raise ValueError("x coordinates are not in increasing order")
        m = len(xi) - 1
        try:
            k = max(len(yi[i]) + len(yi[i + 1]) for i in range(m))
        except TypeError as e:
            raise ValueError("Using a 1-D array for y? Please .reshape(-1, 1).") from e
        if orders is None:
            orders = [None] * m
        else:
            if isinstance(orders, (int, np.integer)):
                orders = [orders] * m
            k = max(k, max(orders))
            if any(o <= 0 for o in orders):
                raise ValueError("Orders must be positive.")
        pieces = []
        for i in range(m):
            left, right = yi[i], yi[i + 1]
            if orders[i] is None:
                n1, n2 = len(left), len(right)
            else:
                n = orders[i] + 1
                n1 = min(n // 2, len(left))
                n2 = min(n - n1, len(right))
                # SciPy's own rule, which bounds n1 by the right end's count.
                n1 = min(n - n2, len(right))
                if n1 + n2 != n:
                    raise ValueError(f"Point {xi[i]} has {len(left)} derivatives, point "
                                     f"{xi[i + 1]} has {len(right)} derivatives, but order "
                                     f"{orders[i]} requested")
                if not (n1 <= len(left) and n2 <= len(right)):
                    raise ValueError("`order` input incompatible with length y1 or y2.")
            b = cls._construct_from_derivatives(xi[i], xi[i + 1], left[:n1], right[:n2])
            pieces.append(_raised(b, k - len(b)) if len(b) < k else b)
        return cls(np.asarray(pieces).swapaxes(0, 1), xi, extrapolate)
