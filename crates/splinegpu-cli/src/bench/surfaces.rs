//! The surface workloads of `splinegpu bench` (contract: "Bench"): s1, 1,000 bicubic bspline
//! surfaces of 20 x 20 control points in 3-D at per_segment 8 with normals (18.8 M vertices),
//! and teapot, 1,000 Utah teapots (32,000 Bezier patches) within 1e-3 of the teapot's extent
//! with normals. Each is timed as the caller waits for it: the whole call (fit, plan,
//! evaluation into new memory), beside a plain hand-written loop over the same vertices (the
//! basis weights of each vertex times its 16 control points, derivatives and normal), memset
//! of the output's bytes, and the GPU's device time and end to end.

use std::hint::black_box;

use rayon::prelude::*;
use splinegpu::surface::{
    Net, Surface, SurfaceJob, SurfaceKind, SurfacePlan, SurfaceSamples, SurfaceSampling,
};
use splinegpu::{Basis, Derivatives, Ends, GpuContext, GpuError, SampleFloat};

use crate::bench::measure::{Measurement, memset, time};

/// The s1 surfaces: 1,000 wavy 20 x 20 nets (a seeded generator, the same every run).
fn s1_surfaces() -> Vec<Surface> {
    let mut state = 0x5EED_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..1000)
        .map(|s| {
            let mut coords = Vec::with_capacity(20 * 20 * 3);
            for i in 0..20 {
                for j in 0..20 {
                    coords.extend([i as f64, j as f64, (s % 7) as f64 + next() * 2.0 - 1.0]);
                }
            }
            let kind = SurfaceKind::Uniform {
                basis: Basis::BSpline,
                ends: [Ends::Control; 2],
            };
            Surface::new(kind, Net::new(3, 20, 20, coords).expect("a 20 x 20 net"))
                .expect("an s1 surface")
        })
        .collect()
}

/// The teapot workload: the example's teapot, 1,000 times, each moved so none coincide.
fn teapots() -> (Vec<Surface>, f64) {
    let text = include_str!("../../examples/teapot.json");
    let doc: serde_json::Value = serde_json::from_str(text).expect("the teapot example");
    let surface = &doc["surfaces"][0];
    let points: Vec<f64> = surface["points"]
        .as_array()
        .expect("points")
        .iter()
        .flat_map(|p| {
            p.as_array()
                .expect("a point")
                .iter()
                .map(|x| x.as_f64().unwrap_or(0.0))
        })
        .collect();
    let patches: Vec<[usize; 16]> = surface["patches"]
        .as_array()
        .expect("patches")
        .iter()
        .map(|p| std::array::from_fn(|k| p[k].as_u64().unwrap_or(0) as usize))
        .collect();
    let surfaces: Vec<Surface> = (0..1000)
        .map(|t| {
            let shift = [(t % 40) as f64 * 8.0, (t / 40) as f64 * 6.0, 0.0];
            let coords = points
                .chunks_exact(3)
                .flat_map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]])
                .collect::<Vec<f64>>();
            let net = Net::new(3, coords.len() / 3, 1, coords).expect("the teapot's points");
            Surface::new(
                SurfaceKind::BezierPatches {
                    patches: patches.clone(),
                },
                net,
            )
            .expect("a teapot")
        })
        .collect();
    let extent = surfaces[0].net().extent();
    (surfaces, extent)
}

/// Runs the surface workload `name` ("s1" or "teapot").
///
/// # Errors
/// The GPU's.
pub(crate) fn run(
    name: &'static str,
    gpu: Option<&GpuContext>,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), GpuError> {
    let (surfaces, sampling) = match name {
        "s1" => (s1_surfaces(), SurfaceSampling::PerSegment([8, 8])),
        _ => {
            let (teapots, extent) = teapots();
            (teapots, SurfaceSampling::Tolerance(1e-3 * extent))
        }
    };
    // The whole call into new memory, every plane the output holds: fit, plan, evaluate.
    let job = || -> SurfaceJob {
        let mut job = SurfaceJob::new(Derivatives::None, true);
        let fitted = surfaces
            .par_iter()
            .map(|s| (s.fit(), sampling.clone()))
            .collect();
        job.push_many(fitted).expect("the workload's surfaces");
        job
    };
    let call = || -> Vec<SurfaceSamples> { job().into_samples() };
    let first = call();
    let vertices: u64 = first.iter().map(|s| s.len() as u64).sum();
    let bytes = |per_value: u64| vertices * 6 * per_value;
    drop(first);
    let measure = |path: &'static str, times: (f64, f64, f64), per_value: u64| Measurement {
        workload: name,
        path,
        seconds: times.0,
        min_seconds: times.1,
        max_seconds: times.2,
        samples: vertices,
        bytes: bytes(per_value),
        float: Some(if per_value == 4 { "f32" } else { "f64" }),
        misses: None,
        max_error: None,
    };
    report(&memset(name, bytes(4) as usize));
    // Fit, plan and evaluate into memory kept from the last call (as a renderer or a repeated
    // job holds it): f32, then f64.
    let kept = job();
    let mut f32_out: Vec<SurfaceSamples<f32>> = memory(&kept);
    report(&measure(
        "cpu-all",
        time(|| reused(&job(), &mut f32_out)),
        4,
    ));
    let mut f64_out: Vec<SurfaceSamples> = memory(&kept);
    report(&measure(
        "cpu-all",
        time(|| reused(&job(), &mut f64_out)),
        8,
    ));
    drop(f64_out);
    report(&measure(
        "cpu-call",
        time(|| {
            black_box(call());
            None
        }),
        8,
    ));
    // The fit and the plan alone.
    report(&measure(
        "fit",
        time(|| {
            black_box(
                surfaces
                    .par_iter()
                    .map(|s| {
                        let t = s.fit();
                        SurfacePlan::new(&t, &sampling)
                            .expect("a plan")
                            .vertices
                            .len()
                    })
                    .sum::<usize>(),
            );
            None
        }),
        8,
    ));
    // The plain loop: the same vertices from the control points, into the same memory, its
    // plans made before it is timed.
    let plans: Vec<SurfacePlan> = kept
        .surfaces()
        .par_iter()
        .map(|s| s.plan().into_owned())
        .collect();
    report(&measure(
        "plain-loop",
        time(|| {
            surfaces
                .par_iter()
                .zip(&plans)
                .zip(&mut f32_out)
                .for_each(|((s, plan), out)| plain_loop(s, plan, out));
            black_box(&f32_out);
            None
        }),
        4,
    ));
    drop(f32_out);
    if let Some(gpu) = gpu {
        // The first call compiles the pipeline; the device's own time of the later ones.
        gpu.evaluate_surfaces(&kept)?;
        let mut failure = None;
        let device = time(|| match gpu.evaluate_surfaces_timed(&kept) {
            Ok((_, time)) => Some(time.seconds),
            Err(e) => {
                failure = Some(e);
                Some(0.0)
            }
        });
        if let Some(e) = failure {
            return Err(e);
        }
        report(&measure("gpu-device", device, 4));
        report(&measure(
            "gpu-end-to-end",
            time(|| {
                black_box(gpu.evaluate_surfaces(&kept).ok());
                None
            }),
            4,
        ));
    }
    Ok(())
}

