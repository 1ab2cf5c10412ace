//! Bulk evaluation: w1 (10,000 Catmull-Rom curves, 9,930,000 samples in 3-D) on the CPU
//! reference and, where wgpu finds an adapter, end to end on the GPU.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use splinegpu::{Basis, Derivatives, GpuContext};

fn w1(c: &mut Criterion) {
    let job = splinegpu_cli::bench::w1_job(Basis::CatmullRom, Derivatives::None);
    let mut group = c.benchmark_group("w1");
    group.sample_size(10);
    group.bench_function("cpu reference, f64, 1 thread", |b| {
        b.iter(|| black_box(splinegpu::evaluate_reference(black_box(&job))));
    });
    match GpuContext::new() {
        Ok(gpu) => {
            group.bench_function("gpu end to end", |b| {
                b.iter(|| black_box(gpu.evaluate(black_box(&job)).unwrap()))
            });
        }
        Err(e) => eprintln!("no GPU adapter ({e}): GPU benches skipped"),
    }
    group.finish();
}

criterion_group!(benches, w1);
criterion_main!(benches);
