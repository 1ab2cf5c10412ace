//! Writing a surface document's samples (contract: "Output of a surface document"): JSON, CSV
//! (vertices), NPZ (streamed), and meshes a viewer opens as they are, Wavefront .obj and glTF
//! 2.0 binary (.glb), through [`crate::mesh_files`].

use std::io::{self, Write};
use std::ops::Range;

use splinegpu::surface::{SurfaceJob, SurfaceSamples};
use splinegpu::{InputError, SampleFloat};

use crate::document::surfaces::group_vertices;
use crate::mesh_files::{Mesh, ObjWriter, write_glb};
use crate::npz::{Dtype, NpzWriter};
use crate::output::OutputError;

/// The number types samples come in: f64 from the CPU, f32 from the GPU, each printed as the
/// shortest text that reads back as the same value of its type.
pub trait Number: SampleFloat + zmij::Float + Into<f64> {}

impl<F: SampleFloat + zmij::Float + Into<f64>> Number for F {}

/// The formats a surface document is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceFormat {
    /// Vertices, one row each.
    Csv,
    /// Every array of every surface.
    Json,
    /// numpy.load's arrays, the whole document's vertices in one array.
    Npz,
    /// Wavefront OBJ: positions, normals when asked, triangles; an object per surface.
    Obj,
    /// glTF 2.0 binary: a mesh per surface, named `surface-<index>`.
    Glb,
}

/// Checks that the job can be written as `format`: a mesh format needs 3-D points and a
/// sampling that makes triangles; NPZ one dimension for every surface.
///
/// # Errors
/// The first surface that cannot, naming its field.
pub fn check_format(job: &SurfaceJob, format: SurfaceFormat) -> Result<(), InputError> {
    let first = job.surfaces()[0].table().dim();
    for (i, surface) in job.surfaces().iter().enumerate() {
        let table = surface.table();
        match format {
            SurfaceFormat::Obj | SurfaceFormat::Glb => {
                let name = if format == SurfaceFormat::Obj {
                    "obj"
                } else {
                    "glb"
                };
                if table.dim() != 3 {
                    return Err(InputError::field(
                        "points",
                        format!(
                            "have {} coordinates per point: a .{name} mesh needs 3",
                            table.dim()
                        ),
                    )
                    .in_surface(i));
                }
                if surface.triangles().is_none() {
                    return Err(InputError::field(
                        "sampling",
                        format!("\"at\" makes no triangles: a .{name} mesh needs per_segment or tolerance"),
                    )
                    .in_surface(i));
                }
            }
            SurfaceFormat::Npz if table.dim() != first => {
                return Err(InputError::field(
                    "points",
                    format!(
                        "have {} coordinates per point but surface 0's have {first}: npz output \
                         needs one dimension for all surfaces",
                        table.dim()
                    ),
                )
                .in_surface(i));
            }
            _ => {}
        }
    }
    Ok(())
}

/// Every value is finite (JSON and CSV have no infinities), naming the first vertex that is not
/// (`samples[0]` is surface `first` of the document).
///
/// # Errors
/// [`OutputError::SurfaceNonFinite`].
pub fn check_finite<F: Number>(
    samples: &[SurfaceSamples<F>],
    first: usize,
) -> Result<(), OutputError> {
    for (i, s) in samples.iter().enumerate() {
        let surface = first + i;
        for (width, plane) in planes(s) {
            if let Some(i) = plane.iter().position(|v| !v.finite()) {
                return Err(OutputError::SurfaceNonFinite {
                    surface,
                    vertex: i / width,
                });
            }
        }
    }
    Ok(())
}

/// A surface's planes that are present, each with its values per vertex: positions, du, dv,
/// duu, duv, dvv, normals, with their contract names.
fn named_planes<F>(s: &SurfaceSamples<F>) -> Vec<(&'static str, usize, &[F])> {
    let mut out = vec![("points", s.dim, s.points.as_slice())];
    for (name, plane) in [
        ("du", &s.du),
        ("dv", &s.dv),
        ("duu", &s.duu),
        ("duv", &s.duv),
        ("dvv", &s.dvv),
    ] {
        if let Some(p) = plane {
            out.push((name, s.dim, p.as_slice()));
        }
    }
    if let Some(n) = &s.normals {
        out.push(("normals", 3, n.as_slice()));
    }
    out
}

/// [`named_planes`] as (width, values).
fn planes<F>(s: &SurfaceSamples<F>) -> Vec<(usize, &[F])> {
    named_planes(s)
        .into_iter()
        .map(|(_, w, p)| (w, p))
        .collect()
}

/// Evaluates a range of a job's surfaces (f64 on the CPU, f32 on the GPU).
pub type Evaluate<'a, F> =
    dyn FnMut(Range<usize>) -> Result<Vec<SurfaceSamples<F>>, OutputError> + 'a;

