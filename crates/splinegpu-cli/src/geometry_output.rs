//! Writing a geometry document's meshes (contract: "Output of a document with geometry"): JSON,
//! CSV (vertices), NPZ (streamed) and the mesh files (.obj, .glb). Meshes are made group by
//! group ([`GeometryJob::groups`]: f64 on the CPU, f32 on the GPU), so that memory holds one
//! group's meshes at a time in every format (a .glb's binary chunk waits in spills, on disk
//! past a few MiB, until its header, which needs the positions' bounds, is written).
//!
//! A stroke's mesh is 2-D: its points are written with 2 coordinates in JSON, CSV and NPZ, and
//! with z = 0 in the mesh files; it has no normals. Tubes and ribbons are 3-D with normals.

use std::io::{self, Write};
use std::ops::Range;

use splinegpu::InputError;
use splinegpu::geometry::{Geometry, GeometryJob, Meshes};

use crate::document::surfaces::group_vertices;
use crate::mesh_files::{GlbWriter, Mesh, ObjWriter};
use crate::npz::{Dtype, NpzWriter};
use crate::output::OutputError;
use crate::spill::Spill;
use crate::surface_output::Number;

/// Makes the meshes of a range of a job's curves (f64 on the CPU, f32 on the GPU), their
/// offsets from 0.
pub type Make<'a, F> = dyn FnMut(Range<usize>) -> Result<Meshes<F>, OutputError> + 'a;

/// The formats a geometry document is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Vertices, one row each.
    Csv,
    /// Every mesh's points, t, normals and triangles.
    Json,
    /// numpy.load's arrays, the whole document's vertices in one array.
    Npz,
    /// Wavefront OBJ: an object per curve.
    Obj,
    /// glTF 2.0 binary: a mesh per curve, named `curve-<index>`.
    Glb,
}

/// The dimension of mesh c's points: 2 for a stroke, 3 for a tube or ribbon.
fn dim(job: &GeometryJob, c: usize) -> usize {
    match job.geometry(c) {
        Geometry::Stroke(_) => 2,
        _ => 3,
    }
}

/// Whether mesh c has normals (tubes and ribbons).
fn has_normals(job: &GeometryJob, c: usize) -> bool {
    dim(job, c) == 3
}

/// Checks that the job can be written as `format`: NPZ holds one array of points, so strokes
/// (2-D) and tubes or ribbons (3-D) cannot share it.
///
/// # Errors
/// The first curve whose dimension differs from curve 0's, naming "geometry".
pub fn check_format(job: &GeometryJob, format: MeshFormat) -> Result<(), InputError> {
    if format != MeshFormat::Npz {
        return Ok(());
    }
    let first = dim(job, 0);
    match (0..job.len()).find(|&c| dim(job, c) != first) {
        None => Ok(()),
        Some(c) => Err(InputError::field(
            "geometry",
            format!(
                "a {} makes {}-D points but curve 0's {} makes {first}-D: npz output needs one \
                 dimension for all curves",
                job.geometry(c).name(),
                dim(job, c),
                job.geometry(0).name()
            ),
        )
        .in_curve(c)),
    }
}

/// One group's meshes made by `make`, checked: every value finite (JSON and CSV have no
/// infinities; a width that overflows the number type is the input's fault), naming the curve
/// and the vertex.
fn evaluate<F: Number>(
    make: &mut Make<'_, F>,
    group: Range<usize>,
) -> Result<Meshes<F>, OutputError> {
    let first = group.start;
    let meshes = make(group)?;
    let finite = |plane: &[F]| plane.iter().fold(true, |ok, v| ok & v.finite());
    if finite(&meshes.points) && finite(&meshes.normals) {
        return Ok(meshes);
    }
    for c in 0..meshes.vertex_offsets.len() - 1 {
        let vertices = vertex_range(&meshes, c);
        for plane in [&meshes.points, &meshes.normals] {
            let values = &plane[3 * vertices.start..3 * vertices.end];
            if let Some(i) = values.iter().position(|v| !v.finite()) {
                return Err(OutputError::MeshNonFinite {
                    curve: first + c,
                    vertex: i / 3,
                });
            }
        }
    }
    unreachable!("a value that is not finite lies in some mesh")
}

fn vertex_range<F>(meshes: &Meshes<F>, c: usize) -> Range<usize> {
    meshes.vertex_offsets[c] as usize..meshes.vertex_offsets[c + 1] as usize
}

fn triangle_range<F>(meshes: &Meshes<F>, c: usize) -> Range<usize> {
    meshes.triangle_offsets[c] as usize..meshes.triangle_offsets[c + 1] as usize
}