/// Samples for every surface of `job`, positions and normals, in `F`.
fn memory<F: SampleFloat>(job: &SurfaceJob) -> Vec<SurfaceSamples<F>> {
    job.surfaces()
        .iter()
        .map(|s| SurfaceSamples::for_plan(s.table(), &s.plan(), Derivatives::None, true))
        .collect()
}

/// Evaluates every surface of `job` (fitted and planned: the call's first half) into `out`,
/// memory of an earlier call.
fn reused<F: SampleFloat>(job: &SurfaceJob, out: &mut [SurfaceSamples<F>]) -> Option<f64> {
    out.par_iter_mut().enumerate().for_each(|(s, out)| {
        job.evaluate_into(s, out.planes_mut())
            .expect("memory made for the job's plans");
    });
    None
}

/// The uniform B-spline's basis at t and its derivative: (1 − t)³/6, (3t³ − 6t² + 4)/6,
/// (−3t³ + 3t² + 3t + 1)/6, t³/6.
fn bspline_basis(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [
            -s * s / 2.0,
            (3.0 * t * t - 4.0 * t) / 2.0,
            (-3.0 * t * t + 2.0 * t + 1.0) / 2.0,
            t * t / 2.0,
        ],
    )
}

/// The cubic Bernstein basis at t and its derivative.
fn bezier_basis(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * (s - 2.0 * t),
            3.0 * t * (2.0 * s - t),
            3.0 * t * t,
        ],
    )
}

/// A plain loop over a plan's vertices: each vertex's 16 control points (its patch's window of
/// the net, or its patch's indices) times the basis weights for S, S_u and S_v, and the unit
/// normal, in f64; positions and normals into `out`'s planes as f32.
fn plain_loop(surface: &Surface, plan: &SurfacePlan, out: &mut SurfaceSamples<f32>) {
    let net = surface.net();
    let coords = net.coords();
    let (_, cols) = net.shape();
    let normals = out.normals.as_mut().expect("normals");
    let list = match surface.kind() {
        SurfaceKind::BezierPatches { patches } => Some(patches),
        _ => None,
    };
    let across = cols - 3;
    for (i, vertex) in plan.vertices.iter().enumerate() {
        let [u, v] = vertex.local;
        let p = vertex.patch as usize;
        let ((bu, du), (bv, dv)) = if list.is_some() {
            (bezier_basis(u), bezier_basis(v))
        } else {
            (bspline_basis(u), bspline_basis(v))
        };
        let index = |i: usize, j: usize| match list {
            Some(patches) => patches[p][4 * i + j],
            None => (p / across + i) * cols + p % across + j,
        };
        let (mut s, mut su, mut sv) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for i in 0..4 {
            for j in 0..4 {
                let point = &coords[3 * index(i, j)..3 * index(i, j) + 3];
                for k in 0..3 {
                    s[k] += bu[i] * bv[j] * point[k];
                    su[k] += du[i] * bv[j] * point[k];
                    sv[k] += bu[i] * dv[j] * point[k];
                }
            }
        }
        let n = [
            su[1] * sv[2] - su[2] * sv[1],
            su[2] * sv[0] - su[0] * sv[2],
            su[0] * sv[1] - su[1] * sv[0],
        ];
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
            .sqrt()
            .max(f64::MIN_POSITIVE);
        for k in 0..3 {
            out.points[3 * i + k] = s[k] as f32;
            normals[3 * i + k] = (n[k] / length) as f32;
        }
    }
}
