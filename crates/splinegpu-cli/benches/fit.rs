//! Interpolating fits: the fit-1m workload (a 3-D natural spline through 1,000,000 non-uniform
//! knots, into a reused table) and a small fit, as a library caller makes them.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use splinegpu::{EndCondition, Fitter, SegmentTable};

fn fits(c: &mut Criterion) {
    let (t, values) = splinegpu_cli::bench::fit_1m_data();
    let mut fitter = Fitter::new();
    let mut table = SegmentTable::default();
    let mut group = c.benchmark_group("fit");
    group.sample_size(20);
    for condition in [EndCondition::Natural, EndCondition::NotAKnot] {
        group.bench_function(format!("1m knots, 3-D, {}", condition.name()), |b| {
            b.iter(|| {
                fitter
                    .fit_into(black_box(&t), black_box(&values), 3, &condition, &mut table)
                    .unwrap();
            });
        });
    }
    group.bench_function("64 knots, 3-D, natural", |b| {
        b.iter(|| {
            fitter
                .fit_into(
                    black_box(&t[..64]),
                    black_box(&values[..192]),
                    3,
                    &EndCondition::Natural,
                    &mut table,
                )
                .unwrap();
        });
    });
    group.finish();
}

criterion_group!(benches, fits);
criterion_main!(benches);
