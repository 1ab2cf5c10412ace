//! Strokes, tubes and ribbons from NumPy (`Context.strokes`, `Context.tubes`,
//! `Context.ribbons`): curves of one kind and the contract's geometry fields into the crate's
//! [`GeometryJob`], planned on every thread and made on the CPU in f64, into the arrays the
//! command line's NPZ holds ("points" (N, D), "t", "normals" for tubes and ribbons,
//! "triangles" indexing the whole vertex array, "curve_offsets", "triangle_offsets").

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use splinegpu::geometry::{Cap, Dash, Geometry, GeometryJob, Join, MeshPlanes, Ribbon, Stroke};
use splinegpu::geometry::{Tube, Width};
use splinegpu::{Curve, InputError, Points};

use crate::args::{PerCurve, Stack2, array, filled, new_zeros, runtime_error, value_error};
use crate::context::{Context, CurveFields, KindSource, SamplingArg, on_threads};

/// The geometry's fields as the Python side normalises them: the shape's name, its width or
/// radius (a number for every curve, or one array per curve), and the shape's own fields.
#[derive(FromPyObject)]
pub(crate) struct GeometryFields<'py> {
    #[pyo3(item)]
    shape: String,
    #[pyo3(item)]
    width: Option<f64>,
    #[pyo3(item)]
    width_each: Option<PerCurve<'py>>,
    #[pyo3(item)]
    cap: Option<String>,
    #[pyo3(item)]
    join: Option<String>,
    #[pyo3(item)]
    miter_limit: Option<f64>,
    #[pyo3(item)]
    sides: Option<u32>,
    #[pyo3(item)]
    up: Option<[f64; 3]>,
    #[pyo3(item)]
    caps: Option<bool>,
    #[pyo3(item)]
    dash: Option<Vec<f64>>,
    #[pyo3(item)]
    dash_offset: Option<f64>,
}

impl GeometryFields<'_> {
    /// Curve c's geometry, with `width` its width or radius.
    fn geometry(&self, width: Width) -> PyResult<Geometry> {
        let dash = self.dash.as_ref().map(|lengths| Dash {
            lengths: lengths.clone(),
            offset: self.dash_offset.unwrap_or(0.0),
        });
        Ok(match self.shape.as_str() {
            "stroke" => {
                let default = Stroke::default();
                Geometry::Stroke(Stroke {
                    width,
                    cap: match self.cap.as_deref() {
                        None | Some("butt") => Cap::Butt,
                        Some("round") => Cap::Round,
                        Some("square") => Cap::Square,
                        Some(other) => {
                            return Err(value_error(format!(
                                "cap: must be \"butt\", \"round\" or \"square\", got \"{other}\""
                            )));
                        }
                    },
                    join: match self.join.as_deref() {
                        None | Some("miter") => Join::Miter,
                        Some("round") => Join::Round,
                        Some("bevel") => Join::Bevel,
                        Some(other) => {
                            return Err(value_error(format!(
                                "join: must be \"miter\", \"round\" or \"bevel\", got \"{other}\""
                            )));
                        }
                    },
                    miter_limit: self.miter_limit.unwrap_or(default.miter_limit),
                    sides: self.sides.unwrap_or(default.sides),
                    dash,
                })
            }
            "tube" => Geometry::Tube(Tube {
                radius: width,
                sides: self.sides,
                up: self.up,
                caps: self.caps.unwrap_or(false),
                dash,
            }),
            _ => Geometry::Ribbon(Ribbon {
                width,
                up: self.up,
                dash,
            }),
        })
    }
}

