//! Surfaces from NumPy (`Context.tessellate_surfaces`): nets of points and the contract's
//! surface fields into the crate's [`Surface`]s, fitted, planned and evaluated on the context's
//! backend, into the arrays the command line's NPZ holds ("uv", "points", "du", "dv", "duu",
//! "duv", "dvv", "normals", "triangles" indexing the whole vertex array, "surface_offsets",
//! "triangle_offsets", "patch" where a patch list is present): float64 written in place by the
//! CPU, float32 from the GPU.

use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use splinegpu::surface::{
    Net, PatchTable, Surface, SurfaceJob, SurfaceKind, SurfacePlan, SurfacePlanes, SurfaceSampling,
};
use splinegpu::{Derivatives, EndCondition, Ends, InputError, SampleFloat};

use crate::args::{array, runtime_error, value_error};
use crate::context::{Context, available_memory};

/// The surface fields, as the Python side normalises them: one value for every surface, or
/// (per-surface arrays) a list with one entry per surface.
#[derive(FromPyObject)]
pub(crate) struct SurfaceFields<'py> {
    #[pyo3(item)]
    ends: Option<(String, String)>,
    #[pyo3(item)]
    tension: Option<f64>,
    #[pyo3(item)]
    bias: Option<f64>,
    #[pyo3(item)]
    matrix: Option<[[f64; 4]; 4]>,
    #[pyo3(item)]
    patches: Option<Vec<PyReadonlyArray2<'py, i64>>>,
    #[pyo3(item)]
    conditions: Option<(String, String)>,
    #[pyo3(item)]
    u: Option<Vec<PyReadonlyArray1<'py, f64>>>,
    #[pyo3(item)]
    v: Option<Vec<PyReadonlyArray1<'py, f64>>>,
    #[pyo3(item)]
    knots_u: Option<Vec<PyReadonlyArray1<'py, f64>>>,
    #[pyo3(item)]
    knots_v: Option<Vec<PyReadonlyArray1<'py, f64>>>,
    #[pyo3(item)]
    weights: Option<Vec<PyReadonlyArray2<'py, f64>>>,
}

/// The sampling, told apart by its type: per_segment (k_u, k_v), tolerance (a number), or at
/// (one (N, 2) or (N, 3) array per surface).
#[derive(FromPyObject)]
pub(crate) enum SurfaceSamplingArg<'py> {
    PerSegment((u32, u32)),
    Tolerance(f64),
    At(Vec<PyReadonlyArray2<'py, f64>>),
}

/// Surface s's kind from the fields, through the library's table of surface kinds.
fn kind_of(name: &str, f: &SurfaceFields<'_>, s: usize) -> Result<SurfaceKind, InputError> {
    let slice = |list: &Option<Vec<PyReadonlyArray1<'_, f64>>>| -> Option<Vec<f64>> {
        list.as_ref()
            .map(|l| l[s].as_slice().map(<[f64]>::to_vec).unwrap_or_default())
    };
    let patches = match &f.patches {
        None => None,
        Some(patches) => {
            let rows = patches[s].as_array();
            let mut list = Vec::with_capacity(rows.nrows());
            for (p, row) in rows.outer_iter().enumerate() {
                let mut indices = [0usize; 16];
                for (j, (&i, slot)) in row.iter().zip(&mut indices).enumerate() {
                    *slot = usize::try_from(i).map_err(|_| {
                        InputError::field("patches", format!("patches[{p}][{j}] = {i} is negative"))
                    })?;
                }
                list.push(indices);
            }
            Some(list)
        }
    };
    let fields = splinegpu::surface::SurfaceFields {
        ends: pair(&f.ends, ends)?,
        tension: f.tension,
        bias: f.bias,
        matrix: f.matrix,
        patches,
        conditions: pair(&f.conditions, condition)?,
        u: slice(&f.u),
        v: slice(&f.v),
        knots_u: slice(&f.knots_u),
        knots_v: slice(&f.knots_v),
        weights: f
            .weights
            .as_ref()
            .map(|w| w[s].as_slice().map(<[f64]>::to_vec).unwrap_or_default()),
    };
    SurfaceKind::named(name, fields)
}

/// A field given along u and along v, each read by `each`.
fn pair<T>(
    given: &Option<(String, String)>,
    each: fn(&str) -> Result<T, InputError>,
) -> Result<Option<[T; 2]>, InputError> {
    given
        .as_ref()
        .map(|(u, v)| Ok([each(u)?, each(v)?]))
        .transpose()
}

