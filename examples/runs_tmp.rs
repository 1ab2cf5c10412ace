//! tmp
fn main() {
    let job = splinegpu::bench::w1_job(splinegpu::Basis::CatmullRom, splinegpu::Derivatives::None);
    let p = splinegpu::gpu::layout::pack(
        &job,
        splinegpu::KernelShape::LOOPING,
        splinegpu::gpu::layout::BatchLimits {
            values: usize::MAX,
            runs: usize::MAX,
        },
    )
    .unwrap();
    println!(
        "runs {} batches {} first {:?}",
        p.runs.len(),
        p.batches.len(),
        &p.runs[..3]
    );
}