/// Fits a batch of curves of one kind and makes their meshes (see `splinegpu.Context.tubes`)
/// on the context's backend: f64 on the CPU, f32 points and normals from the GPU (strokes made
/// on the host there, rounded once). A dict of the NPZ's arrays, filled
/// into `out`'s (an earlier result of the same shapes) where given.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
#[expect(
    clippy::too_many_arguments,
    reason = "the Python call's arguments, one each"
)]
pub(crate) fn geometry_meshes<'py>(
    py: Python<'py>,
    context: PyRef<'py, Context>,
    points: Stack2<'py>,
    kind: &str,
    fields: CurveFields<'py>,
    sampling: SamplingArg<'py>,
    geometry: GeometryFields<'py>,
    out: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let points = points.items()?;
    let n = points.len();
    let kinds = KindSource::new(kind, &fields)?;
    let samplings = sampling.per_curve(n)?;
    let widths: Vec<Option<&[f64]>> = match &geometry.width_each {
        Some(each) => each.items()?,
        None => vec![None; n],
    };
    if widths.len() != n {
        return Err(value_error(format!(
            "{}: {} arrays for {n} curves",
            width_name(&geometry.shape),
            widths.len()
        )));
    }
    let shapes: Vec<Geometry> = widths
        .iter()
        .map(|w| {
            let width = match (w, geometry.width) {
                (Some(each), _) => Width::PerPoint(each.to_vec()),
                (None, Some(all)) => Width::Constant(all),
                (None, None) => {
                    return Err(value_error(format!(
                        "{}: is missing",
                        width_name(&geometry.shape)
                    )));
                }
            };
            geometry.geometry(width)
        })
        .collect::<PyResult<_>>()?;
    let job = py
        .detach(|| -> Result<GeometryJob, InputError> {
            let curves = on_threads(n, |c| {
                let (dim, coords) = points[c];
                let curve = Points::new(dim, coords.to_vec())
                    .and_then(|points| Curve::new(kinds.kind(c)?, points))
                    .map_err(|e| e.in_curve(c))?;
                Ok((curve, shapes[c].clone(), samplings[c].clone()))
            })?;
            let mut job = GeometryJob::new();
            job.push_many(&curves)?;
            Ok(job)
        })
        .map_err(|e| {
            // The job's own refusal of meshes larger than the process's memory.
            if e.message.contains("of memory available") {
                PyMemoryError::new_err(e.to_string())
            } else {
                value_error(e)
            }
        })?;
    match &context.gpu {
        None => write(py, &job, &geometry.shape, out.as_ref()),
        Some(gpu) => {
            let meshes = py
                .detach(|| gpu.evaluate_geometry(&job))
                .map_err(runtime_error)?;
            write_f32(py, &job, &meshes, &geometry.shape, out.as_ref())
        }
    }
}

fn width_name(shape: &str) -> &'static str {
    if shape == "tube" { "radius" } else { "width" }
}

/// The job's meshes as the NPZ's arrays: positions and normals made straight into NumPy's
/// arrays for tubes and ribbons (a stroke's points through a buffer, keeping x and y), the
/// triangles' local indices moved to index the whole vertex array.
fn write<'py>(
    py: Python<'py>,
    job: &GeometryJob,
    shape: &str,
    out: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (v, m) = (job.vertex_count() as usize, job.triangle_count() as usize);
    let flat = shape == "stroke";
    let dim = if flat { 2 } else { 3 };
    let points = array::<f64>(py, out, "points", [v, dim])?;
    let t = t_array(py, out, v)?;
    let normals = if flat {
        None
    } else {
        Some(array::<f64>(py, out, "normals", [v, 3])?)
    };
    let mut local = filled(m, "triangles")?;
    {
        let mut points_view = points.readwrite();
        let mut t_view = t.readwrite();
        let t_slice = t_view.as_slice_mut()?;
        match &normals {
            Some(normals) => {
                let mut normals_view = normals.readwrite();
                let planes = MeshPlanes {
                    points: points_view.as_slice_mut()?,
                    normals: normals_view.as_slice_mut()?,
                    t: t_slice,
                    triangles: &mut local,
                };
                py.detach(|| job.evaluate_into(planes))
                    .map_err(runtime_error)?;
            }
            None => {
                let (mut xyz, mut up) = (filled(3 * v, "points")?, filled(3 * v, "points")?);
                let planes = MeshPlanes {
                    points: &mut xyz,
                    normals: &mut up,
                    t: t_slice,
                    triangles: &mut local,
                };
                py.detach(|| job.evaluate_into(planes))
                    .map_err(runtime_error)?;
                for (xy, p) in points_view
                    .as_slice_mut()?
                    .chunks_exact_mut(2)
                    .zip(xyz.chunks_exact(3))
                {
                    xy.copy_from_slice(&p[..2]);
                }
            }
        }
    }
    let triangles = triangle_array(py, job, &local, out, m)?;
    refuse_non_finite(job, points.readonly().as_slice()?, dim)?;
    if let Some(normals) = &normals {
        refuse_non_finite(job, normals.readonly().as_slice()?, 3)?;
    }
    result(py, job, points, t, normals, triangles)
}

/// The result's dict: the arrays by the NPZ's names, with the job's offsets.
fn result<'py, F: numpy::Element>(
    py: Python<'py>,
    job: &GeometryJob,
    points: Bound<'py, numpy::PyArray2<F>>,
    t: Bound<'py, PyArray1<f64>>,
    normals: Option<Bound<'py, numpy::PyArray2<F>>>,
    triangles: Bound<'py, numpy::PyArray2<i64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let signed = |o: &[u64]| -> Vec<i64> { o.iter().map(|&x| x as i64).collect() };
    let result = PyDict::new(py);
    result.set_item("points", points)?;
    result.set_item("t", t)?;
    result.set_item("normals", normals)?;
    result.set_item("triangles", triangles)?;
    result.set_item(
        "curve_offsets",
        PyArray1::from_vec(py, signed(job.vertex_offsets())),
    )?;
    result.set_item(
        "triangle_offsets",
        PyArray1::from_vec(py, signed(job.triangle_offsets())),
    )?;
    Ok(result)
}

