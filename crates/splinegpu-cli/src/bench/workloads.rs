//! The bench's data, the same every run: w1 and its variants as jobs, the 1 M-point fit's data,
//! the eval-at job and the cli-w1 document, from a seeded generator.

use splinegpu::EndCondition;
use splinegpu::{Basis, Sampling};
use splinegpu::{Curve, CurveKind, Ends, Points};
use splinegpu::{Derivatives, EvalJob};

/// A deterministic generator (xorshift64*) for the workloads' data.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        lo + (hi - lo) * (bits as f64 / (1u64 << 53) as f64)
    }
}

/// w1's 10,000 curves: 34 control points in 3-D in ±100, "control" ends.
pub(crate) fn w1_curves(basis: &Basis) -> impl Iterator<Item = Curve> + '_ {
    curves_like_w1(basis, 10_000)
}

/// `count` curves made as w1's are (w1's own first, for any count >= 10,000).
pub(crate) fn curves_like_w1(basis: &Basis, count: usize) -> impl Iterator<Item = Curve> + '_ {
    let mut rng = Rng(1);
    (0..count).map(move |_| {
        let points = Points::new(3, (0..34 * 3).map(|_| rng.range(-100.0, 100.0)).collect())
            .expect("finite points");
        let kind = CurveKind::Uniform {
            basis: basis.clone(),
            ends: Ends::Control,
        };
        Curve::new(kind, points).expect("34 points")
    })
}

/// w1 (`basis` Catmull-Rom), w1-b (B-spline), w1-d (w1 with derivatives): w1's curves, 32
/// samples per segment plus the end point: 10,000 × (31 × 32 + 1) = 9,930,000 samples.
#[must_use]
pub fn w1_job(basis: Basis, derivatives: Derivatives) -> EvalJob {
    w1_job_sampled(&basis, derivatives, |_| Sampling::PerSegment(32))
}

/// w1's Catmull-Rom curves, each sampled as `sampling(curve)` says.
pub(crate) fn w1_job_sampled(
    basis: &Basis,
    derivatives: Derivatives,
    sampling: impl Fn(&Curve) -> Sampling,
) -> EvalJob {
    let mut job = EvalJob::new(derivatives);
    for curve in w1_curves(basis) {
        job.push(&curve, &sampling(&curve)).expect("valid sampling");
    }
    job
}

/// w1-nurbs: w1's points as clamped rational B-splines (34 points, knots 0 four times, 30
/// interior knots with spacings 10^U(-1, 1), the end four times; weights in [0.5, 2]), 32
/// samples per span: w1's 31 segments per curve and its 9,930,000 samples.
#[must_use]
pub fn w1_nurbs_job() -> EvalJob {
    let mut rng = Rng(3);
    let mut job = EvalJob::new(Derivatives::None);
    for curve in w1_curves(&Basis::CatmullRom) {
        let mut knots = vec![0.0; 4];
        let mut at = 0.0;
        for _ in 0..30 {
            at += 10f64.powf(rng.range(-1.0, 1.0));
            knots.push(at);
        }
        at += 10f64.powf(rng.range(-1.0, 1.0));
        knots.extend([at; 4]);
        let kind = CurveKind::Nurbs {
            knots,
            weights: Some((0..34).map(|_| rng.range(0.5, 2.0)).collect()),
        };
        let curve = Curve::new(kind, curve.points().clone()).expect("a valid knot vector");
        job.push(&curve, &Sampling::PerSegment(32))
            .expect("valid sampling");
    }
    job
}

/// w1-x10: 100,000 curves made as w1's (99.3 M samples, 1.19 GB of f32 positions), so that
/// on a GPU the timed region dwarfs launch overhead.
#[must_use]
pub fn w1_x10_job() -> EvalJob {
    let mut job = EvalJob::new(Derivatives::None);
    for curve in curves_like_w1(&Basis::CatmullRom, 100_000) {
        job.push(&curve, &Sampling::PerSegment(32))
            .expect("valid sampling");
    }
    job
}

/// w1-arc: w1's curves at 993 points evenly spaced by arc length (w1's 9,930,000 samples).
#[must_use]
pub fn w1_arc_job() -> EvalJob {
    w1_job_sampled(&Basis::CatmullRom, Derivatives::None, |_| {
        Sampling::ArcLength(993)
    })
}

/// The tolerance of w1-tol's curves: 1e-3 of each one's extent.
pub(crate) fn w1_tolerance(curve: &Curve) -> f64 {
    1e-3 * curve.points().extent()
}

/// w1-tol: w1's curves, each at a tolerance of 1e-3 of its own extent.
#[must_use]
pub fn w1_tol_job() -> EvalJob {
    w1_job_sampled(&Basis::CatmullRom, Derivatives::None, |curve| {
        Sampling::Tolerance(w1_tolerance(curve))
    })
}

/// fit-1m's data: 1,000,000 non-uniform knots (spacings within a factor of 100) and 3-D points.
#[must_use]
pub fn fit_1m_data() -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng(2);
    let mut t = Vec::with_capacity(1_000_000);
    let mut at = 0.0;
    for _ in 0..1_000_000 {
        t.push(at);
        at += 10f64.powf(rng.range(-1.0, 1.0));
    }
    let values = (0..3_000_000).map(|_| rng.range(-10.0, 10.0)).collect();
    (t, values)
}

/// eval-at: 10,000 natural splines of 64 non-uniform knots in 3-D, each at 1,000 random t.
#[must_use]
pub fn eval_at_job() -> EvalJob {
    let mut rng = Rng(3);
    let mut job = EvalJob::new(Derivatives::None);
    for _ in 0..10_000 {
        let mut t = vec![0.0];
        for i in 1..64 {
            t.push(t[i - 1] + rng.range(0.1, 2.0));
        }
        let points = Points::new(3, (0..64 * 3).map(|_| rng.range(-10.0, 10.0)).collect())
            .expect("finite points");
        let ts: Vec<f64> = (0..1_000).map(|_| rng.range(0.0, t[63])).collect();
        let kind = CurveKind::Interpolating {
            condition: EndCondition::Natural,
            t: Some(t),
        };
        let curve = Curve::new(kind, points).expect("valid knots");
        job.push(&curve, &Sampling::At(ts)).expect("t in range");
    }
    job
}

/// w1 as the contract's document: the same curves (their coordinates as the shortest text
/// that round-trips them), "control" ends by default, 32 samples per segment.
#[must_use]
pub fn w1_document() -> Vec<u8> {
    let mut rng = Rng(1);
    let mut text = zmij::Buffer::new();
    let mut doc = br#"{"sampling": {"per_segment": 32}, "curves": ["#.to_vec();
    for c in 0..10_000 {
        doc.extend_from_slice(if c > 0 { b",\n" } else { b"\n" });
        doc.extend_from_slice(br#"{"kind": "catmull-rom", "points": ["#);
        for p in 0..34 {
            doc.extend_from_slice(if p > 0 { b", [" } else { b"[" });
            for k in 0..3 {
                if k > 0 {
                    doc.extend_from_slice(b", ");
                }
                doc.extend_from_slice(text.format(rng.range(-100.0, 100.0)).as_bytes());
            }
            doc.push(b']');
        }
        doc.extend_from_slice(b"]}");
    }
    doc.extend_from_slice(b"\n]}\n");
    doc
}
