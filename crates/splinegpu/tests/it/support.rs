//! Helpers shared by the integration tests: the GPU context and the GPU-vs-CPU comparison.
#![allow(
    dead_code,
    unused_macros,
    unused_imports,
    reason = "each test binary uses a different subset of these helpers"
)]

use std::sync::OnceLock;

use splinegpu::accuracy::gpu_bound;
use splinegpu::{EvalJob, GpuContext, SamplePlan, Samples, Sampling};

/// The context every GPU test of this binary shares, or `None` on a developer's machine without
/// an adapter. Under CI (`CI=true`) a missing adapter fails the test instead: a broken driver
/// install must never pass as green.
pub(crate) fn gpu() -> Option<&'static GpuContext> {
    static CONTEXT: OnceLock<Option<GpuContext>> = OnceLock::new();
    CONTEXT
        .get_or_init(|| match GpuContext::new() {
            Ok(context) => Some(context),
            Err(e) if std::env::var("CI").is_ok_and(|v| v == "true") => {
                panic!("CI=true and no GPU adapter: {e}")
            }
            Err(e) => {
                eprintln!("skipping GPU test: {e}");
                None
            }
        })
        .as_ref()
}

/// Whether this machine runs the GPU tests: under CI always (a missing adapter then fails
/// them), elsewhere when wgpu finds an adapter.
pub(crate) fn gpu_tests_run() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true") || gpu().is_some()
}

/// The GPU tests `$test` (each a `fn()` that panics on failure) as libtest-mimic trials named
/// by their paths, reported as ignored where [`gpu_tests_run`] says no. An attribute before a
/// test (a `#[cfg]`) applies to its trial.
macro_rules! gpu_trials {
    ($($(#[$attr:meta])* $test:path),* $(,)?) => {{
        let run = $crate::support::gpu_tests_run();
        let mut trials = Vec::new();
        $(
            $(#[$attr])*
            trials.push(
                libtest_mimic::Trial::test(stringify!($test).replace(' ', ""), || {
                    $test();
                    Ok(())
                })
                .with_ignored_flag(!run),
            );
        )*
        trials
    }};
}
pub(crate) use gpu_trials;

/// The worst GPU sample of a comparison, as a fraction of its promised bound.
#[derive(Clone, Debug, Default)]
pub(crate) struct Worst {
    /// error / bound; the promise holds while this is <= 1.
    pub(crate) ratio: f64,
    pub(crate) curve: usize,
    pub(crate) sample: usize,
    pub(crate) order: usize,
    pub(crate) coord: usize,
    pub(crate) gpu: f32,
    pub(crate) cpu: f64,
    pub(crate) bound: f64,
    /// The worst ratio for positions, first and second derivatives.
    pub(crate) per_order: [f64; 3],
}

/// Compares GPU samples with the CPU reference, sample by sample, coordinate by coordinate,
/// against the contract's accuracy promise, and returns the worst. The t must be the same,
/// except on curves sampled by arc length, whose places the GPU finds itself: there the
/// reference is evaluated again at the GPU's t.
pub(crate) fn compare(job: &EvalJob, cpu: &Samples<f64>, gpu: &Samples<f32>) -> Worst {
    let mut worst = Worst::default();
    for c in 0..job.len() {
        let (mut table, mut plan) = (job.table(c), job.plan(c));
        let (mut cc, gc) = (cpu.curve(c), gpu.curve(c));
        let at_gpu_t;
        if plan.is_arc_length() {
            let mut job_at = EvalJob::new(job.derivatives());
            let places = SamplePlan::new(table, &Sampling::At(gc.t.to_vec())).unwrap();
            job_at.push_table(table.clone(), places).unwrap();
            at_gpu_t = (splinegpu::evaluate_reference(&job_at), job_at);
            (table, plan, cc) = (at_gpu_t.1.table(0), at_gpu_t.1.plan(0), at_gpu_t.0.curve(0));
        }
        assert_eq!(cc.t, gc.t, "curve {c}: t differs between backends");
        let planes = [
            (cc.points, Some(gc.points)),
            (cc.d1.unwrap_or(&[]), gc.d1),
            (cc.d2.unwrap_or(&[]), gc.d2),
        ];
        for (order, (cpu_values, gpu_values)) in planes.into_iter().enumerate() {
            let Some(gpu_values) = gpu_values else {
                continue;
            };
            assert_eq!(cpu_values.len(), gpu_values.len());
            for (i, (cv, gv)) in cpu_values.iter().zip(gpu_values).enumerate() {
                let (sample, coord) = (i / cc.dim, i % cc.dim);
                let segment = table.segment(plan.loc(sample).segment);
                let bound = gpu_bound(&segment, table.extent(), order, coord, *cv);
                // A NaN from the GPU counts as infinitely wrong.
                let ratio = (f64::from(*gv) - cv).abs() / bound;
                let ratio = if ratio.is_nan() { f64::INFINITY } else { ratio };
                if ratio > worst.per_order[order] {
                    worst.per_order[order] = ratio;
                }
                if ratio > worst.ratio {
                    let per_order = worst.per_order;
                    worst = Worst {
                        ratio,
                        curve: c,
                        sample,
                        order,
                        coord,
                        gpu: *gv,
                        cpu: *cv,
                        bound,
                        per_order,
                    };
                }
            }
        }
    }
    worst
}

/// Runs `job` on both backends and asserts that every GPU value meets the promise; returns the
/// worst ratio seen. Returns `None` when there is no GPU (outside CI).
pub(crate) fn assert_gpu_matches_cpu(job: &EvalJob) -> Option<Worst> {
    let context = gpu()?;
    let cpu = splinegpu::evaluate_reference(job);
    let gpu = context.evaluate(job).expect("GPU evaluation");
    let worst = compare(job, &cpu, &gpu);
    assert!(
        worst.ratio <= 1.0,
        "GPU breaks the accuracy promise: {worst:?} (error {} > bound {})",
        (f64::from(worst.gpu) - worst.cpu).abs(),
        worst.bound
    );
    Some(worst)
}

/// A small deterministic generator (xorshift64*), so tests need no extra crate.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// A value in [lo, hi).
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        lo + (hi - lo) * (bits as f64 / (1u64 << 53) as f64)
    }

    /// `n` points of `dim` coordinates in [lo, hi).
    pub(crate) fn points(&mut self, n: usize, dim: usize, lo: f64, hi: f64) -> splinegpu::Points {
        splinegpu::Points::new(dim, (0..n * dim).map(|_| self.range(lo, hi)).collect()).unwrap()
    }
}

