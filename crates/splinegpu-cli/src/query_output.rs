//! Query answers as CSV, JSON and NPZ (contract: "Queries", Output): one row, object or array
//! entry per answer, in the queries' order (intersections as the library sorts them); every number the shortest text that reads back as
//! the same f64.

use std::io::{self, Write};

use splinegpu::query::{ClosestPoints, Intersection, RayHit, SurfacePoint};

use crate::npz::{Dtype, NpzWriter};

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
            let ints = |f: fn(&Intersection) -> usize| -> Vec<i64> {
                found.iter().map(|x| f(x) as i64).collect()
            };
            let floats =
                |f: fn(&Intersection) -> f64| -> Vec<f64> { found.iter().map(f).collect() };
            let flags = |f: fn(&Intersection) -> bool| -> Vec<u8> {
                found.iter().map(|x| u8::from(f(x))).collect()
            };
            let (i, j) = (ints(|x| x.i), ints(|x| x.j));
            let (t_i, t_j) = (floats(|x| x.t_i), floats(|x| x.t_j));
            let points: Vec<f64> = found.iter().flat_map(|x| x.point).collect();
            let (tangent, overlap) = (flags(|x| x.tangent), flags(|x| x.overlap));
            let arrays: [(&str, Dtype, &[u64], &[u8]); 7] = [
                ("i", Dtype::I64, &[n], bytemuck::cast_slice(&i)),
                ("j", Dtype::I64, &[n], bytemuck::cast_slice(&j)),
                ("t_i", Dtype::F64, &[n], bytemuck::cast_slice(&t_i)),
                ("t_j", Dtype::F64, &[n], bytemuck::cast_slice(&t_j)),
                ("point", Dtype::F64, &[n, 2], bytemuck::cast_slice(&points)),
                ("tangent", Dtype::Bool, &[n], &tangent),
                ("overlap", Dtype::Bool, &[n], &overlap),
            ];
            write_npz(out, &arrays)?;
        }
    }
    Ok(())
}

/// Closest points on surfaces (D coordinates each) written as `format` to `out`: "patch" only
/// for patch lists in JSON, empty in CSV and -1 in NPZ on nets.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_surface_closest(
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
                    write!(out, ",{}", text.format(x))?;
                }
                writeln!(out, ",{}", text.format(a.distance))?;
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
                crate::output::write_json_numbers(&a.point, true, &mut &mut *out)?;
                write!(out, "], \"distance\": {}}}", text.format(a.distance))?;
            }
            writeln!(out, "]}}")?;
        }
        QueryFormat::Npz => {
            let q = answers.len() as u64;
            let surface: Vec<i64> = answers.iter().map(|a| a.surface as i64).collect();
            let patch: Vec<i64> = answers
                .iter()
                .map(|a| a.patch.map_or(-1, |p| p as i64))
                .collect();
            let u: Vec<f64> = answers.iter().map(|a| a.u).collect();
            let v: Vec<f64> = answers.iter().map(|a| a.v).collect();
            let points: Vec<f64> = answers
                .iter()
                .flat_map(|a| a.point.iter().copied())
                .collect();
            let distance: Vec<f64> = answers.iter().map(|a| a.distance).collect();
            write_npz(
                out,
                &[
                    ("surface", Dtype::I64, &[q], bytemuck::cast_slice(&surface)),
                    ("patch", Dtype::I64, &[q], bytemuck::cast_slice(&patch)),
                    ("u", Dtype::F64, &[q], bytemuck::cast_slice(&u)),
                    ("v", Dtype::F64, &[q], bytemuck::cast_slice(&v)),
                    (
                        "point",
                        Dtype::F64,
                        &[q, dim as u64],
                        bytemuck::cast_slice(&points),
                    ),
                    (
                        "distance",
                        Dtype::F64,
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
/// empty, or NPZ "hit" false with NaN and -1, where a ray meets nothing.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_rays(
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
                for x in [h.u, h.v, h.s].iter().chain(&h.point).chain(&h.normal) {
                    write!(out, ",{}", text.format(*x))?;
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
                crate::output::write_json_numbers(&h.point, true, &mut &mut *out)?;
                write!(out, "], \"normal\": [")?;
                crate::output::write_json_numbers(&h.normal, true, &mut &mut *out)?;
                write!(out, "]}}")?;
            }
            writeln!(out, "]}}")?;
        }
        QueryFormat::Npz => {
            let q = hits.len() as u64;
            let nan = f64::NAN;
            let hit: Vec<u8> = hits.iter().map(|h| u8::from(h.is_some())).collect();
            let surface: Vec<i64> = hits
                .iter()
                .map(|h| h.as_ref().map_or(-1, |h| h.surface as i64))
                .collect();
            let patch: Vec<i64> = hits
                .iter()
                .map(|h| h.as_ref().and_then(|h| h.patch).map_or(-1, |p| p as i64))
                .collect();
            let scalar = |f: fn(&RayHit) -> f64| -> Vec<f64> {
                hits.iter().map(|h| h.as_ref().map_or(nan, f)).collect()
            };
            let (u, v, s) = (scalar(|h| h.u), scalar(|h| h.v), scalar(|h| h.s));
            let point: Vec<f64> = hits
                .iter()
                .flat_map(|h| h.as_ref().map_or([nan; 3], |h| h.point))
                .collect();
            let normal: Vec<f64> = hits
                .iter()
                .flat_map(|h| h.as_ref().map_or([nan; 3], |h| h.normal))
                .collect();
            write_npz(
                out,
                &[
                    ("hit", Dtype::Bool, &[q], &hit),
                    ("surface", Dtype::I64, &[q], bytemuck::cast_slice(&surface)),
                    ("patch", Dtype::I64, &[q], bytemuck::cast_slice(&patch)),
                    ("u", Dtype::F64, &[q], bytemuck::cast_slice(&u)),
                    ("v", Dtype::F64, &[q], bytemuck::cast_slice(&v)),
                    ("s", Dtype::F64, &[q], bytemuck::cast_slice(&s)),
                    ("point", Dtype::F64, &[q, 3], bytemuck::cast_slice(&point)),
                    ("normal", Dtype::F64, &[q, 3], bytemuck::cast_slice(&normal)),
                ],
            )?;
        }
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

/// Closest points on curves written as `format` to `out`.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_closest(
    answers: &ClosestPoints,
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
                crate::output::write_json_numbers(
                    &answers.points[i * dim..][..dim],
                    true,
                    &mut &mut *out,
                )?;
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
                    Dtype::F64,
                    &[q, dim as u64],
                    bytemuck::cast_slice(&answers.points),
                ),
                (
                    "distance",
                    Dtype::F64,
                    &[q],
                    bytemuck::cast_slice(&answers.distance),
                ),
            ];
            write_npz(out, &arrays)?;
        }
    }
    Ok(())
}