/// Writes every surface of `job` as `format`, evaluating them with `evaluate` group by group
/// ([`SurfaceJob::groups`]), so that memory holds one group's samples at a time: CSV, JSON and
/// .obj write each group as it comes; NPZ writes "uv" as it comes and keeps the other arrays in
/// temporary files until their turn. A .glb holds its whole binary chunk after a header that
/// gives its length: it is the one format written from every group at once.
///
/// Every group is checked before any of it is written: a value that is not finite (a surface
/// whose values overflow f64) is refused in every format, naming the surface and the vertex.
///
/// # Errors
/// An I/O error of `out`, the evaluator's, or a value that is not finite.
pub fn write<F: Number>(
    job: &SurfaceJob,
    format: SurfaceFormat,
    out: &mut dyn Write,
    evaluate: &mut Evaluate<'_, F>,
) -> Result<(), OutputError> {
    let groups = job.groups(group_vertices());
    let evaluate: &mut Evaluate<'_, F> = &mut |group: Range<usize>| {
        let first = group.start;
        let samples = evaluate(group)?;
        check_finite(&samples, first)?;
        Ok(samples)
    };
    match format {
        SurfaceFormat::Csv => write_csv(job, &groups, evaluate, out),
        SurfaceFormat::Json => write_json(&groups, evaluate, out),
        SurfaceFormat::Npz => write_npz(job, &groups, evaluate, out),
        SurfaceFormat::Obj => write_obj(&groups, evaluate, out),
        SurfaceFormat::Glb => {
            let mut all = Vec::with_capacity(job.len());
            for group in groups {
                all.extend(evaluate(group)?);
            }
            let meshes: Vec<Mesh<'_, F>> =
                all.iter().enumerate().map(|(i, s)| mesh_of(i, s)).collect();
            Ok(write_glb(&meshes, out)?)
        }
    }
}

/// The planes the job's samples hold, with their contract names: positions, du, dv, duu, duv,
/// dvv as asked, normals when asked.
fn job_planes(job: &SurfaceJob) -> Vec<&'static str> {
    let order = job.derivatives().order();
    let mut names = vec!["points"];
    if order >= 1 {
        names.extend(["du", "dv"]);
    }
    if order >= 2 {
        names.extend(["duu", "duv", "dvv"]);
    }
    if job.normals() {
        names.push("normals");
    }
    names
}

