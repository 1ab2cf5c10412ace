//! Query answers as CSV, JSON and NPZ (contract: "Queries", Output): one row, object or array
//! entry per query, in the queries' order; every number the shortest text that reads back as
//! the same f64.

use std::io::{self, Write};

use splinegpu::query::ClosestPoints;

use crate::npz::{Dtype, NpzWriter};

/// The formats a query's answers are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryFormat {
    /// `query,curve,t,x0..,distance`.
    Csv,
    /// `{"closest": [{"curve", "t", "point", "distance"}, ...]}`.
    Json,
    /// Arrays "curve" (int64), "t", "point" (Q, D) and "distance".
    Npz,
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
            let mut npz = NpzWriter::new(out);
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
            for (name, dtype, shape, bytes) in arrays {
                npz.begin(name, dtype, shape)?;
                npz.write(bytes)?;
                npz.end()?;
            }
            npz.finish()?;
        }
    }
    Ok(())
}
