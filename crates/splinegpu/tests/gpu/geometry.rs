//! Tubes, ribbons and strokes made on the GPU against the f64 reference under the contract's
//! promise: the same vertex counts, triangles and t bit for bit; positions within the curve's
//! GPU position bound plus 1e-5 of the radius or width; normals within 1e-3 radians. Curves of
//! many kinds in one call (closed and open, caps, a rational NURBS, per-point radii,
//! arc-length places, loops near the origin and at 1e6, a dashed closed tube with capped
//! dashes; strokes with every join and cap, dashed, rational, at 1e6, at a tolerance). Run
//! under the GPU harness (lavapipe in CI).

use crate::support::{Rng, gpu};
use crate::surfaces::read_back;
use splinegpu::accuracy::gpu_bound;
use splinegpu::geometry::{
    Cap, Dash, Geometry, GeometryJob, Join, Meshes, Ribbon, Stroke, Tube, Width,
};
use splinegpu::{Basis, Curve, CurveKind, EndCondition, Ends, Points, Sampling};

/// A wobbly loop of `n` points about `center`.
fn loop_points(rng: &mut Rng, n: usize, center: f64) -> Vec<f64> {
    (0..n)
        .flat_map(|j| {
            let a = std::f64::consts::TAU * j as f64 / n as f64;
            let r = 1.0 + 0.3 * rng.range(-1.0, 1.0);
            [
                center + r * a.cos(),
                center + r * a.sin(),
                center + 0.4 * rng.range(-1.0, 1.0),
            ]
        })
        .collect()
}

fn curve(kind: CurveKind, dim: usize, coords: Vec<f64>) -> Curve {
    Curve::new(kind, Points::new(dim, coords).unwrap()).unwrap()
}

fn tube(radius: Width, sides: u32, caps: bool) -> Geometry {
    Geometry::Tube(Tube {
        radius,
        sides: Some(sides),
        caps,
        ..Tube::default()
    })
}

/// The job: (curve, geometry, sampling, the largest radius or width).
fn cases() -> Vec<(Curve, Geometry, Sampling, f64)> {
    let mut rng = Rng(45);
    let closed = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let mut out = Vec::new();
    for center in [0.0, 1e6, -3e4] {
        out.push((
            curve(closed.clone(), 3, loop_points(&mut rng, 12, center)),
            tube(Width::Constant(0.05), 8, false),
            Sampling::PerSegment(16),
            0.05,
        ));
    }
    let open = CurveKind::Uniform {
        basis: Basis::BSpline,
        ends: Ends::Repeat,
    };
    out.push((
        curve(open, 3, loop_points(&mut rng, 9, 10.0)),
        tube(Width::Constant(0.1), 6, true),
        Sampling::ArcLength(100),
        0.1,
    ));
    // Uneven knots and a radius per point.
    let natural = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: Some(vec![0.0, 1e-3, 1.0, 1.5, 40.0, 41.0]),
    };
    out.push((
        curve(natural, 3, loop_points(&mut rng, 6, 0.0)),
        tube(
            Width::PerPoint(vec![0.02, 0.05, 0.1, 0.05, 0.02, 0.08]),
            7,
            true,
        ),
        Sampling::PerSegment(12),
        0.1,
    ));
    // A rational NURBS with weights, as a ribbon.
    let nurbs = CurveKind::Nurbs {
        knots: vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 1.0, 1.0, 1.0, 1.0],
        weights: Some(vec![1.0, 2.0, 0.5, 1.5, 1.0, 3.0]),
    };
    out.push((
        curve(nurbs.clone(), 3, loop_points(&mut rng, 6, 5.0)),
        Geometry::Ribbon(Ribbon {
            width: Width::Constant(0.2),
            up: Some([0.0, 0.0, 1.0]),
            dash: None,
        }),
        Sampling::PerSegment(20),
        0.2,
    ));
    out.push((
        curve(closed.clone(), 3, loop_points(&mut rng, 10, 1e6)),
        Geometry::Ribbon(Ribbon {
            width: Width::Constant(0.05),
            ..Ribbon::default()
        }),
        Sampling::PerSegment(16),
        0.05,
    ));
    // A dashed tube (capped dashes on a closed loop).
    out.push((
        curve(closed, 3, loop_points(&mut rng, 8, 0.0)),
        Geometry::Tube(Tube {
            radius: Width::Constant(0.05),
            caps: true,
            dash: Some(Dash {
                lengths: vec![0.5, 0.2],
                offset: 0.0,
            }),
            ..Tube::default()
        }),
        Sampling::PerSegment(8),
        0.05,
    ));
    // Tolerance cross-sections: a loop far from the origin whose sides the method chooses, a
    // rational ribbon, a dashed tube.
    out.push((
        curve(closed_again(), 3, loop_points(&mut rng, 9, 1e6)),
        Geometry::Tube(Tube {
            radius: Width::Constant(0.05),
            ..Tube::default()
        }),
        Sampling::Tolerance(1e-3),
        0.05,
    ));
    out.push((
        curve(nurbs, 3, loop_points(&mut rng, 6, 5.0)),
        Geometry::Ribbon(Ribbon {
            width: Width::PerPoint(vec![0.2, 0.1, 0.3, 0.2, 0.1, 0.2]),
            ..Ribbon::default()
        }),
        Sampling::Tolerance(1e-3),
        0.3,
    ));
    out.push((
        curve(closed_again(), 3, loop_points(&mut rng, 8, 0.0)),
        Geometry::Tube(Tube {
            radius: Width::Constant(0.05),
            sides: Some(24),
            caps: true,
            dash: Some(Dash {
                lengths: vec![0.5, 0.2],
                offset: 0.1,
            }),
            ..Tube::default()
        }),
        Sampling::Tolerance(1e-3),
        0.05,
    ));
    out.extend(strokes(&mut rng));
    out
}

