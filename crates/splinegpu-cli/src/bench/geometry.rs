//! The geometry workloads: tubes (10,000 closed Catmull-Rom loops of 16 3-D points, radius 0.02
//! of a curve's extent, per_segment 16, 8 sides: 20.5 M vertices with normals) and strokes
//! (10,000 open Catmull-Rom curves of 16 2-D points, width 0.01 of the extent, round joins and
//! caps, tolerance 1e-4 of the extent; every path's "max_error" the largest distance of its
//! mesh from the exact stroke over the first 100 curves, `bench::strokes`). Paths: memset (the
//! meshes' bytes), cpu-all (the job's
//! meshes made into new memory on every thread, f64), cpu-1t (the same on one thread),
//! cpu-into (into kept f32 buffers, t and triangles too), cpu-refit (the vertices alone into
//! kept f32 buffers: a renderer's frame after a refit, `evaluate_vertices_into`), cpu-call (the whole call: every curve
//! planned on every thread, then made), gpu-device (the renderer's recording of the job into
//! kept vertex buffers, from submission to completion: no packing, no readback) and
//! gpu-end-to-end (`GpuContext::evaluate_geometry`: packed, uploaded, made, read back; a
//! stroke's triangles made on the host from its f64 mesh); for tubes also plain-loop (the same
//! rings hand-written into the same f32 buffers as cpu-into, on every thread: Catmull-Rom from
//! its points, parallel-transport frames, radial normals); for strokes also cpu-call-1t (the
//! whole call on one thread) and lyon (lyon's stroke tessellator on the same curves' Bezier
//! segments, same width, joins, caps and tolerance, one thread).

use std::hint::black_box;

use rayon::prelude::*;
use splinegpu::geometry::{Cap, Geometry, GeometryJob, Join, MeshPlanes, Stroke, Tube, Width};
use splinegpu::{Basis, Curve, CurveKind, Ends, GpuContext, GpuError, Points, Sampling};

use crate::bench::measure::{Measurement, memset, time};
use crate::bench::strokes;
use crate::bench::workloads::Rng;

/// The strokes' tolerance, in units of a curve's extent (the contract's 1e-4).
const STROKE_TOLERANCE: f64 = 1e-4;

/// The strokes whose meshes' errors are measured (ours and lyon's).
const ERROR_CURVES: usize = 100;

/// `count` curves of 16 points in `dim` dimensions about a unit circle (radius 1 ± 0.3,
/// out of its plane ± 0.3 in 3-D), closed or open, each with its extent (about 2).
fn curves(count: usize, dim: usize, ends: Ends, seed: u64) -> Vec<Curve> {
    let mut rng = Rng(seed);
    (0..count)
        .map(|_| {
            let points: Vec<f64> = (0..16)
                .flat_map(|i| {
                    let a = std::f64::consts::TAU * f64::from(i) / 16.0;
                    let r = 1.0 + rng.range(-0.3, 0.3);
                    let z = rng.range(-0.3, 0.3);
                    [r * a.cos(), r * a.sin(), z]
                        .into_iter()
                        .take(dim)
                        .collect::<Vec<_>>()
                })
                .collect();
            let kind = CurveKind::Uniform {
                basis: Basis::CatmullRom,
                ends,
            };
            Curve::new(kind, Points::new(dim, points).expect("16 points")).expect("a curve")
        })
        .collect()
}