/// Mesh c of a group as the mesh files take it (`curve` its index in the document).
fn mesh_of<'a, F>(job: &GeometryJob, meshes: &'a Meshes<F>, c: usize, curve: usize) -> Mesh<'a, F> {
    let (v, f) = (vertex_range(meshes, c), triangle_range(meshes, c));
    let normals = &meshes.normals[3 * v.start..3 * v.end];
    Mesh {
        name: format!("curve-{curve}"),
        positions: &meshes.points[3 * v.start..3 * v.end],
        normals: has_normals(job, curve).then_some(normals),
        triangles: &meshes.triangles[f],
    }
}

/// Writes every mesh of `job` as `format`, group by group, each group made by `make`.
///
/// # Errors
/// An I/O error of `out`, `make`'s, or a value that is not finite.
pub fn write<F: Number>(
    job: &GeometryJob,
    format: MeshFormat,
    out: &mut dyn Write,
    make: &mut Make<'_, F>,
) -> Result<(), OutputError> {
    // As surfaces': 2^20 vertices a group (7 f64 each, about 60 MB), or SPLINEGPU_CHUNK_SAMPLES.
    let groups = job.groups(group_vertices() as u64);
    match format {
        MeshFormat::Csv => write_csv(job, &groups, out, make),
        MeshFormat::Json => write_json(job, &groups, out, make),
        MeshFormat::Npz => write_npz(job, &groups, out, make),
        MeshFormat::Obj => {
            let mut obj = ObjWriter::new(out, "geometry: one object per curve")?;
            for group in groups {
                let meshes = evaluate(make, group.clone())?;
                for (c, curve) in group.enumerate() {
                    obj.mesh(&mesh_of(job, &meshes, c, curve))?;
                }
            }
            Ok(())
        }
        MeshFormat::Glb => {
            let mut glb = GlbWriter::new();
            for group in groups {
                let meshes = evaluate(make, group.clone())?;
                for (c, curve) in group.enumerate() {
                    glb.mesh(&mesh_of(job, &meshes, c, curve))?;
                }
            }
            Ok(glb.finish(out)?)
        }
    }
}

/// Numbers as CSV fields or JSON numbers, `separator` between them.
fn put<F: zmij::Float + Copy>(
    line: &mut Vec<u8>,
    number: &mut zmij::Buffer,
    values: &[F],
    separator: &[u8],
) {
    for (k, x) in values.iter().enumerate() {
        if k > 0 {
            line.extend_from_slice(separator);
        }
        line.extend_from_slice(number.format(*x).as_bytes());
    }
}

fn write_csv<F: Number>(
    job: &GeometryJob,
    groups: &[Range<usize>],
    out: &mut dyn Write,
    make: &mut Make<'_, F>,
) -> Result<(), OutputError> {
    let width = (0..job.len()).map(|c| dim(job, c)).max().unwrap_or(3);
    let normals = (0..job.len()).any(|c| has_normals(job, c));
    let mut header = String::from("curve,vertex,t");
    for k in 0..width {
        header.push_str(&format!(",x{k}"));
    }
    if normals {
        header.push_str(",nx,ny,nz");
    }
    writeln!(out, "{header}")?;
    let mut number = zmij::Buffer::new();
    let mut line = Vec::new();
    for group in groups {
        let meshes = evaluate(make, group.clone())?;
        for (c, curve) in group.clone().enumerate() {
            let d = dim(job, curve);
            for (v, vertex) in vertex_range(&meshes, c).enumerate() {
                line.clear();
                write!(line, "{curve},{v},")?;
                line.extend_from_slice(number.format(meshes.t[vertex]).as_bytes());
                line.push(b',');
                put(
                    &mut line,
                    &mut number,
                    &meshes.points[3 * vertex..3 * vertex + d],
                    b",",
                );
                line.extend(std::iter::repeat_n(b',', width - d));
                if normals {
                    line.push(b',');
                    if has_normals(job, curve) {
                        let n = &meshes.normals[3 * vertex..3 * vertex + 3];
                        put(&mut line, &mut number, n, b",");
                    } else {
                        line.extend_from_slice(b",,");
                    }
                }
                line.push(b'\n');
                out.write_all(&line)?;
            }
        }
    }
    Ok(())
}