/// Straight cubic Bezier segments through `corners` (x, y pairs), thirds as inner points.
fn polyline(corners: &[[f64; 2]]) -> Vec<f64> {
    let mut out = corners[0].to_vec();
    for pair in corners.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        for k in 1..=3 {
            let f = f64::from(k) / 3.0;
            out.extend([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]);
        }
    }
    out
}

fn stroke(width: Width, join: Join, cap: Cap) -> Geometry {
    Geometry::Stroke(Stroke {
        width,
        join,
        cap,
        ..Stroke::default()
    })
}

/// Strokes: a polyline with miters and a bevel past the miter limit, round joins and caps at
/// 1e6, a cusp with square caps, a rational NURBS with a width per point, a dashed closed
/// curve, and one at a tolerance.
fn strokes(rng: &mut Rng) -> Vec<(Curve, Geometry, Sampling, f64)> {
    let flat =
        |coords: Vec<f64>| -> Vec<f64> { coords.chunks(3).flat_map(|p| [p[0], p[1]]).collect() };
    let zigzag = |at: f64| {
        polyline(&[
            [at, at],
            [at + 1.0, at],
            [at + 2.0, at + 0.1],
            [at + 1.0, at + 0.2],
        ])
    };
    let nurbs = CurveKind::Nurbs {
        knots: vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 1.0, 1.0, 1.0, 1.0],
        weights: Some(vec![1.0, 2.0, 0.5, 1.5, 1.0, 3.0]),
    };
    vec![
        (
            curve(CurveKind::Bezier, 2, zigzag(0.0)),
            stroke(Width::Constant(0.05), Join::Miter, Cap::Butt),
            Sampling::PerSegment(4),
            0.05,
        ),
        (
            curve(CurveKind::Bezier, 2, zigzag(1e6)),
            stroke(Width::Constant(0.05), Join::Round, Cap::Round),
            Sampling::PerSegment(4),
            0.05,
        ),
        (
            curve(
                CurveKind::Bezier,
                2,
                vec![0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0],
            ),
            stroke(Width::Constant(0.05), Join::Bevel, Cap::Square),
            Sampling::PerSegment(9),
            0.05,
        ),
        (
            curve(nurbs, 2, flat(loop_points(rng, 6, 1e6))),
            stroke(
                Width::PerPoint(vec![0.02, 0.05, 0.1, 0.05, 0.02, 0.08]),
                Join::Miter,
                Cap::Round,
            ),
            Sampling::PerSegment(12),
            0.1,
        ),
        (
            curve(closed_again(), 2, flat(loop_points(rng, 9, -2.0))),
            Geometry::Stroke(Stroke {
                width: Width::Constant(0.05),
                cap: Cap::Round,
                dash: Some(Dash {
                    lengths: vec![0.8, 0.3],
                    offset: 0.1,
                }),
                ..Stroke::default()
            }),
            Sampling::PerSegment(8),
            0.05,
        ),
        (
            curve(
                CurveKind::Uniform {
                    basis: Basis::CatmullRom,
                    ends: Ends::Control,
                },
                2,
                flat(loop_points(rng, 7, 0.0)),
            ),
            stroke(Width::Constant(0.05), Join::Round, Cap::Round),
            Sampling::Tolerance(1e-3),
            0.05,
        ),
    ]
}