/// Runs "tubes" or "strokes", reporting each path.
///
/// # Errors
/// A GPU failure.
pub(crate) fn run(
    name: &'static str,
    gpu: Option<&GpuContext>,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), GpuError> {
    let extent = 2.0;
    let work: Vec<(Curve, Geometry, Sampling)> = if name == "tubes" {
        let tube = Geometry::Tube(Tube {
            radius: Width::Constant(0.02 * extent),
            sides: Some(8),
            ..Tube::default()
        });
        curves(10_000, 3, Ends::Closed, 7)
            .into_iter()
            .map(|c| (c, tube.clone(), Sampling::PerSegment(16)))
            .collect()
    } else {
        let stroke = Geometry::Stroke(Stroke {
            width: Width::Constant(0.01 * extent),
            cap: Cap::Round,
            join: Join::Round,
            ..Stroke::default()
        });
        curves(10_000, 2, Ends::Control, 8)
            .into_iter()
            .map(|c| {
                (
                    c,
                    stroke.clone(),
                    Sampling::Tolerance(STROKE_TOLERANCE * extent),
                )
            })
            .collect()
    };
    let plan = || {
        let mut job = GeometryJob::new();
        job.push_many(&work).expect("the workload's curves");
        job
    };
    let job = plan();
    let (vertices, triangles) = (job.vertex_count(), job.triangle_count());
    let (stroke_width, tol) = (0.01 * extent, STROKE_TOLERANCE * extent);
    let beziers: Vec<strokes::Beziers> = if name == "strokes" {
        work.iter().map(|(c, _, _)| strokes::beziers(c)).collect()
    } else {
        Vec::new()
    };
    // The strokes' accuracy, ours and lyon's, on the first curves.
    let errors = (name == "strokes").then(|| {
        let first = &work[..ERROR_CURVES];
        let mut part = GeometryJob::new();
        part.push_many(first).expect("the workload's curves");
        strokes::max_errors(
            &beziers[..ERROR_CURVES],
            &part.evaluate_cpu(),
            stroke_width,
            tol,
        )
    });
    // Useful bytes: f64 positions and normals.
    let bytes = vertices * 6 * 8;
    let measure = |path: &'static str, times: (f64, f64, f64)| Measurement {
        workload: name,
        path,
        seconds: times.0,
        min_seconds: times.1,
        max_seconds: times.2,
        samples: vertices,
        bytes,
        float: Some("f64"),
        misses: None,
        max_error: errors.map(|e| e.0),
    };
    report(&memset(name, (vertices * 7 * 8 + triangles * 12) as usize));
    report(&measure(
        "cpu-all",
        time(|| {
            black_box(job.evaluate_cpu());
            None
        }),
    ));
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool of one thread");
    report(&measure(
        "cpu-1t",
        time(|| {
            one_thread.install(|| black_box(job.evaluate_cpu()));
            None
        }),
    ));
    // A renderer's frame: the same job's meshes into kept f32 buffers.
    let (v, f) = (vertices as usize, triangles as usize);
    let (mut points, mut normals) = (vec![0f32; 3 * v], vec![0f32; 3 * v]);
    let (mut t, mut faces) = (vec![0.0; v], vec![[0u32; 3]; f]);
    let f32_measure = |times| Measurement {
        bytes: vertices * 6 * 4,
        float: Some("f32"),
        misses: None,
        max_error: None,
        ..measure("cpu-into", times)
    };
    report(&f32_measure(time(|| {
        let planes = MeshPlanes {
            points: &mut points,
            normals: &mut normals,
            t: &mut t,
            triangles: &mut faces,
        };
        job.evaluate_into(planes)
            .expect("buffers sized for the job");
        black_box(&points);
        None
    })));
    report(&f32_measure_as(
        "cpu-refit",
        f32_measure,
        time(|| {
            job.evaluate_vertices_into(&mut points, &mut normals)
                .expect("buffers sized for the job");
            black_box(&points);
            None
        }),
    ));
    if name == "tubes" {
        let curves: Vec<&Curve> = work.iter().map(|(c, _, _)| c).collect();
        let rings = 16 * 16;
        report(&f32_measure_as(
            "plain-loop",
            f32_measure,
            time(|| {
                plain_tubes(&curves, rings, 8, 0.02 * extent, &mut points, &mut normals);
                black_box(&points);
                None
            }),
        ));
    }
    report(&measure(
        "cpu-call",
        time(|| {
            black_box(plan().evaluate_cpu());
            None
        }),
    ));
    if let Some((_, lyon_error)) = errors {
        report(&measure(
            "cpu-call-1t",
            time(|| {
                one_thread.install(|| black_box(plan().evaluate_cpu()));
                None
            }),
        ));
        let mut lyon_vertices = 0;
        let lyon = time(|| {
            let mut out = lyon_tessellation::VertexBuffers::new();
            strokes::lyon_strokes(&beziers, stroke_width, tol, &mut out);
            lyon_vertices = out.vertices.len() as u64;
            black_box(out);
            None
        });
        report(&Measurement {
            samples: lyon_vertices,
            bytes: lyon_vertices * 2 * 4,
            float: Some("f32"),
            max_error: Some(lyon_error),
            ..measure("lyon", lyon)
        });
    }
    if let Some(gpu) = gpu {
        gpu_paths(gpu, name, &work, &job, report)?;
    }
    Ok(())
}

/// A measurement of `path` in f32 as `f32_measure` makes them.
fn f32_measure_as(
    path: &'static str,
    f32_measure: impl Fn((f64, f64, f64)) -> Measurement,
    times: (f64, f64, f64),
) -> Measurement {
    Measurement {
        path,
        ..f32_measure(times)
    }
}

/// gpu-device and gpu-end-to-end for workload `name`: the job cut into recordings that each
/// fit a storage binding (lavapipe binds 128 MiB), recorded into kept vertex buffers in one
/// submission; and the whole evaluation with its readback.
fn gpu_paths(
    gpu: &GpuContext,
    name: &'static str,
    work: &[(Curve, Geometry, Sampling)],
    job: &GeometryJob,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), GpuError> {
    let limits = gpu.device().limits();
    let binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let mut recordings = Vec::new();
    let mut start = 0;
    for group in job.groups(binding / 24) {
        let mut part = GeometryJob::new();
        part.push_many(&work[group.clone()])
            .expect("the workload's curves");
        let recording = gpu.geometry_recording(&part)?;
        let target = gpu
            .device()
            .create_buffer(&splinegpu::wgpu::BufferDescriptor {
                label: Some("bench mesh vertices"),
                size: recording.layout().bytes.max(4),
                usage: splinegpu::wgpu::BufferUsages::STORAGE
                    | splinegpu::wgpu::BufferUsages::VERTEX,
                mapped_at_creation: false,
            });
        recordings.push((recording, target));
        start = group.end;
    }
    debug_assert_eq!(start, job.len());
    let (vertices, mut failure) = (job.vertex_count(), None);
    let device = time(|| {
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        for (recording, target) in &recordings {
            if let Err(e) = recording.record_into(gpu, &mut encoder, target, 0) {
                failure.get_or_insert(e);
            }
        }
        gpu.queue().submit([encoder.finish()]);
        gpu.device()
            .poll(splinegpu::wgpu::PollType::wait_indefinitely())
            .expect("the device finishes");
        None
    });
    if let Some(e) = failure {
        return Err(e);
    }
    let measure = |path, times: (f64, f64, f64)| Measurement {
        workload: name,
        path,
        seconds: times.0,
        min_seconds: times.1,
        max_seconds: times.2,
        samples: vertices,
        bytes: vertices * 6 * 4,
        float: Some("f32"),
        misses: None,
        max_error: None,
    };
    report(&measure("gpu-device", device));
    let mut failure = None;
    let end_to_end = time(|| {
        if let Err(e) = gpu.evaluate_geometry(job).map(black_box) {
            failure.get_or_insert(e);
        }
        None
    });
    if let Some(e) = failure {
        return Err(e);
    }
    report(&measure("gpu-end-to-end", end_to_end));
    Ok(())
}

