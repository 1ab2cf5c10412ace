//! The CPU reference evaluator, in f64: the twin of `shaders/eval.wgsl`.
//!
//! Same Horner order as the kernel (D + u(C + u(B + uA)), its derivatives divided by Δ and Δ^2),
//! but every step in f64 and straight from the [`SamplePlan`](crate::SamplePlan), so it also
//! checks the GPU path's run packing.

use crate::job::EvalJob;
use crate::samples::Samples;

/// Evaluates every curve of `job` in f64.
#[must_use]
pub fn evaluate(job: &EvalJob) -> Samples<f64> {
    let mut samples = Samples::for_job(job);
    let order = job.derivatives().order();
    for c in 0..job.len() {
        let (table, plan) = (job.table(c), job.plan(c));
        let dim = table.dim();
        let base = samples.value_offset(c);
        let [points, d1, d2] = samples.planes_mut();
        for i in 0..plan.len() {
            let loc = plan.loc(i);
            let segment = table.segment(loc.segment);
            let at = base + i * dim..base + (i + 1) * dim;
            segment.eval(loc.u, &mut points[at.clone()]);
            if order >= 1 {
                segment.deriv(loc.u, &mut d1[at.clone()]);
            }
            if order >= 2 {
                segment.deriv2(loc.u, &mut d2[at]);
            }
        }
    }
    samples
}