fn closed_again() -> CurveKind {
    CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    }
}

fn range(offsets: &[u64], c: usize) -> std::ops::Range<usize> {
    offsets[c] as usize..offsets[c + 1] as usize
}

/// The GPU's meshes against the CPU's, curve by curve, under the promise. Measured on
/// lavapipe: positions at most 0.10 of the bound (the loops at 1e6, at f32's last bits),
/// normals 1.0e-4 rad apart at most (the natural spline's knots 1e-3 and 40 apart).
fn check(cases: &[(Curve, Geometry, Sampling, f64)], cpu: &Meshes, gpu: &Meshes<f32>) {
    assert_eq!(gpu.vertex_offsets, cpu.vertex_offsets);
    assert_eq!(gpu.triangle_offsets, cpu.triangle_offsets);
    assert_eq!(gpu.triangles, cpu.triangles);
    assert_eq!(gpu.t, cpu.t, "t bit for bit");
    for (c, (curve, _, _, radius)) in cases.iter().enumerate() {
        let table = curve.fit();
        let points = curve.points();
        let extent = (0..points.dim())
            .map(|k| {
                let values = (0..points.len()).map(|i| points.point(i)[k]);
                let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                });
                hi - lo
            })
            .fold(0.0, f64::max);
        let mut worst_position: f64 = 0.0;
        let mut worst_angle: f64 = 0.0;
        for v in range(&cpu.vertex_offsets, c) {
            for k in 0..3 {
                let want = cpu.points[3 * v + k];
                let got = f64::from(gpu.points[3 * v + k]);
                // The largest position bound over the curve's segments, plus 1e-5 r.
                let bound = (0..table.len())
                    .map(|s| gpu_bound(&table.segment(s), extent, 0, k.min(points.dim() - 1), want))
                    .fold(0.0, f64::max)
                    + 1e-5 * radius;
                worst_position = worst_position.max((got - want).abs() / bound);
            }
            let (n, m): (Vec<f64>, Vec<f64>) = (0..3)
                .map(|k| (cpu.normals[3 * v + k], f64::from(gpu.normals[3 * v + k])))
                .unzip();
            let dot: f64 = n.iter().zip(&m).map(|(a, b)| a * b).sum();
            let length: f64 = m.iter().map(|x| x * x).sum::<f64>().sqrt();
            worst_angle = worst_angle.max((dot / length).clamp(-1.0, 1.0).acos());
        }
        assert!(
            worst_position <= 1.0,
            "curve {c}: {worst_position} of the position bound"
        );
        assert!(
            worst_angle <= 1e-3,
            "curve {c}: normals {worst_angle} rad apart"
        );
    }
}

pub(crate) fn tubes_ribbons_and_strokes_of_many_kinds_in_one_call_keep_the_promise() {
    let Some(gpu) = gpu() else { return };
    let cases = cases();
    let mut job = GeometryJob::new();
    for (curve, geometry, sampling, _) in &cases {
        job.push(curve, geometry, sampling).unwrap();
    }
    let cpu = job.evaluate_cpu();
    let made = gpu.evaluate_geometry(&job).unwrap();
    check(&cases, &cpu, &made);
    // Group by group (as the command line writes them), the same meshes.
    let (mut points, mut normals) = (Vec::new(), Vec::new());
    for group in job.groups(500) {
        let part = gpu.evaluate_geometry_group(&job, group).unwrap();
        points.extend(part.points);
        normals.extend(part.normals);
    }
    assert!(points == made.points && normals == made.normals);
}

