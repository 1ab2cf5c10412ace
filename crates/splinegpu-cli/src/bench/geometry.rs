//! The geometry workloads: tubes (10,000 closed Catmull-Rom loops of 16 3-D points, radius 0.02
//! of a curve's extent, per_segment 16, 8 sides: 20.5 M vertices with normals) and strokes
//! (10,000 open Catmull-Rom curves of 16 2-D points, width 0.01 of the extent, round joins and
//! caps; per_segment 16 until the certified tolerance sampling lands, where the contract asks
//! a tolerance of 1e-4 of the extent). Paths: memset (the meshes' bytes), cpu-all (the job's
//! meshes made into new memory on every thread, f64), cpu-into (into kept f32 buffers, a
//! renderer's frame) and cpu-call (the whole call: every curve planned on every thread, then
//! made).

use std::hint::black_box;

use splinegpu::geometry::{Cap, Geometry, GeometryJob, Join, MeshPlanes, Stroke, Tube, Width};
use splinegpu::{Basis, Curve, CurveKind, Ends, Points, Sampling};

use crate::bench::measure::{Measurement, memset, time};
use crate::bench::workloads::Rng;

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
pub(crate) fn run(name: &'static str, report: &mut impl FnMut(&Measurement)) {
    let extent = 2.0;
    let work: Vec<(Curve, Geometry, Sampling)> = if name == "tubes" {
        let tube = Geometry::Tube(Tube {
            radius: Width::Constant(0.02 * extent),
            sides: 8,
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
            .map(|c| (c, stroke.clone(), Sampling::PerSegment(16)))
            .collect()
    };
    let plan = || {
        let mut job = GeometryJob::new();
        job.push_many(&work).expect("the workload's curves");
        job
    };
    let job = plan();
    let (vertices, triangles) = (job.vertex_count(), job.triangle_count());
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
    };
    report(&memset(name, (vertices * 7 * 8 + triangles * 12) as usize));
    report(&measure(
        "cpu-all",
        time(|| {
            black_box(job.evaluate_cpu());
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
    report(&measure(
        "cpu-call",
        time(|| {
            black_box(plan().evaluate_cpu());
            None
        }),
    ));
}
