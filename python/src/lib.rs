//! `splinegpu._native`: the Rust half of the Python package. The Python half
//! (`python/splinegpu/__init__.py`) turns NumPy-shaped arguments (a (C, n, D) array or a list of
//! (n_i, D) arrays, SciPy's `bc_type`) into the plain per-curve lists taken here, and wraps the
//! results.
//!
//! Errors: a bad argument raises `ValueError` with the crate's located message (curve index,
//! field, value); a GPU failure raises `RuntimeError`. The GIL is released while fitting and
//! evaluating. Results come back without a copy where the crate's buffers allow it: a fresh
//! result's arrays take over the evaluator's vectors (NumPy owns them from then on); with `out=`
//! the CPU backend evaluates straight into the given arrays, while the GPU backend copies its
//! readback into them (the mapped GPU buffer cannot outlive the call).

mod args;
mod context;
mod fits;
mod geometry;
mod pieces;
mod queries;
mod roots;
mod splines;
mod surfaces;
mod tensor;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<context::Context>()?;
    m.add_class::<splines::Splines>()?;
    m.add_class::<roots::PendingRoots>()?;
    m.add_function(wrap_pyfunction!(splines::fit, m)?)?;
    m.add_function(wrap_pyfunction!(splines::fit_hermite, m)?)?;
    m.add_function(wrap_pyfunction!(splines::fit_bspline, m)?)?;
    m.add_function(wrap_pyfunction!(roots::solve_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(fits::solve_banded, m)?)?;
    m.add_function(wrap_pyfunction!(fits::fit_lsq, m)?)?;
    m.add_function(wrap_pyfunction!(fits::fit_smoothing, m)?)?;
    m.add_function(wrap_pyfunction!(fits::fit_splrep, m)?)?;
    m.add_function(wrap_pyfunction!(fits::fit_curfit, m)?)?;
    m.add_function(wrap_pyfunction!(fits::fit_regrid, m)?)?;
    m.add_function(wrap_pyfunction!(fits::smoothing_gcv, m)?)?;
    m.add_function(wrap_pyfunction!(pieces::evaluate_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(pieces::integrate_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(pieces::antiderivative_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(pieces::evaluate_bspline, m)?)?;
    m.add_function(wrap_pyfunction!(tensor::evaluate_tensor, m)?)?;
    m.add_function(wrap_pyfunction!(tensor::evaluate_tensors, m)?)?;
    m.add_function(wrap_pyfunction!(tensor::pchip_grid, m)?)?;
    m.add_function(wrap_pyfunction!(tensor::fit_tensor, m)?)?;
    m.add_function(wrap_pyfunction!(tensor::column_ranges, m)?)?;
    m.add_function(wrap_pyfunction!(pieces::bspline_basis, m)?)?;
    m.add_function(wrap_pyfunction!(surfaces::tessellate_surfaces, m)?)?;
    m.add_function(wrap_pyfunction!(geometry::geometry_meshes, m)?)?;
    m.add_function(wrap_pyfunction!(queries::closest_points, m)?)?;
    m.add_function(wrap_pyfunction!(queries::intersections_of, m)?)?;
    m.add_function(wrap_pyfunction!(queries::closest_on_surfaces, m)?)?;
    m.add_function(wrap_pyfunction!(queries::ray_hits, m)?)?;
    m.add("KIND_NAMES", splinegpu::kinds::KIND_NAMES.to_vec())?;
    Ok(())
}