/// The renderer's path: the recording writes what `evaluate_geometry` gives, bit for bit, into
/// the renderer's vertex buffer (position and normal interleaved), its indices are the
/// triangles over all vertices, a moving tube and a moving stroke refitted in place are
/// recorded as a new job of them evaluates; unusable targets, a refit of another shape and a
/// stroke whose joins changed are refused by name.
pub(crate) fn a_renderer_records_meshes_into_its_own_buffers_and_refits_moving_curves() {
    use splinegpu::wgpu;
    let Some(gpu) = gpu() else { return };
    let cases = cases();
    let mut job = GeometryJob::new();
    for (curve, geometry, sampling, _) in &cases {
        job.push(curve, geometry, sampling).unwrap();
    }
    let mut recording = gpu.geometry_recording(&job).unwrap();
    let layout = recording.layout().clone();
    assert_eq!(layout.stride, 24);
    assert_eq!(layout.bytes, 24 * job.vertex_count());
    let target = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("renderer vertices"),
        size: 256 + layout.bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let record = |recording: &splinegpu::GeometryRecording| -> Vec<f32> {
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        recording
            .record_into(gpu, &mut encoder, &target, 256)
            .unwrap();
        gpu.queue().submit([encoder.finish()]);
        read_back(gpu, &target, 256 + layout.bytes)[64..].to_vec()
    };
    let interleaved = |m: &Meshes<f32>| -> Vec<f32> {
        m.points
            .chunks_exact(3)
            .zip(m.normals.chunks_exact(3))
            .flat_map(|(p, n)| p.iter().chain(n).copied())
            .collect()
    };
    let made = gpu.evaluate_geometry(&job).unwrap();
    assert!(
        record(&recording) == interleaved(&made),
        "recorded vertices differ"
    );
    let whole: Vec<u32> = (0..job.len())
        .flat_map(|c| {
            let first = made.vertex_offsets[c] as u32;
            made.triangles[range(&made.triangle_offsets, c)]
                .iter()
                .flatten()
                .map(move |&i| first + i)
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(recording.indices(), whole.as_slice());
    // Curve 0 (a tube) and the first stroke move: refitted on the host, their tables uploaded
    // in place.
    let first_stroke = cases
        .iter()
        .position(|(_, g, _, _)| matches!(g, Geometry::Stroke(_)))
        .unwrap();
    for c in [0, first_stroke] {
        let curve = &cases[c].0;
        let moved: Vec<f64> = curve
            .points()
            .coords()
            .iter()
            .map(|x| x * 1.1 + 0.3)
            .collect();
        let dim = curve.points().dim();
        let moved = Curve::new(curve.kind().clone(), Points::new(dim, moved).unwrap()).unwrap();
        job.refit(c, &moved).unwrap();
    }
    recording.refit(gpu, &job).unwrap();
    let again = gpu.evaluate_geometry(&job).unwrap();
    assert!(
        record(&recording) == interleaved(&again),
        "refitted vertices differ"
    );
    assert!(again.points != made.points);
    // Refused: another job's shape; a stroke whose miter and bevel swapped corners (the same
    // counts, other triangles); targets it cannot write.
    let mut other = GeometryJob::new();
    other.push(&cases[1].0, &cases[1].1, &cases[1].2).unwrap();
    let error = recording.refit(gpu, &other).unwrap_err();
    assert_eq!(error.field.as_deref(), Some("job"));
    let swapped = polyline(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.1], [-1.0, 0.25]]);
    let swapped = curve(CurveKind::Bezier, 2, swapped);
    let mut other = GeometryJob::new();
    for (c, (curve, geometry, sampling, _)) in cases.iter().enumerate() {
        let curve = if c == first_stroke { &swapped } else { curve };
        other.push(curve, geometry, sampling).unwrap();
    }
    let error = recording.refit(gpu, &other).unwrap_err();
    assert!(error.to_string().contains("other joins or caps"), "{error}");
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    let small = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 64,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    assert!(recording.record_into(gpu, &mut encoder, &small, 0).is_err());
    assert!(
        recording
            .record_into(gpu, &mut encoder, &target, 4)
            .is_err()
    );
}
