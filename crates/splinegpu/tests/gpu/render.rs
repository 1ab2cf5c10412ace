//! Renderer integration: samples recorded into a caller's encoder and buffer, laid out as
//! `OutputLayout` says, and drawn as line strips with no readback of the samples.

use crate::support::gpu;
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, GpuError, Points, Sampling,
    TargetError,
};

/// A closed Catmull-Rom curve through 6 points on the circle of radius 0.6.
fn ring(derivatives: Derivatives) -> EvalJob {
    let points: Vec<f64> = (0..6)
        .flat_map(|i| {
            let a = f64::from(i) * std::f64::consts::PI / 3.0;
            [0.6 * a.cos(), 0.6 * a.sin(), 0.25]
        })
        .collect();
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let mut job = EvalJob::new(derivatives);
    job.push(
        &Curve::new(kind, Points::new(3, points).unwrap()).unwrap(),
        &Sampling::PerSegment(64),
    )
    .unwrap();
    job
}

pub(crate) fn recorded_samples_follow_the_output_layout() {
    let Some(context) = gpu() else { return };
    let (device, queue) = (context.device(), context.queue());
    let mut job = ring(Derivatives::Second);
    let kind = CurveKind::Uniform {
        basis: Basis::BSpline,
        ends: Ends::Repeat,
    };
    job.push(
        &Curve::new(
            kind,
            Points::new(2, vec![0.0, 0.0, 1.0, 2.0, 3.0, -1.0]).unwrap(),
        )
        .unwrap(),
        &Sampling::PerSegment(5),
    )
    .unwrap();
    // 5-D samples, 3 per segment: runs that start between vec4s.
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let coords = (0..30).map(|v| f64::from(v % 7) - 3.0).collect();
    job.push(
        &Curve::new(kind, Points::new(5, coords).unwrap()).unwrap(),
        &Sampling::PerSegment(3),
    )
    .unwrap();
    // Samples the kernel places itself: a dash pattern along the ring, by arc length.
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let ring_points = Points::new(2, vec![0.6, 0.0, 0.0, 0.6, -0.6, 0.0, 0.0, -0.6]).unwrap();
    job.push(
        &Curve::new(kind, ring_points).unwrap(),
        &Sampling::ArcLength(41),
    )
    .unwrap();
    // The job whole, and cut into dispatches of 24 floats that start wherever a run does.
    let cut = GpuContext::from_device(device, queue).with_max_dispatch_values(24);
    for context in [context, &cut] {
        check_recorded_samples(context, &job);
    }
}

/// Records `job` into a buffer at an offset, reads it back, and compares every curve's planes
/// with `evaluate`'s samples where the output layout puts them.
fn check_recorded_samples(context: &GpuContext, job: &EvalJob) {
    let (device, queue) = (context.device(), context.queue());
    let layout = context.output_layout(job);
    let offset = 256;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("vertices"),
        size: offset + layout.bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    assert_eq!(
        context
            .record_into(&mut encoder, job, &buffer, offset)
            .unwrap(),
        layout
    );
    let download = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("check"),
        size: layout.bytes,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(&buffer, offset, &download, 0, layout.bytes);
    queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    download.map_async(wgpu::MapMode::Read, .., move |r| tx.send(r).unwrap());
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    rx.recv().unwrap().unwrap();
    let bytes = download.get_mapped_range(..).unwrap();
    let floats: &[f32] = bytemuck::cast_slice(&bytes);
    let expected = context.evaluate(job).unwrap();
    for c in 0..job.len() {
        let e = expected.curve(c);
        let n = layout.counts[c] as usize * layout.dims[c] as usize;
        for (p, plane) in [e.points, e.d1.unwrap(), e.d2.unwrap()]
            .into_iter()
            .enumerate()
        {
            let start = ((p as u64 * layout.plane_bytes + layout.curve_starts[c]) / 4) as usize;
            assert_eq!(&floats[start..start + n], plane, "curve {c} plane {p}");
        }
    }
}

pub(crate) fn unusable_target_buffers_are_errors() {
    let Some(context) = gpu() else { return };
    let device = context.device();
    let job = ring(Derivatives::None);
    let bytes = context.output_layout(&job).bytes;
    let buffer = |usage, size| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    let alignment = u64::from(device.limits().min_storage_buffer_offset_alignment);
    let cases = [
        (
            buffer(wgpu::BufferUsages::VERTEX, bytes),
            0,
            TargetError::MissingStorageUsage,
        ),
        (
            buffer(wgpu::BufferUsages::STORAGE, bytes),
            4,
            TargetError::MisalignedOffset {
                offset: 4,
                alignment,
            },
        ),
        (
            buffer(wgpu::BufferUsages::STORAGE, bytes - 16),
            0,
            TargetError::TooSmall {
                available: bytes - 16,
                needed: bytes,
            },
        ),
    ];
    for (target, offset, expected) in cases {
        match context.record_into(&mut encoder, &job, &target, offset) {
            Err(GpuError::Target(e)) => assert_eq!(e, expected),
            other => panic!("expected {expected:?}, got {other:?}"),
        }
    }
}
