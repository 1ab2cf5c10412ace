//! Query answers as CSV, JSON and NPZ (contract: "Queries", Output): one row, object or array
//! entry per answer, in the queries' order (intersections as the library sorts them); every number the shortest text that reads back as
//! the same f64.

use std::io::{self, Write};

use splinegpu::query::{
    ClosestPoints, Intersection, IntersectionColumns, RayHit, RayHitColumns, SurfacePoint,
    SurfacePointColumns,
};

use crate::npz::{Dtype, NpzWriter};
use crate::surface_output::Number;

/// The formats a query's answers are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryFormat {
    /// `query,curve,t,x0..,distance`; `i,j,t_i,t_j,x0,x1,tangent,overlap`.
    Csv,
    /// `{"closest": [{"curve", "t", "point", "distance"}, ...]}`;
    /// `{"intersections": [{"i", "j", "t_i", "t_j", "point", "tangent", "overlap"}, ...]}`.
    Json,
    /// Arrays by the JSON keys: "curve" (int64), "t", "point" (Q, D), "distance"; "i", "j"
    /// (int64), "t_i", "t_j", "point" (N, 2), "tangent", "overlap" (bool).
    Npz,
}

/// Intersections written as `format` to `out`, in the order given.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_intersections(
    found: &[Intersection],
    format: QueryFormat,
    out: &mut dyn Write,
) -> io::Result<()> {
    let mut text = zmij::Buffer::new();
    let flag = |b: bool| u8::from(b);
    match format {
        QueryFormat::Csv => {
            writeln!(out, "i,j,t_i,t_j,x0,x1,tangent,overlap")?;
            for x in found {
                write!(out, "{},{},{}", x.i, x.j, text.format(x.t_i))?;
                write!(out, ",{}", text.format(x.t_j))?;
                write!(out, ",{}", text.format(x.point[0]))?;
                write!(out, ",{}", text.format(x.point[1]))?;
                writeln!(out, ",{},{}", flag(x.tangent), flag(x.overlap))?;
            }
        }
        QueryFormat::Json => {
            write!(out, "{{\"intersections\": [")?;
            for (k, x) in found.iter().enumerate() {
                let sep = if k == 0 { "" } else { ", " };
                write!(
                    out,
                    "{sep}{{\"i\": {}, \"j\": {}, \"t_i\": {}",
                    x.i,
                    x.j,
                    text.format(x.t_i)
                )?;
                write!(out, ", \"t_j\": {}, \"point\": [", text.format(x.t_j))?;
                crate::output::write_json_numbers(&x.point, true, &mut &mut *out)?;
                write!(
                    out,
                    "], \"tangent\": {}, \"overlap\": {}}}",
                    x.tangent, x.overlap
                )?;
            }
            writeln!(out, "]}}")?;
        }
        QueryFormat::Npz => {
            let n = found.len() as u64;
            let c = IntersectionColumns::new(found);
            let arrays: [(&str, Dtype, &[u64], &[u8]); 7] = [
                ("i", Dtype::I64, &[n], bytemuck::cast_slice(&c.i)),
                ("j", Dtype::I64, &[n], bytemuck::cast_slice(&c.j)),
                ("t_i", Dtype::F64, &[n], bytemuck::cast_slice(&c.t_i)),
                ("t_j", Dtype::F64, &[n], bytemuck::cast_slice(&c.t_j)),
                ("point", Dtype::F64, &[n, 2], bytemuck::cast_slice(&c.point)),
                (
                    "tangent",
                    Dtype::Bool,
                    &[n],
                    bytemuck::cast_slice(&c.tangent),
                ),
                (
                    "overlap",
                    Dtype::Bool,
                    &[n],
                    bytemuck::cast_slice(&c.overlap),
                ),
            ];
            write_npz(out, &arrays)?;
        }
    }
    Ok(())
}