/// The CPU reference at explicit parameter values, with derivatives.
pub(crate) fn cpu_at(curve: &splinegpu::Curve, ts: &[f64]) -> Samples<f64> {
    let mut job = EvalJob::new(splinegpu::Derivatives::Second);
    job.push(curve, &splinegpu::Sampling::At(ts.to_vec()))
        .unwrap();
    splinegpu::evaluate_reference(&job)
}

/// Asserts |a - b| <= tol elementwise, naming `what`.
pub(crate) fn assert_close(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tol,
            "{what}: [{i}] {x} vs {y} (tolerance {tol})"
        );
    }
}

/// Every kind of basis matrix, with parameters away from the defaults.
pub(crate) fn bases() -> Vec<splinegpu::Basis> {
    use splinegpu::Basis;
    vec![
        Basis::Cardinal { tension: 0.3 },
        Basis::CatmullRom,
        Basis::BSpline,
        Basis::TensionedBSpline { tension: 0.6 },
        Basis::Beta {
            bias: 1.7,
            tension: 3.0,
        },
        Basis::Matrix([
            [1.0, -2.0, 0.5, 0.0],
            [0.0, 3.0, -1.0, 0.25],
            [2.0, 0.0, 0.0, 1.0],
            [0.1, 0.2, 0.3, 0.4],
        ]),
    ]
}

/// A Beta-spline with local bias and tension for `n` points with `ends`: a random b1 in
/// [0.2, 5] (log-uniform) and b2 in [0, 6] at every joint.
pub(crate) fn local_beta(rng: &mut Rng, ends: splinegpu::Ends, n: usize) -> splinegpu::CurveKind {
    use splinegpu::{CurveKind, Ends, PerPoint};
    let joints = match ends {
        Ends::Control => n - 2,
        Ends::Repeat | Ends::Closed => n,
    };
    CurveKind::LocalBeta {
        ends,
        bias: PerPoint::Each(
            (0..joints)
                .map(|_| 5f64.powf(rng.range(-1.0, 1.0)))
                .collect(),
        ),
        tension: PerPoint::Each((0..joints).map(|_| rng.range(0.0, 6.0)).collect()),
    }
}

/// `table` sampled by `sampling`, evaluated on the CPU in f64 through a one-surface job.
pub(crate) fn surface_samples(
    table: &splinegpu::surface::PatchTable,
    sampling: &splinegpu::surface::SurfaceSampling,
    derivatives: splinegpu::Derivatives,
    normals: bool,
) -> splinegpu::surface::SurfaceSamples {
    surface_job(&[(table, sampling)], derivatives, normals)
        .evaluate_cpu()
        .remove(0)
}

/// A job of `surfaces`, each pushed as given.
pub(crate) fn surface_job(
    surfaces: &[(
        &splinegpu::surface::PatchTable,
        &splinegpu::surface::SurfaceSampling,
    )],
    derivatives: splinegpu::Derivatives,
    normals: bool,
) -> splinegpu::surface::SurfaceJob {
    let mut job = splinegpu::surface::SurfaceJob::new(derivatives, normals);
    for (table, sampling) in surfaces {
        job.push((*table).clone(), (*sampling).clone()).unwrap();
    }
    job
}
