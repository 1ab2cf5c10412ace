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

use crate::args::{PerCurve, Stack2, array, runtime_error, value_error};
use crate::context::{CurveFields, KindSource, SamplingArg, on_threads};

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
                sides: self.sides.unwrap_or(Tube::default().sides),
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

/// Fits a batch of curves of one kind and makes their meshes on the CPU in f64 (see
/// `splinegpu.Context.tubes`; the GPU kernel is not built yet, and the Python side refuses a
/// context opened as "gpu"): a dict of the NPZ's arrays, filled into `out`'s (an earlier
/// result of the same shapes) where given.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
pub(crate) fn geometry_meshes<'py>(
    py: Python<'py>,
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
                let curve = Curve::new(kinds.kind(c)?, Points::new(dim, coords.to_vec())?)
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
    write(py, &job, &geometry.shape, out.as_ref())
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
    let t = match out.map(|o| o.get_item("t")).transpose()?.flatten() {
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
        None => PyArray1::<f64>::zeros(py, v, false),
    };
    let triangles = array::<i64>(py, out, "triangles", [m, 3])?;
    let normals = if flat {
        None
    } else {
        Some(array::<f64>(py, out, "normals", [v, 3])?)
    };
    let mut local = vec![[0u32; 3]; m];
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
                let (mut xyz, mut up) = (vec![0.0; 3 * v], vec![0.0; 3 * v]);
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
    let offsets = job.vertex_offsets();
    {
        let mut view = triangles.readwrite();
        let whole = view.as_slice_mut()?;
        let mut next = 0;
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
    refuse_non_finite(job, points.readonly().as_slice()?, dim)?;
    if let Some(normals) = &normals {
        refuse_non_finite(job, normals.readonly().as_slice()?, 3)?;
    }
    let signed = |o: &[u64]| -> Vec<i64> { o.iter().map(|&x| x as i64).collect() };
    let result = PyDict::new(py);
    result.set_item("points", points)?;
    result.set_item("t", t)?;
    result.set_item("normals", normals)?;
    result.set_item("triangles", triangles)?;
    result.set_item("curve_offsets", PyArray1::from_vec(py, signed(offsets)))?;
    result.set_item(
        "triangle_offsets",
        PyArray1::from_vec(py, signed(job.triangle_offsets())),
    )?;
    Ok(result)
}

/// A mesh whose values overflow f64 (a radius near the largest float) is refused, naming the
/// curve and the vertex, rather than returned with NaN.
fn refuse_non_finite(job: &GeometryJob, values: &[f64], width: usize) -> PyResult<()> {
    let Some(i) = values.iter().position(|x| !x.is_finite()) else {
        return Ok(());
    };
    let vertex = (i / width) as u64;
    let offsets = job.vertex_offsets();
    let c = offsets.partition_point(|&o| o <= vertex) - 1;
    Err(value_error(format!(
        "curve {c}: mesh vertex {} is not finite (the mesh overflows float64)",
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