/// Closest points on surfaces (D coordinates each) written as `format` to `out`: "patch" only
/// for patch lists in JSON, empty in CSV and -1 in NPZ on nets; points and distances as `F`
/// (f32 from the GPU backend), parameters in f64.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_surface_closest<F: Number>(
    answers: &[SurfacePoint],
    dim: usize,
    format: QueryFormat,
    out: &mut dyn Write,
) -> io::Result<()> {
    let mut text = zmij::Buffer::new();
    match format {
        QueryFormat::Csv => {
            write!(out, "query,surface,patch,u,v")?;
            for k in 0..dim {
                write!(out, ",x{k}")?;
            }
            writeln!(out, ",distance")?;
            for (i, a) in answers.iter().enumerate() {
                let patch = a.patch.map(|p| p.to_string()).unwrap_or_default();
                write!(out, "{i},{},{patch},{}", a.surface, text.format(a.u))?;
                write!(out, ",{}", text.format(a.v))?;
                for &x in &a.point {
                    write!(out, ",{}", text.format(F::from_f64(x)))?;
                }
                writeln!(out, ",{}", text.format(F::from_f64(a.distance)))?;
            }
        }
        QueryFormat::Json => {
            write!(out, "{{\"closest\": [")?;
            for (i, a) in answers.iter().enumerate() {
                let sep = if i == 0 { "" } else { ", " };
                write!(out, "{sep}{{\"surface\": {}", a.surface)?;
                if let Some(p) = a.patch {
                    write!(out, ", \"patch\": {p}")?;
                }
                write!(out, ", \"u\": {}", text.format(a.u))?;
                write!(out, ", \"v\": {}, \"point\": [", text.format(a.v))?;
                write_json_as::<F>(&a.point, out)?;
                write!(
                    out,
                    "], \"distance\": {}}}",
                    text.format(F::from_f64(a.distance))
                )?;
            }
            writeln!(out, "]}}")?;
        }
        QueryFormat::Npz => {
            let q = answers.len() as u64;
            let c = SurfacePointColumns::new(answers);
            let (point, distance) = (as_type::<F>(&c.point), as_type::<F>(&c.distance));
            write_npz(
                out,
                &[
                    (
                        "surface",
                        Dtype::I64,
                        &[q],
                        bytemuck::cast_slice(&c.surface),
                    ),
                    ("patch", Dtype::I64, &[q], bytemuck::cast_slice(&c.patch)),
                    ("u", Dtype::F64, &[q], bytemuck::cast_slice(&c.u)),
                    ("v", Dtype::F64, &[q], bytemuck::cast_slice(&c.v)),
                    (
                        "point",
                        Dtype::of::<F>(),
                        &[q, dim as u64],
                        bytemuck::cast_slice(&point),
                    ),
                    (
                        "distance",
                        Dtype::of::<F>(),
                        &[q],
                        bytemuck::cast_slice(&distance),
                    ),
                ],
            )?;
        }
    }
    Ok(())
}

/// Rays' first hits written as `format` to `out`: JSON null, a CSV row with hit 0 and the rest
/// empty, or NPZ "hit" false with NaN and -1, where a ray meets nothing; points and normals as
/// `F` (f32 from the GPU backend), parameters (u, v, s) in f64.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_rays<F: Number>(
    hits: &[Option<RayHit>],
    format: QueryFormat,
    out: &mut dyn Write,
) -> io::Result<()> {
    let mut text = zmij::Buffer::new();
    match format {
        QueryFormat::Csv => {
            writeln!(out, "query,hit,surface,patch,u,v,s,x,y,z,nx,ny,nz")?;
            for (i, hit) in hits.iter().enumerate() {
                let Some(h) = hit else {
                    writeln!(out, "{i},0,,,,,,,,,,,")?;
                    continue;
                };
                let patch = h.patch.map(|p| p.to_string()).unwrap_or_default();
                write!(out, "{i},1,{},{patch}", h.surface)?;
                for x in [h.u, h.v, h.s] {
                    write!(out, ",{}", text.format(x))?;
                }
                for &x in h.point.iter().chain(&h.normal) {
                    write!(out, ",{}", text.format(F::from_f64(x)))?;
                }
                writeln!(out)?;
            }
        }
        QueryFormat::Json => {
            write!(out, "{{\"rays\": [")?;
            for (i, hit) in hits.iter().enumerate() {
                let sep = if i == 0 { "" } else { ", " };
                let Some(h) = hit else {
                    write!(out, "{sep}null")?;
                    continue;
                };
                write!(out, "{sep}{{\"surface\": {}", h.surface)?;
                if let Some(p) = h.patch {
                    write!(out, ", \"patch\": {p}")?;
                }
                write!(out, ", \"u\": {}", text.format(h.u))?;
                write!(out, ", \"v\": {}", text.format(h.v))?;
                write!(out, ", \"s\": {}, \"point\": [", text.format(h.s))?;
                write_json_as::<F>(&h.point, out)?;
                write!(out, "], \"normal\": [")?;
                write_json_as::<F>(&h.normal, out)?;
                write!(out, "]}}")?;
            }
            writeln!(out, "]}}")?;
        }
        QueryFormat::Npz => {
            let q = hits.len() as u64;
            let c = RayHitColumns::new(hits);
            let (point, normal) = (as_type::<F>(&c.point), as_type::<F>(&c.normal));
            write_npz(
                out,
                &[
                    ("hit", Dtype::Bool, &[q], bytemuck::cast_slice(&c.hit)),
                    (
                        "surface",
                        Dtype::I64,
                        &[q],
                        bytemuck::cast_slice(&c.surface),
                    ),
                    ("patch", Dtype::I64, &[q], bytemuck::cast_slice(&c.patch)),
                    ("u", Dtype::F64, &[q], bytemuck::cast_slice(&c.u)),
                    ("v", Dtype::F64, &[q], bytemuck::cast_slice(&c.v)),
                    ("s", Dtype::F64, &[q], bytemuck::cast_slice(&c.s)),
                    (
                        "point",
                        Dtype::of::<F>(),
                        &[q, 3],
                        bytemuck::cast_slice(&point),
                    ),
                    (
                        "normal",
                        Dtype::of::<F>(),
                        &[q, 3],
                        bytemuck::cast_slice(&normal),
                    ),
                ],
            )?;
        }
    }
    Ok(())
}