fn ends(name: &str) -> Result<Ends, InputError> {
    Ends::from_name(name).ok_or_else(|| {
        InputError::field(
            "ends",
            format!("must be \"control\", \"repeat\" or \"closed\", got \"{name}\""),
        )
    })
}

fn condition(name: &str) -> Result<EndCondition, InputError> {
    match name {
        "natural" => Ok(EndCondition::Natural),
        "not-a-knot" => Ok(EndCondition::NotAKnot),
        "periodic" => Ok(EndCondition::Periodic),
        _ => Err(InputError::field(
            "conditions",
            format!("each must be \"natural\", \"not-a-knot\" or \"periodic\", got \"{name}\""),
        )),
    }
}

/// Surface s's sampling.
fn sampling_of(arg: &SurfaceSamplingArg<'_>, s: usize) -> Result<SurfaceSampling, InputError> {
    Ok(match arg {
        SurfaceSamplingArg::PerSegment((ku, kv)) => SurfaceSampling::PerSegment([*ku, *kv]),
        SurfaceSamplingArg::Tolerance(tol) => SurfaceSampling::Tolerance(*tol),
        SurfaceSamplingArg::At(at) => {
            let rows = at[s].as_array();
            match rows.ncols() {
                2 => SurfaceSampling::At(rows.outer_iter().map(|r| [r[0], r[1]]).collect()),
                3 => {
                    let mut list = Vec::with_capacity(rows.nrows());
                    for r in rows.outer_iter() {
                        if !(r[0] >= 0.0 && r[0].fract() == 0.0 && r[0] < u32::MAX as f64) {
                            return Err(InputError::field(
                                "sampling",
                                format!("\"at\" triples start with a patch index, got {}", r[0]),
                            ));
                        }
                        list.push((r[0] as usize, [r[1], r[2]]));
                    }
                    SurfaceSampling::AtPatches(list)
                }
                n => {
                    return Err(InputError::field(
                        "sampling",
                        format!(
                            "\"at\" takes pairs [u, v] (triples [p, u, v] on a patch list), got {n} values each"
                        ),
                    ));
                }
            }
        }
    })
}

