//! The adapter's ceiling for any kernel that writes w1's output: a dispatch that only stores
//! as many bytes as w1's samples take (each invocation writing a run of vec4s, as the
//! evaluator's looping shape does), timed on the device, beside the evaluator on w1 and the
//! machine's memset, all in one run.
//!
//! `cargo run --release --example store_ceiling`
//!
//! On lavapipe the storage-buffer store path, not the arithmetic, bounds the evaluator: Mesa
//! 22.3 stores each float through a loop over the SIMD lanes.

use splinegpu::internals::bench::{self, Measurement};
use splinegpu::{Basis, Derivatives, GpuContext, Samples};

/// The store-only kernel: invocation i writes vec4s `i·RUN .. (i+1)·RUN` of `out`, with
/// values that depend on both indices so that nothing can be folded away.
const KERNEL: &str = "
@group(0) @binding(0) var<storage, read_write> out: array<vec4<f32>>;
override RUN: u32;
override INVOCATIONS: u32;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * 65535u * 64u + id.x;
    if i >= INVOCATIONS { return; }
    let f = f32(i);
    for (var j = 0u; j < RUN; j++) {
        let u = f32(j);
        out[i * RUN + j] = vec4(u, f, u * f, u + f);
    }
}";

/// Vec4s one invocation writes: w1's 8 segments of 32 three-dimensional samples per run.
const RUN: u32 = 8 * 32 * 3 / 4;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let gpu = GpuContext::new()?;
    let info = gpu.adapter_info();
    eprintln!("adapter: {} (driver {})", info.name, info.driver_info);
    let job = bench::w1_job(Basis::CatmullRom, Derivatives::None);
    let bytes = job.sample_count() as u64 * 3 * 4;
    let invocations = (bytes / 16).div_ceil(u64::from(RUN)) as u32;

    let device = gpu.device();
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("store ceiling"),
        source: wgpu::ShaderSource::Wgsl(KERNEL.into()),
    });
    let constants = [
        ("RUN", f64::from(RUN)),
        ("INVOCATIONS", f64::from(invocations)),
    ];
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("store ceiling"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &constants,
            ..Default::default()
        },
        cache: None,
    });
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size: u64::from(invocations) * u64::from(RUN) * 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("store ceiling"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: out.as_entire_binding(),
        }],
    });
    let groups = invocations.div_ceil(64);
    let stores = |gpu: &GpuContext| {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
        }
        let start = std::time::Instant::now();
        gpu.queue().submit([encoder.finish()]);
        device.poll(wgpu::PollType::wait_indefinitely()).ok();
        start.elapsed().as_secs_f64()
    };
    stores(&gpu); // compiles the pipeline and faults the buffer in

    let report = |m: &Measurement, memset: f64| {
        println!(
            "{:<26} median {:>7.2} ms  min {:>7.2} ms  {:>6.2} GB/s  {:>5.1} % of memset",
            m.path,
            m.seconds * 1e3,
            m.min_seconds * 1e3,
            m.gbps(),
            100.0 * m.gbps() / memset
        );
    };
    let memset = bench::memset("w1", bytes as usize);
    let memset_gbps = memset.gbps();
    report(&memset, memset_gbps);
    let measured = |path, (seconds, min_seconds, max_seconds)| Measurement {
        workload: "w1",
        path,
        seconds,
        min_seconds,
        max_seconds,
        samples: job.sample_count() as u64,
        bytes,
        float: Some("f32"),
    };
    let ceiling = bench::time(|| Some(stores(&gpu)));
    report(&measured("stores only (wall)", ceiling), memset_gbps);
    let mut samples = Samples::for_job(&job);
    gpu.evaluate_into(&job, &mut samples)?;
    let evaluator = bench::time(|| {
        gpu.evaluate_timed(&job, &mut samples)
            .ok()
            .map(|t| t.seconds)
    });
    report(&measured("evaluator (gpu-device)", evaluator), memset_gbps);
    Ok(())
}