fn write_json<F: Number>(
    job: &GeometryJob,
    groups: &[Range<usize>],
    out: &mut dyn Write,
    make: &mut Make<'_, F>,
) -> Result<(), OutputError> {
    let mut number = zmij::Buffer::new();
    let mut text = Vec::new();
    // A mesh's text is written out whenever it passes this, so that memory holds a bounded
    // part of it however large the mesh.
    const FLUSH: usize = 1 << 16;
    let flush = |text: &mut Vec<u8>, out: &mut dyn Write| -> io::Result<()> {
        if text.len() >= FLUSH {
            out.write_all(text)?;
            text.clear();
        }
        Ok(())
    };
    let rows = |text: &mut Vec<u8>,
                number: &mut zmij::Buffer,
                plane: &[F],
                d: usize,
                out: &mut dyn Write|
     -> io::Result<()> {
        text.push(b'[');
        for (i, p) in plane.chunks_exact(3).enumerate() {
            text.extend_from_slice(if i > 0 { b", [" } else { b"[" });
            put(text, number, &p[..d], b", ");
            text.push(b']');
            flush(text, out)?;
        }
        text.push(b']');
        Ok(())
    };
    out.write_all(b"{\"meshes\": [")?;
    for group in groups {
        let meshes = evaluate(make, group.clone())?;
        for (c, curve) in group.clone().enumerate() {
            let (v, f) = (vertex_range(&meshes, c), triangle_range(&meshes, c));
            text.clear();
            text.extend_from_slice(if curve > 0 { b",\n" } else { b"\n" });
            text.extend_from_slice(b"{\"points\": ");
            rows(
                &mut text,
                &mut number,
                &meshes.points[3 * v.start..3 * v.end],
                dim(job, curve),
                out,
            )?;
            text.extend_from_slice(b", \"t\": [");
            for (i, ts) in meshes.t[v.clone()].chunks(1024).enumerate() {
                if i > 0 {
                    text.extend_from_slice(b", ");
                }
                put(&mut text, &mut number, ts, b", ");
                flush(&mut text, out)?;
            }
            text.push(b']');
            if has_normals(job, curve) {
                text.extend_from_slice(b", \"normals\": ");
                rows(
                    &mut text,
                    &mut number,
                    &meshes.normals[3 * v.start..3 * v.end],
                    3,
                    out,
                )?;
            }
            text.extend_from_slice(b", \"triangles\": [");
            for (i, [a, b, c]) in meshes.triangles[f].iter().enumerate() {
                write!(text, "{}[{a}, {b}, {c}]", if i > 0 { ", " } else { "" })?;
                flush(&mut text, out)?;
            }
            text.extend_from_slice(b"]}");
            out.write_all(&text)?;
        }
    }
    out.write_all(b"\n]}\n")?;
    Ok(())
}

fn write_npz<F: Number>(
    job: &GeometryJob,
    groups: &[Range<usize>],
    out: &mut dyn Write,
    make: &mut Make<'_, F>,
) -> Result<(), OutputError> {
    let mut npz = NpzWriter::new(out);
    let d = dim(job, 0);
    let normals = has_normals(job, 0);
    let (vertices, triangles) = (job.vertex_count(), job.triangle_count());
    // "t", "normals" and "triangles" wait while "points" is written.
    let mut waiting: [Spill; 3] = Default::default();
    npz.begin("points", Dtype::of::<F>(), &[vertices, d as u64])?;
    for group in groups {
        let first = job.vertex_offsets()[group.start];
        let meshes = evaluate(make, group.clone())?;
        if d == 3 {
            npz.write(bytemuck::cast_slice(&meshes.points))?;
        } else {
            // A stroke's (x, y), a bounded run at a time.
            let mut flat: Vec<F> = Vec::with_capacity(2 * 4096);
            for run in meshes.points.chunks(3 * 4096) {
                flat.clear();
                flat.extend(run.chunks_exact(3).flat_map(|p| [p[0], p[1]]));
                npz.write(bytemuck::cast_slice(&flat))?;
            }
        }
        waiting[0].write_all(bytemuck::cast_slice(&meshes.t))?;
        if normals {
            waiting[1].write_all(bytemuck::cast_slice(&meshes.normals))?;
        }
        // Indices into the whole vertex array, a bounded run at a time.
        let mut shifted: Vec<i64> = Vec::with_capacity(3 * 4096);
        for c in 0..group.len() {
            let base = (first + meshes.vertex_offsets[c]) as i64;
            for run in meshes.triangles[triangle_range(&meshes, c)].chunks(4096) {
                shifted.clear();
                shifted.extend(run.iter().flatten().map(|&i| i64::from(i) + base));
                waiting[2].write_all(bytemuck::cast_slice(&shifted))?;
            }
        }
    }
    npz.end()?;
    let [t, n, tri] = &mut waiting;
    npz.array_from("t", Dtype::F64, &[vertices], t)?;
    if normals {
        npz.array_from("normals", Dtype::of::<F>(), &[vertices, 3], n)?;
    }
    npz.array_from("triangles", Dtype::I64, &[triangles, 3], tri)?;
    npz.offsets("curve_offsets", job.vertex_offsets())?;
    npz.offsets("triangle_offsets", job.triangle_offsets())?;
    npz.finish()?;
    Ok(())
}