/// The floor for the tubes: closed uniform Catmull-Rom loops evaluated from their points with
/// the basis written out, `per_segment` rings a segment, frames by parallel transport (the
/// normal projected onto each new tangent's plane, the cheapest form), `sides` vertices a ring at
/// `radius` with radial normals, into the same f32 buffers (the closing twist left in: a plain
/// loop that a renderer might write).
fn plain_tubes(
    curves: &[&Curve],
    rings: usize,
    sides: usize,
    radius: f64,
    points: &mut [f32],
    normals: &mut [f32],
) {
    let per_curve = 3 * rings * sides;
    let turns: Vec<(f64, f64)> = (0..sides)
        .map(|k| (std::f64::consts::TAU * k as f64 / sides as f64).sin_cos())
        .collect();
    points
        .par_chunks_mut(per_curve)
        .zip(normals.par_chunks_mut(per_curve))
        .zip(curves.par_iter())
        .for_each(|((points, normals), curve)| {
            let p = curve.points();
            let n = p.len();
            let at = |i: usize| -> [f64; 3] {
                let q = p.point(i % n);
                [q[0], q[1], q[2]]
            };
            let per_segment = rings / n;
            let mut normal = [0.0f64; 3];
            for j in 0..rings {
                let (s, u) = (
                    j / per_segment,
                    (j % per_segment) as f64 / per_segment as f64,
                );
                let (p0, p1, p2, p3) = (at(s + n - 1), at(s), at(s + 1), at(s + 2));
                let (u2, u3) = (u * u, u * u * u);
                let mut c = [0.0; 3];
                let mut d = [0.0; 3];
                for k in 0..3 {
                    c[k] = 0.5
                        * (2.0 * p1[k]
                            + (p2[k] - p0[k]) * u
                            + (2.0 * p0[k] - 5.0 * p1[k] + 4.0 * p2[k] - p3[k]) * u2
                            + (3.0 * p1[k] - p0[k] - 3.0 * p2[k] + p3[k]) * u3);
                    d[k] = 0.5
                        * ((p2[k] - p0[k])
                            + 2.0 * (2.0 * p0[k] - 5.0 * p1[k] + 4.0 * p2[k] - p3[k]) * u
                            + 3.0 * (3.0 * p1[k] - p0[k] - 3.0 * p2[k] + p3[k]) * u2);
                }
                let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let t = d.map(|x| x / length);
                if j == 0 {
                    // The axis least aligned with the tangent, made perpendicular.
                    let e = if t[0].abs() <= t[1].abs() && t[0].abs() <= t[2].abs() {
                        [1.0, 0.0, 0.0]
                    } else if t[1].abs() <= t[2].abs() {
                        [0.0, 1.0, 0.0]
                    } else {
                        [0.0, 0.0, 1.0]
                    };
                    let along = e[0] * t[0] + e[1] * t[1] + e[2] * t[2];
                    normal = [
                        e[0] - along * t[0],
                        e[1] - along * t[1],
                        e[2] - along * t[2],
                    ];
                } else {
                    // Parallel transport: remove the new tangent's part.
                    let along = normal[0] * t[0] + normal[1] * t[1] + normal[2] * t[2];
                    normal = [
                        normal[0] - along * t[0],
                        normal[1] - along * t[1],
                        normal[2] - along * t[2],
                    ];
                }
                let size =
                    (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
                normal = normal.map(|x| x / size);
                let b = [
                    t[1] * normal[2] - t[2] * normal[1],
                    t[2] * normal[0] - t[0] * normal[2],
                    t[0] * normal[1] - t[1] * normal[0],
                ];
                for (k, &(sin, cos)) in turns.iter().enumerate() {
                    let v = 3 * (j * sides + k);
                    for i in 0..3 {
                        let e = cos * normal[i] + sin * b[i];
                        points[v + i] = (c[i] + radius * e) as f32;
                        normals[v + i] = e as f32;
                    }
                }
            }
        });
}
