//! Brent's bounded minimisation of a function of one variable, as SciPy's
//! `minimize_scalar(method="bounded")` (`_minimize_scalar_bounded`) runs it: golden sections
//! and parabolic steps on (a, b), absolute tolerance 1e-5 in x, at most 500 evaluations.
//! Every step and comparison is SciPy's, so that the same function values give the same
//! minimum. It is a state machine (ask for x, tell f(x)) so that many searches can share one
//! evaluator that works on several at once.

/// Why a search found no minimum, in SciPy's words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoMinimum(pub &'static str);

/// What a search wants next.
#[derive(Debug)]
pub enum Step {
    /// f at this x.
    Evaluate(f64),
    /// The minimum's x, or why there is none.
    Done(Result<f64, NoMinimum>),
}

/// One search in progress (SciPy's variable names: xf the best x so far, nfc and fulc the
/// second and third best, e and rat the last two steps).
#[derive(Debug)]
pub struct Search {
    a: f64,
    b: f64,
    fulc: f64,
    nfc: f64,
    xf: f64,
    rat: f64,
    e: f64,
    fx: f64,
    fu: f64,
    ffulc: f64,
    fnfc: f64,
    /// The x asked for; None before the first value.
    asked: Option<f64>,
    calls: usize,
}

const XATOL: f64 = 1e-5;
const MAXFUN: usize = 500;
const GOLDEN_MEAN: f64 = 0.381_966_011_250_105_1;

/// NumPy's sign(v) + (v == 0): a step's direction, +1 for zero.
fn direction(v: f64) -> f64 {
    if v < 0.0 { -1.0 } else { 1.0 }
}

impl Search {
    /// A search on (a, b) and the first x it asks for.
    pub fn new(a: f64, b: f64) -> (Self, f64) {
        let start = a + GOLDEN_MEAN * (b - a);
        let search = Self {
            a,
            b,
            fulc: start,
            nfc: start,
            xf: start,
            rat: 0.0,
            e: 0.0,
            fx: 0.0,
            fu: f64::INFINITY,
            ffulc: 0.0,
            fnfc: 0.0,
            asked: None,
            calls: 1,
        };
        (search, start)
    }

    /// The best x so far (the x `Done` gives when the search ends there).
    pub fn best(&self) -> f64 {
        self.xf
    }

    fn tolerance(&self) -> f64 {
        2.2e-16_f64.sqrt() * self.xf.abs() + XATOL / 3.0
    }

    /// f at the x last asked for; what the search wants next.
    pub fn tell(&mut self, value: f64) -> Step {
        match self.asked {
            None => {
                (self.fx, self.ffulc, self.fnfc) = (value, value, value);
            }
            Some(x) => {
                self.fu = value;
                self.calls += 1;
                self.update(x, value);
                if self.calls >= MAXFUN {
                    return self.finish(Some("Maximum number of function calls reached."));
                }
            }
        }
        let xm = 0.5 * (self.a + self.b);
        let tol1 = self.tolerance();
        let tol2 = 2.0 * tol1;
        if (self.xf - xm).abs() <= tol2 - 0.5 * (self.b - self.a) {
            return self.finish(None);
        }
        let x = self.next_x(xm, tol1, tol2);
        self.asked = Some(x);
        Step::Evaluate(x)
    }

    fn finish(&self, exhausted: Option<&'static str>) -> Step {
        if self.xf.is_nan() || self.fx.is_nan() || self.fu.is_nan() {
            return Step::Done(Err(NoMinimum("NaN result encountered.")));
        }
        Step::Done(exhausted.map_or(Ok(self.xf), |why| Err(NoMinimum(why))))
    }

    /// The next x: a parabola through the three best points where it steps inside the
    /// interval and less than half the step before last, a golden section otherwise.
    fn next_x(&mut self, xm: f64, tol1: f64, tol2: f64) -> f64 {
        let (a, b, xf) = (self.a, self.b, self.xf);
        let mut golden = true;
        if self.e.abs() > tol1 {
            golden = false;
            let mut r = (xf - self.nfc) * (self.fx - self.ffulc);
            let mut q = (xf - self.fulc) * (self.fx - self.fnfc);
            let mut p = (xf - self.fulc) * q - (xf - self.nfc) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            r = self.e;
            self.e = self.rat;
            if p.abs() < (0.5 * q * r).abs() && p > q * (a - xf) && p < q * (b - xf) {
                self.rat = p / q;
                let x = xf + self.rat;
                if (x - a) < tol2 || (b - x) < tol2 {
                    self.rat = tol1 * direction(xm - xf);
                }
            } else {
                golden = true;
            }
        }
        if golden {
            self.e = if xf >= xm { a - xf } else { b - xf };
            self.rat = GOLDEN_MEAN * self.e;
        }
        xf + direction(self.rat) * self.rat.abs().max(tol1)
    }

    /// The interval and the three best points after f(x) = fu.
    fn update(&mut self, x: f64, fu: f64) {
        if fu <= self.fx {
            if x >= self.xf {
                self.a = self.xf;
            } else {
                self.b = self.xf;
            }
            (self.fulc, self.ffulc) = (self.nfc, self.fnfc);
            (self.nfc, self.fnfc) = (self.xf, self.fx);
            (self.xf, self.fx) = (x, fu);
        } else {
            if x < self.xf {
                self.a = x;
            } else {
                self.b = x;
            }
            if fu <= self.fnfc || self.nfc == self.xf {
                (self.fulc, self.ffulc) = (self.nfc, self.fnfc);
                (self.nfc, self.fnfc) = (x, fu);
            } else if fu <= self.ffulc || self.fulc == self.xf || self.fulc == self.nfc {
                (self.fulc, self.ffulc) = (x, fu);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{NoMinimum, Search, Step};

    /// The minimum of f on (a, b), searched to the end.
    fn minimum(f: impl Fn(f64) -> f64, a: f64, b: f64) -> Result<f64, NoMinimum> {
        let (mut search, mut x) = Search::new(a, b);
        loop {
            match search.tell(f(x)) {
                Step::Evaluate(next) => x = next,
                Step::Done(result) => return result,
            }
        }
    }

    /// A parabola's minimum within the tolerance, and a minimum at the lower bound from a
    /// start far from it.
    #[test]
    fn finds_minima() {
        let x = minimum(|x| (x - 1.3) * (x - 1.3), 0.0, 10.0).unwrap();
        assert!((x - 1.3).abs() < 1e-5);
        let x = minimum(|x| (x + 1.0).ln(), 0.0, 2048.0).unwrap();
        assert!(x < 1e-4, "{x}");
    }
}