/// The "t" array: `out`'s (checked) or a new one.
fn t_array<'py>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyDict>>,
    v: usize,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    Ok(match out.map(|o| o.get_item("t")).transpose()?.flatten() {
        Some(given) => {
            let given = given
                .cast_into::<PyArray1<f64>>()
                .map_err(|_| value_error("out: \"t\" must be a 1-D float64 array"))?;
            if given.shape() != [v] {
                return Err(value_error(format!(
                    "out: \"t\" has shape {:?}, this result [{v}]",
                    given.shape()
                )));
            }
            if !given.is_c_contiguous() || given.try_readwrite().is_err() {
                return Err(value_error(
                    "out: \"t\" must be C-contiguous and writeable (and not borrowed elsewhere)",
                ));
            }
            given
        }
        None => new_zeros(py, &[v])?,
    })
}

/// The triangles indexing the whole vertex array: each mesh's local indices moved by its
/// first vertex, into `out`'s array (checked) or a new one.
fn triangle_array<'py>(
    py: Python<'py>,
    job: &GeometryJob,
    local: &[[u32; 3]],
    out: Option<&Bound<'py, PyDict>>,
    m: usize,
) -> PyResult<Bound<'py, numpy::PyArray2<i64>>> {
    let triangles = array::<i64>(py, out, "triangles", [m, 3])?;
    {
        let mut view = triangles.readwrite();
        let whole = view.as_slice_mut()?;
        let mut next = 0;
        let offsets = job.vertex_offsets();
        for (base, ends) in offsets.iter().zip(job.triangle_offsets().windows(2)) {
            let count = (ends[1] - ends[0]) as usize;
            for (target, tri) in whole[3 * next..3 * (next + count)]
                .chunks_exact_mut(3)
                .zip(&local[next..next + count])
            {
                for (to, &from) in target.iter_mut().zip(tri) {
                    *to = i64::from(from) + *base as i64;
                }
            }
            next += count;
        }
    }
    Ok(triangles)
}

/// The GPU's meshes as the NPZ's arrays: f32 points (a stroke's x and y) and normals, t and
/// the triangles as the CPU's.
fn write_f32<'py>(
    py: Python<'py>,
    job: &GeometryJob,
    meshes: &splinegpu::geometry::Meshes<f32>,
    shape: &str,
    out: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (v, m) = (meshes.t.len(), meshes.triangles.len());
    let flat = shape == "stroke";
    let dim = if flat { 2 } else { 3 };
    let points = array::<f32>(py, out, "points", [v, dim])?;
    {
        let mut view = points.readwrite();
        let target = view.as_slice_mut()?;
        if flat {
            for (xy, p) in target
                .chunks_exact_mut(2)
                .zip(meshes.points.chunks_exact(3))
            {
                xy.copy_from_slice(&p[..2]);
            }
        } else {
            target.copy_from_slice(&meshes.points);
        }
    }
    let t = t_array(py, out, v)?;
    t.readwrite().as_slice_mut()?.copy_from_slice(&meshes.t);
    let triangles = triangle_array(py, job, &meshes.triangles, out, m)?;
    refuse_non_finite(job, points.readonly().as_slice()?, dim)?;
    let normals = if flat {
        None
    } else {
        let normals = array::<f32>(py, out, "normals", [v, 3])?;
        normals
            .readwrite()
            .as_slice_mut()?
            .copy_from_slice(&meshes.normals);
        refuse_non_finite(job, &meshes.normals, 3)?;
        Some(normals)
    };
    result(py, job, points, t, normals, triangles)
}

/// A mesh whose values overflow their float type (a radius near the largest float) is
/// refused, naming the curve and the vertex, rather than returned with NaN.
fn refuse_non_finite<F: splinegpu::SampleFloat>(
    job: &GeometryJob,
    values: &[F],
    width: usize,
) -> PyResult<()> {
    let Some(i) = values.iter().position(|x| !x.finite()) else {
        return Ok(());
    };
    let vertex = (i / width) as u64;
    let offsets = job.vertex_offsets();
    let c = offsets.partition_point(|&o| o <= vertex) - 1;
    Err(value_error(format!(
        "curve {c}: mesh vertex {} is not finite (the mesh overflows the result's number type)",
        vertex - offsets[c]
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_width_is_named_as_the_shape_names_it() {
        assert_eq!(width_name("tube"), "radius");
        assert_eq!(width_name("stroke"), "width");
        assert_eq!(width_name("ribbon"), "width");
    }
}