/// `values` rounded to `F`.
fn as_type<F: Number>(values: &[f64]) -> Vec<F> {
    values.iter().map(|&x| F::from_f64(x)).collect()
}

/// `values` rounded to `F`, as comma-separated JSON numbers (each the shortest text of its
/// `F`).
fn write_json_as<F: Number>(values: &[f64], out: &mut dyn Write) -> io::Result<()> {
    let mut text = zmij::Buffer::new();
    for (k, &x) in values.iter().enumerate() {
        let sep = if k == 0 { "" } else { ", " };
        write!(out, "{sep}{}", text.format(F::from_f64(x)))?;
    }
    Ok(())
}

/// The arrays (name, type, shape, bytes) as an NPZ archive on `out`.
fn write_npz(out: &mut dyn Write, arrays: &[(&str, Dtype, &[u64], &[u8])]) -> io::Result<()> {
    let mut npz = NpzWriter::new(out);
    for &(name, dtype, shape, bytes) in arrays {
        npz.begin(name, dtype, shape)?;
        npz.write(bytes)?;
        npz.end()?;
    }
    npz.finish()?;
    Ok(())
}

/// Closest points on curves written as `format` to `out`: points and distances as their type
/// (f64 from the CPU, f32 from the GPU), parameters in f64.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_closest<F: Number>(
    answers: &ClosestPoints<F>,
    format: QueryFormat,
    out: &mut dyn Write,
) -> io::Result<()> {
    let dim = answers.dim;
    let mut text = zmij::Buffer::new();
    match format {
        QueryFormat::Csv => {
            write!(out, "query,curve,t")?;
            for k in 0..dim {
                write!(out, ",x{k}")?;
            }
            writeln!(out, ",distance")?;
            for i in 0..answers.len() {
                write!(
                    out,
                    "{i},{},{}",
                    answers.curve[i],
                    text.format(answers.t[i])
                )?;
                for &x in &answers.points[i * dim..][..dim] {
                    write!(out, ",{}", text.format(x))?;
                }
                writeln!(out, ",{}", text.format(answers.distance[i]))?;
            }
        }
        QueryFormat::Json => {
            write!(out, "{{\"closest\": [")?;
            for i in 0..answers.len() {
                let sep = if i == 0 { "" } else { ", " };
                write!(
                    out,
                    "{sep}{{\"curve\": {}, \"t\": {}, \"point\": [",
                    answers.curve[i],
                    text.format(answers.t[i])
                )?;
                let point = &answers.points[i * dim..][..dim];
                let values: Vec<f64> = point.iter().map(|&x| x.into()).collect();
                write_json_as::<F>(&values, out)?;
                write!(
                    out,
                    "], \"distance\": {}}}",
                    text.format(answers.distance[i])
                )?;
            }
            writeln!(out, "]}}")?;
        }
        QueryFormat::Npz => {
            let q = answers.len() as u64;
            let curves: Vec<i64> = answers.curve.iter().map(|&c| c as i64).collect();
            let arrays: [(&str, Dtype, &[u64], &[u8]); 4] = [
                ("curve", Dtype::I64, &[q], bytemuck::cast_slice(&curves)),
                ("t", Dtype::F64, &[q], bytemuck::cast_slice(&answers.t)),
                (
                    "point",
                    Dtype::of::<F>(),
                    &[q, dim as u64],
                    bytemuck::cast_slice(&answers.points),
                ),
                (
                    "distance",
                    Dtype::of::<F>(),
                    &[q],
                    bytemuck::cast_slice(&answers.distance),
                ),
            ];
            write_npz(out, &arrays)?;
        }
    }
    Ok(())
}