/// Every surface of a batch of one kind fitted; errors name the surface.
pub(crate) fn fitted(
    nets: &[PyReadonlyArray3<'_, f64>],
    kind: &str,
    fields: &SurfaceFields<'_>,
) -> PyResult<Vec<PatchTable>> {
    let mut tables = Vec::with_capacity(nets.len());
    for (s, net) in nets.iter().enumerate() {
        let place = |e: InputError| value_error(e.in_surface(s));
        let shape = net.shape();
        let coords = net
            .as_slice()
            .map_err(|e| InputError::field("points", e.to_string()))
            .map_err(place)?
            .to_vec();
        let net = Net::new(shape[2], shape[0], shape[1], coords).map_err(place)?;
        let surface = Surface::new(kind_of(kind, fields, s).map_err(place)?, net).map_err(place)?;
        tables.push(surface.fit());
    }
    Ok(tables)
}

/// Fits and plans every surface into one job; errors name the surface.
fn planned(
    nets: &[PyReadonlyArray3<'_, f64>],
    kind: &str,
    fields: &SurfaceFields<'_>,
    sampling: &SurfaceSamplingArg<'_>,
    (derivatives, normals): (Derivatives, bool),
    value_bytes: u128,
) -> PyResult<SurfaceJob> {
    let mut fitted_planned = Vec::with_capacity(nets.len());
    for (s, table) in fitted(nets, kind, fields)?.into_iter().enumerate() {
        let place = |e: InputError| value_error(e.in_surface(s));
        fitted_planned.push((table, sampling_of(sampling, s).map_err(place)?));
    }
    let fitted = fitted_planned;
    // The counts the samplings give, refused before the plans are made where the plans (40
    // bytes a vertex) and the arrays of the whole batch would not fit in memory.
    let mut bytes: u128 = 0;
    for (table, sampling) in &fitted {
        if let Some(vertices) = SurfacePlan::vertex_count(table, sampling) {
            let per_vertex = 40 + 16 + 8 + 6 * table.dim() as u128 * value_bytes + 3 * value_bytes;
            bytes += u128::from(vertices) * per_vertex;
        }
    }
    if let Some(available) = available_memory()
        && bytes > available
    {
        return Err(PyMemoryError::new_err(format!(
            "tessellate_surfaces: the sampling gives meshes whose plans and arrays need {bytes} \
             bytes; the process has {available} bytes of memory available"
        )));
    }
    let mut job = SurfaceJob::new(derivatives, normals);
    job.push_many(fitted).map_err(value_error)?;
    Ok(job)
}

/// Fits, samples and evaluates a batch of surfaces of one kind (see
/// `splinegpu.Context.tessellate_surfaces`): a dict of the NPZ's arrays, the value planes, "uv"
/// and "triangles" those of `out` (an earlier result of the same shapes) where given.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
#[expect(
    clippy::too_many_arguments,
    reason = "the Python call's arguments, one each"
)]
pub(crate) fn tessellate_surfaces<'py>(
    py: Python<'py>,
    context: PyRef<'py, Context>,
    nets: Vec<PyReadonlyArray3<'py, f64>>,
    kind: &str,
    fields: SurfaceFields<'py>,
    sampling: SurfaceSamplingArg<'py>,
    derivatives: u64,
    normals: bool,
    out: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let derivatives = Derivatives::from_order(derivatives)
        .ok_or_else(|| value_error(format!("derivatives: must be 0, 1 or 2, got {derivatives}")))?;
    let value_bytes = if context.gpu.is_some() { 4 } else { 8 };
    let job = planned(
        &nets,
        kind,
        &fields,
        &sampling,
        (derivatives, normals),
        value_bytes,
    )?;
    let dims: Vec<usize> = job.surfaces().iter().map(|s| s.table().dim()).collect();
    let dim = dims.first().copied().unwrap_or(0);
    if let Some(s) = dims.iter().position(|&d| d != dim) {
        return Err(value_error(format!(
            "surface {s}: \"points\" has {} coordinates per point, surface 0 {dim}: one array \
             of points holds one dimension",
            dims[s]
        )));
    }
    let (n, m) = (job.vertex_count() as usize, job.triangle_count() as usize);
    let orders = derivatives.order();
    let planes = 1 + [0, 2, 5][orders];
    let per_vertex =
        16 + (planes * dim) as u128 * value_bytes + u128::from(normals) * 3 * value_bytes + 8;
    let bytes = n as u128 * per_vertex + m as u128 * 24;
    if let Some(available) = available_memory()
        && bytes > available
    {
        return Err(PyMemoryError::new_err(format!(
            "tessellate_surfaces: the sampling gives {n} vertices and {m} triangles, whose \
             arrays need {bytes} bytes; the process has {available} bytes of memory available"
        )));
    }
    let signed = |offsets: &[u64]| -> Vec<i64> { offsets.iter().map(|&o| o as i64).collect() };
    let (vertex_offsets, triangle_offsets) =
        (signed(job.vertex_offsets()), signed(job.triangle_offsets()));
    // (u, v), triangles (indexing the whole vertex array) and patches.
    let mut uv = Vec::with_capacity(2 * n);
    let mut tri = Vec::with_capacity(3 * m);
    let lists = job.has_patch_lists();
    let mut patch = Vec::with_capacity(if lists { n } else { 0 });
    for (s, surface) in job.surfaces().iter().enumerate() {
        let plan = surface.plan();
        for vertex in &plan.vertices {
            uv.extend_from_slice(&vertex.uv);
        }
        if lists {
            let list = surface.table().patch_indices().is_some();
            patch.extend(
                plan.vertices
                    .iter()
                    .map(|v| if list { i64::from(v.patch) } else { -1 }),
            );
        }
        for t in plan.triangles.iter().flatten() {
            tri.extend(t.iter().map(|&i| i64::from(i) + vertex_offsets[s]));
        }
    }
    let result = PyDict::new(py);
    let uv_array = array::<f64>(py, out.as_ref(), "uv", [n, 2])?;
    uv_array.readwrite().as_slice_mut()?.copy_from_slice(&uv);
    let tri_array = array::<i64>(py, out.as_ref(), "triangles", [m, 3])?;
    tri_array.readwrite().as_slice_mut()?.copy_from_slice(&tri);
    result.set_item("uv", uv_array)?;
    result.set_item("triangles", tri_array)?;
    result.set_item(
        "surface_offsets",
        PyArray1::from_vec(py, vertex_offsets.clone()),
    )?;
    result.set_item("triangle_offsets", PyArray1::from_vec(py, triangle_offsets))?;
    if lists {
        result.set_item("patch", PyArray1::from_vec(py, patch))?;
    }
    let names: Vec<&str> = ["points", "du", "dv", "duu", "duv", "dvv"][..planes]
        .iter()
        .copied()
        .chain(normals.then_some("normals"))
        .collect();
    let width = |name: &str| if name == "normals" { 3 } else { dim };
    match &context.gpu {
        None => {
            let arrays: Vec<Bound<'py, PyArray2<f64>>> = names
                .iter()
                .map(|name| array::<f64>(py, out.as_ref(), name, [n, width(name)]))
                .collect::<PyResult<_>>()?;
            let mut views: Vec<numpy::PyReadwriteArray2<'py, f64>> =
                arrays.iter().map(|a| a.readwrite()).collect();
            let mut slices: Vec<&mut [f64]> = views
                .iter_mut()
                .map(|v| v.as_slice_mut())
                .collect::<Result<_, _>>()?;
            py.detach(|| -> Result<(), InputError> {
                for s in 0..job.len() {
                    let (a, b) = (vertex_offsets[s] as usize, vertex_offsets[s + 1] as usize);
                    // The surface's rows of each plane, in the order of `names`.
                    let mut parts = slices.iter_mut().zip(&names).map(|(plane, name)| {
                        let w = width(name);
                        &mut plane[a * w..b * w]
                    });
                    let points = parts.next().expect("the positions' plane");
                    let mut pick = |asked: bool| if asked { parts.next() } else { None };
                    let planes = SurfacePlanes {
                        points,
                        du: pick(orders >= 1),
                        dv: pick(orders >= 1),
                        duu: pick(orders >= 2),
                        duv: pick(orders >= 2),
                        dvv: pick(orders >= 2),
                        normals: pick(normals),
                    };
                    job.evaluate_into(s, planes)?;
                }
                Ok(())
            })
            .map_err(runtime_error)?;
            let planes: Vec<(&[f64], usize)> = slices
                .iter()
                .zip(&names)
                .map(|(plane, name)| (&plane[..], width(name)))
                .collect();
            refuse_non_finite(&planes, &vertex_offsets)?;
            drop(slices);
            drop(views);
            for (name, array) in names.iter().zip(arrays) {
                result.set_item(*name, array)?;
            }
        }
        Some(gpu) => {
            let samples = py
                .detach(|| gpu.evaluate_surfaces(&job))
                .map_err(runtime_error)?;
            for (s, sample) in samples.iter().enumerate() {
                let mut planes = vec![(&sample.points[..], dim)];
                for plane in [
                    &sample.du,
                    &sample.dv,
                    &sample.duu,
                    &sample.duv,
                    &sample.dvv,
                ] {
                    planes.extend(plane.as_deref().map(|p| (p, dim)));
                }
                planes.extend(sample.normals.as_deref().map(|p| (p, 3)));
                if let Some(v) = first_non_finite(&planes) {
                    return Err(non_finite(s, v));
                }
            }
            for name in &names {
                let target = array::<f32>(py, out.as_ref(), name, [n, width(name)])?;
                {
                    let mut view = target.readwrite();
                    let mut rest = view.as_slice_mut()?;
                    for sample in &samples {
                        let plane = match *name {
                            "points" => Some(&sample.points),
                            "du" => sample.du.as_ref(),
                            "dv" => sample.dv.as_ref(),
                            "duu" => sample.duu.as_ref(),
                            "duv" => sample.duv.as_ref(),
                            "dvv" => sample.dvv.as_ref(),
                            _ => sample.normals.as_ref(),
                        };
                        let plane = plane.map_or(&[][..], Vec::as_slice);
                        let (part, tail) = rest.split_at_mut(plane.len());
                        part.copy_from_slice(plane);
                        rest = tail;
                    }
                }
                result.set_item(*name, target)?;
            }
        }
    }
    Ok(result)
}

/// The first vertex of `planes` (values, values a vertex) with a value that is not finite.
fn first_non_finite<F: SampleFloat>(planes: &[(&[F], usize)]) -> Option<usize> {
    planes
        .iter()
        .filter_map(|(plane, width)| plane.iter().position(|v| !v.finite()).map(|i| i / width))
        .min()
}

fn non_finite(surface: usize, vertex: usize) -> PyErr {
    value_error(format!(
        "surface {surface}: vertex {vertex} is not finite (the surface overflows the result's \
         number type)"
    ))
}

/// Refuses a result with a value that is not finite (a surface whose values overflow), naming
/// the surface (by `vertex_offsets`) and its vertex, as the command line does.
fn refuse_non_finite<F: SampleFloat>(
    planes: &[(&[F], usize)],
    vertex_offsets: &[i64],
) -> PyResult<()> {
    let Some(v) = first_non_finite(planes) else {
        return Ok(());
    };
    let s = vertex_offsets.partition_point(|&o| o as usize <= v) - 1;
    Err(non_finite(s, v - vertex_offsets[s] as usize))
}