fn write_csv<F: Number>(
    job: &SurfaceJob,
    groups: &[Range<usize>],
    evaluate: &mut Evaluate<'_, F>,
    out: &mut dyn Write,
) -> Result<(), OutputError> {
    let dim = job
        .surfaces()
        .iter()
        .map(|s| s.table().dim())
        .max()
        .unwrap_or(1);
    let patches = job.has_patch_lists();
    let mut header = String::from("surface,sample,u,v");
    for name in job_planes(job) {
        if name == "normals" {
            header.push_str(",nx,ny,nz");
            continue;
        }
        let prefix = if name == "points" { "" } else { name };
        for k in 0..dim {
            header.push_str(&format!(",{prefix}x{k}"));
        }
    }
    if patches {
        header.push_str(",patch");
    }
    writeln!(out, "{header}")?;
    let mut number = zmij::Buffer::new();
    let mut line = Vec::new();
    for group in groups {
        let samples = evaluate(group.clone())?;
        for (i, s) in (group.start..).zip(&samples) {
            let planes = named_planes(s);
            for v in 0..s.len() {
                line.clear();
                write!(line, "{i},{v}")?;
                for x in s.uv[v] {
                    line.push(b',');
                    line.extend_from_slice(number.format(x).as_bytes());
                }
                for (name, width, plane) in &planes {
                    for x in &plane[v * width..(v + 1) * width] {
                        line.push(b',');
                        line.extend_from_slice(number.format(*x).as_bytes());
                    }
                    if *name != "normals" {
                        line.extend(std::iter::repeat_n(b',', dim - width));
                    }
                }
                if patches {
                    line.push(b',');
                    if let Some(p) = &s.patch {
                        write!(line, "{}", p[v])?;
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
    groups: &[Range<usize>],
    evaluate: &mut Evaluate<'_, F>,
    out: &mut dyn Write,
) -> Result<(), OutputError> {
    fn rows<T: zmij::Float + Copy>(
        out: &mut dyn Write,
        values: &[T],
        width: usize,
    ) -> io::Result<()> {
        let mut number = zmij::Buffer::new();
        out.write_all(b"[")?;
        for (i, row) in values.chunks_exact(width.max(1)).enumerate() {
            out.write_all(if i > 0 { b", [" } else { b"[" })?;
            for (k, x) in row.iter().enumerate() {
                if k > 0 {
                    out.write_all(b", ")?;
                }
                out.write_all(number.format(*x).as_bytes())?;
            }
            out.write_all(b"]")?;
        }
        out.write_all(b"]")
    }
    out.write_all(b"{\"surfaces\": [")?;
    for group in groups {
        let samples = evaluate(group.clone())?;
        for (i, s) in (group.start..).zip(&samples) {
            out.write_all(if i > 0 {
                b",\n{\"uv\": "
            } else {
                b"\n{\"uv\": "
            })?;
            let uv: Vec<f64> = s.uv.iter().flatten().copied().collect();
            rows(out, &uv, 2)?;
            for (name, width, plane) in named_planes(s) {
                write!(out, ", \"{name}\": ")?;
                rows(out, plane, width)?;
            }
            if let Some(triangles) = &s.triangles {
                out.write_all(b", \"triangles\": [")?;
                for (t, [a, b, c]) in triangles.iter().enumerate() {
                    write!(out, "{}[{a}, {b}, {c}]", if t > 0 { ", " } else { "" })?;
                }
                out.write_all(b"]")?;
            }
            if let Some(patch) = &s.patch {
                out.write_all(b", \"patch\": [")?;
                for (t, p) in patch.iter().enumerate() {
                    write!(out, "{}{p}", if t > 0 { ", " } else { "" })?;
                }
                out.write_all(b"]")?;
            }
            out.write_all(b"}")?;
        }
    }
    out.write_all(b"\n]}\n")?;
    Ok(())
}

/// A temporary file an NPZ array waits in for its turn.
type Waiting = io::BufWriter<std::fs::File>;

fn write_npz<F: Number>(
    job: &SurfaceJob,
    groups: &[Range<usize>],
    evaluate: &mut Evaluate<'_, F>,
    out: &mut dyn Write,
) -> Result<(), OutputError> {
    let mut npz = NpzWriter::new(out);
    let dim = job.surfaces()[0].table().dim() as u64;
    let (vertices, triangles) = (job.vertex_count(), job.triangle_count());
    let patches = job.has_patch_lists();
    // Every array after "uv" waits in a file: the planes, the triangles, the patches.
    let names = job_planes(job);
    let mut waiting: Vec<Waiting> = (0..names.len() + 1 + usize::from(patches))
        .map(|_| tempfile::tempfile().map(|f| io::BufWriter::with_capacity(1 << 20, f)))
        .collect::<Result<_, _>>()?;
    npz.begin("uv", Dtype::F64, &[vertices, 2])?;
    let mut offset = 0i64;
    for group in groups {
        for s in evaluate(group.clone())? {
            npz.write(bytemuck::cast_slice(&s.uv))?;
            let planes = named_planes(&s);
            let (files, rest) = waiting.split_at_mut(planes.len());
            for (file, (_, _, plane)) in files.iter_mut().zip(&planes) {
                file.write_all(bytemuck::cast_slice(plane))?;
            }
            if let Some(t) = &s.triangles {
                let shifted: Vec<i64> =
                    t.iter().flatten().map(|&i| i64::from(i) + offset).collect();
                rest[0].write_all(bytemuck::cast_slice(&shifted))?;
            }
            if patches {
                let patch: Vec<i64> = match &s.patch {
                    Some(p) => p.iter().map(|&p| i64::from(p)).collect(),
                    None => vec![-1; s.len()],
                };
                rest[1].write_all(bytemuck::cast_slice(&patch))?;
            }
            offset += s.len() as i64;
        }
    }
    npz.end()?;
    let mut waiting = waiting.into_iter();
    let mut copy = |npz: &mut NpzWriter<&mut dyn Write>, name, dtype, shape: &[u64]| {
        let file = waiting.next().expect("one file per waiting array");
        npz.array_from(name, dtype, shape, file)
    };
    for name in &names {
        let width = if *name == "normals" { 3 } else { dim };
        copy(&mut npz, name, Dtype::of::<F>(), &[vertices, width])?;
    }
    copy(&mut npz, "triangles", Dtype::I64, &[triangles, 3])?;
    let s = job.len() as u64 + 1;
    let signed = |offsets: &[u64]| -> Vec<i64> { offsets.iter().map(|&o| o as i64).collect() };
    npz.begin("surface_offsets", Dtype::I64, &[s])?;
    npz.write(bytemuck::cast_slice(&signed(job.vertex_offsets())))?;
    npz.end()?;
    npz.begin("triangle_offsets", Dtype::I64, &[s])?;
    npz.write(bytemuck::cast_slice(&signed(job.triangle_offsets())))?;
    npz.end()?;
    if patches {
        copy(&mut npz, "patch", Dtype::I64, &[vertices])?;
    }
    npz.finish()?;
    Ok(())
}

fn write_obj<F: Number>(
    groups: &[Range<usize>],
    evaluate: &mut Evaluate<'_, F>,
    out: &mut dyn Write,
) -> Result<(), OutputError> {
    let mut obj = ObjWriter::new(out, "surfaces: one object per surface")?;
    for group in groups {
        for (i, s) in (group.start..).zip(evaluate(group.clone())?) {
            obj.mesh(&mesh_of(i, &s))?;
        }
    }
    Ok(())
}

/// A surface's mesh as the mesh files take it.
fn mesh_of<F: Number>(i: usize, s: &SurfaceSamples<F>) -> Mesh<'_, F> {
    Mesh {
        name: format!("surface-{i}"),
        positions: &s.points,
        normals: s.normals.as_deref(),
        triangles: s.triangles.as_deref().unwrap_or_default(),
    }
}
