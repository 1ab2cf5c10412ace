//! `Planes`: a caller's memory for a job's samples, the one destination every evaluator's
//! `*_into` call writes: each sample's t when wanted, the positions, and the derivative planes
//! the job asks for.

use crate::job::EvalJob;

/// A caller's memory for a job's samples, laid out as the job's
/// [`JobLayout`](crate::JobLayout) lays out host planes: curve after curve, `dim` values per
/// sample. `points` holds the positions; `d1` and `d2` hold dP/dt and d²P/dt² and must be
/// given exactly when the job asks for them; `t` (one f64 per sample) is filled when given.
///
/// [`Samples::planes_for`](crate::Samples::planes_for) lays a [`Samples`](crate::Samples) out
/// for a job and views it as `Planes`, so that repeated jobs reuse its memory.
#[derive(Debug)]
pub struct Planes<'a, F> {
    /// Each sample's curve parameter, when the caller wants it (`job.layout().samples()` long).
    pub t: Option<&'a mut [f64]>,
    /// Positions (`job.layout().values()` long).
    pub points: &'a mut [F],
    /// dP/dt, exactly when the job asks for first or second derivatives.
    pub d1: Option<&'a mut [F]>,
    /// d²P/dt², exactly when the job asks for second derivatives.
    pub d2: Option<&'a mut [F]>,
}

impl<'a, F> Planes<'a, F> {
    /// Positions only: no t, no derivatives.
    #[must_use]
    pub fn new(points: &'a mut [F]) -> Self {
        Self {
            t: None,
            points,
            d1: None,
            d2: None,
        }
    }

    /// The same planes, with each sample's t written into `t` too.
    #[must_use]
    pub fn with_t(self, t: &'a mut [f64]) -> Self {
        Self { t: Some(t), ..self }
    }

    /// The same planes, with the first derivatives going into `d1`.
    #[must_use]
    pub fn with_d1(self, d1: &'a mut [F]) -> Self {
        Self {
            d1: Some(d1),
            ..self
        }
    }

    /// The same planes, with the second derivatives going into `d2`.
    #[must_use]
    pub fn with_d2(self, d2: &'a mut [F]) -> Self {
        Self {
            d2: Some(d2),
            ..self
        }
    }

    /// The planes as the evaluators take them: t (empty when not wanted) and the three value
    /// planes, an absent one empty, each checked against `job`.
    ///
    /// # Panics
    /// If a plane's presence or length does not match the job (the message names the plane).
    pub(crate) fn checked(self, job: &EvalJob) -> (&'a mut [f64], [&'a mut [F]; 3]) {
        let layout = job.layout();
        let (samples, values) = (layout.samples(), layout.values());
        let order = job.derivatives().order();
        let check = |name: &str, plane: Option<&'a mut [F]>, wanted: bool| -> &'a mut [F] {
            match (plane, wanted) {
                (Some(plane), true) => {
                    assert_eq!(
                        plane.len(),
                        values,
                        "{name} holds {} of {values} values",
                        plane.len()
                    );
                    plane
                }
                (None, false) => &mut [],
                (Some(_), false) => panic!("{name} given, but the job does not compute it"),
                (None, true) => panic!("the job computes {name}, but no plane was given for it"),
            }
        };
        let points = check("points", Some(self.points), true);
        let d1 = check("d1", self.d1, order >= 1);
        let d2 = check("d2", self.d2, order >= 2);
        let t = match self.t {
            Some(t) => {
                assert_eq!(t.len(), samples, "t holds {} of {samples} samples", t.len());
                t
            }
            None => &mut [],
        };
        (t, [points, d1, d2])
    }
}
