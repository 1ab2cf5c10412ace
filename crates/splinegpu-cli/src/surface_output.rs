//! Writing a surface document's samples (contract: "Output of a surface document"): JSON, CSV
//! (vertices), NPZ, and meshes a viewer opens as they are, Wavefront .obj and glTF 2.0 binary
//! (.glb), through [`crate::mesh_files`]. Every format is streamed: the job is evaluated chunk
//! by chunk ([`SurfaceJob::chunks`]: runs of whole surfaces, a surface larger than a chunk in
//! pieces), each chunk written as it comes and what the format puts later (NPZ's arrays after
//! "uv", JSON's arrays after a surface's "uv", a mesh file's normals, faces and binary chunk)
//! waiting in spills, so that memory holds one chunk's samples however large a surface.

use std::io::Write;

use splinegpu::surface::{ChunkPart, SurfaceChunk, SurfaceJob, SurfaceSamples};
use splinegpu::{InputError, SampleFloat};

use crate::document::surfaces::group_vertices;
use crate::mesh_files::{GlbWriter, Mesh, ObjWriter};
use crate::npz::{Dtype, NpzWriter};
use crate::output::OutputError;
use crate::spill::Spill;

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
/// (vertex numbers within its surface).
///
/// # Errors
/// [`OutputError::SurfaceNonFinite`].
pub fn check_finite<F: Number>(
    chunk: &SurfaceChunk,
    samples: &[SurfaceSamples<F>],
) -> Result<(), OutputError> {
    for (part, s) in chunk.parts().iter().zip(samples) {
        for (_, width, plane) in named_planes(s) {
            if let Some(i) = plane.iter().position(|v| !v.finite()) {
                return Err(OutputError::SurfaceNonFinite {
                    surface: part.surface(),
                    vertex: part.first_vertex() + i / width,
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

/// Evaluates a chunk of a job (f64 on the CPU, f32 on the GPU): a sample list per part.
pub type Evaluate<'a, F> =
    dyn FnMut(&SurfaceChunk) -> Result<Vec<SurfaceSamples<F>>, OutputError> + 'a;

/// A format's writer, taking the job's parts in order (a surface's pieces one after the
/// other, then the next surface).
trait Sink<F: Number> {
    /// One part and its samples (a piece's triangles index its whole surface's vertices).
    fn part(&mut self, part: &ChunkPart, samples: &SurfaceSamples<F>) -> Result<(), OutputError>;

    /// Ends the file.
    fn finish(self: Box<Self>) -> Result<(), OutputError>;
}

/// Writes every surface of `job` as `format`, evaluating them with `evaluate` chunk by chunk
/// ([`SurfaceJob::chunks`]), so that memory holds one chunk's samples at a time.
///
/// Every chunk is checked before any of it is written: a value that is not finite (a surface
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
    let mut sink: Box<dyn Sink<F> + '_> = match format {
        SurfaceFormat::Csv => Box::new(Csv::new(job, out)?),
        SurfaceFormat::Json => Box::new(Json::new(job, out)?),
        SurfaceFormat::Npz => Box::new(Npz::new(job, out)?),
        SurfaceFormat::Obj => Box::new(Obj {
            obj: ObjWriter::new(out, "surfaces: one object per surface")?,
        }),
        SurfaceFormat::Glb => Box::new(Glb {
            glb: GlbWriter::new(),
            out,
        }),
    };
    for chunk in job.chunks(group_vertices()) {
        let samples = evaluate(&chunk)?;
        check_finite(&chunk, &samples)?;
        for (part, s) in chunk.parts().iter().zip(&samples) {
            sink.part(part, s)?;
        }
    }
    sink.finish()
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

/// CSV: a row a vertex.
struct Csv<'w> {
    out: &'w mut dyn Write,
    dim: usize,
    patches: bool,
    number: zmij::Buffer,
    line: Vec<u8>,
}

impl<'w> Csv<'w> {
    /// Writes the header.
    fn new(job: &SurfaceJob, out: &'w mut dyn Write) -> Result<Self, OutputError> {
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
        Ok(Self {
            out,
            dim,
            patches,
            number: zmij::Buffer::new(),
            line: Vec::new(),
        })
    }
}

impl<F: Number> Sink<F> for Csv<'_> {
    fn part(&mut self, part: &ChunkPart, s: &SurfaceSamples<F>) -> Result<(), OutputError> {
        let (line, number) = (&mut self.line, &mut self.number);
        let planes = named_planes(s);
        for v in 0..s.len() {
            line.clear();
            write!(line, "{},{}", part.surface(), part.first_vertex() + v)?;
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
                    line.extend(std::iter::repeat_n(b',', self.dim - width));
                }
            }
            if self.patches {
                line.push(b',');
                if let Some(p) = &s.patch {
                    write!(line, "{}", p[v])?;
                }
            }
            line.push(b'\n');
            self.out.write_all(line)?;
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), OutputError> {
        Ok(())
    }
}

/// JSON: an object a surface, its "uv" written as it comes, its other arrays waiting in a
/// spill each until the surface's last piece.
struct Json<'w> {
    out: &'w mut dyn Write,
    /// One spill per array after "uv": the planes, then "triangles", then "patch".
    waiting: Vec<Spill>,
    /// Triangles of the open surface written so far.
    triangles: usize,
    number: zmij::Buffer,
    text: Vec<u8>,
}

impl<'w> Json<'w> {
    fn new(job: &SurfaceJob, out: &'w mut dyn Write) -> Result<Self, OutputError> {
        out.write_all(b"{\"surfaces\": [")?;
        let arrays = job_planes(job).len() + 2;
        Ok(Self {
            out,
            waiting: (0..arrays).map(|_| Spill::new()).collect(),
            triangles: 0,
            number: zmij::Buffer::new(),
            text: Vec::new(),
        })
    }
}

/// Rows of `width` numbers as JSON arrays, after `before` rows of the same array.
fn json_rows<T: zmij::Float + Copy>(
    text: &mut Vec<u8>,
    number: &mut zmij::Buffer,
    values: &[T],
    width: usize,
    before: usize,
) {
    for (i, row) in values.chunks_exact(width.max(1)).enumerate() {
        text.extend_from_slice(if before + i > 0 { b", [" } else { b"[" });
        for (k, x) in row.iter().enumerate() {
            if k > 0 {
                text.extend_from_slice(b", ");
            }
            text.extend_from_slice(number.format(*x).as_bytes());
        }
        text.push(b']');
    }
}

impl<F: Number> Sink<F> for Json<'_> {
    fn part(&mut self, part: &ChunkPart, s: &SurfaceSamples<F>) -> Result<(), OutputError> {
        let (text, number, before) = (&mut self.text, &mut self.number, part.first_vertex());
        text.clear();
        if part.is_first() {
            self.triangles = 0;
            text.extend_from_slice(if part.surface() > 0 {
                b",\n{\"uv\": ["
            } else {
                b"\n{\"uv\": ["
            });
        }
        let uv: Vec<f64> = s.uv.iter().flatten().copied().collect();
        json_rows(text, number, &uv, 2, before);
        self.out.write_all(text)?;
        let planes = named_planes(s);
        let (planes_waiting, rest) = self.waiting.split_at_mut(planes.len());
        for (waiting, (_, width, plane)) in planes_waiting.iter_mut().zip(&planes) {
            text.clear();
            json_rows(text, number, plane, *width, before);
            waiting.write_all(text)?;
        }
        if let Some(triangles) = &s.triangles {
            text.clear();
            for (t, [a, b, c]) in triangles.iter().enumerate() {
                let comma = if self.triangles + t > 0 { ", " } else { "" };
                write!(text, "{comma}[{a}, {b}, {c}]")?;
            }
            self.triangles += triangles.len();
            rest[0].write_all(text)?;
        }
        if let Some(patch) = &s.patch {
            text.clear();
            for (t, p) in patch.iter().enumerate() {
                write!(text, "{}{p}", if before + t > 0 { ", " } else { "" })?;
            }
            rest[1].write_all(text)?;
        }
        if part.is_last() {
            self.out.write_all(b"]")?;
            for (waiting, (name, _, _)) in planes_waiting.iter_mut().zip(&planes) {
                write!(self.out, ", \"{name}\": [")?;
                waiting.drain_into(self.out)?;
                self.out.write_all(b"]")?;
            }
            let present = [s.triangles.is_some(), s.patch.is_some()];
            for ((waiting, name), present) in
                rest.iter_mut().zip(["triangles", "patch"]).zip(present)
            {
                if present {
                    write!(self.out, ", \"{name}\": [")?;
                    waiting.drain_into(self.out)?;
                    self.out.write_all(b"]")?;
                }
            }
            self.out.write_all(b"}")?;
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), OutputError> {
        self.out.write_all(b"\n]}\n")?;
        Ok(())
    }
}

/// NPZ: "uv" streamed, every other array waiting in a spill until its turn.
struct Npz<'w, 'j> {
    npz: NpzWriter<&'w mut dyn Write>,
    job: &'j SurfaceJob,
    /// One spill per plane, then "triangles", then "patch" where the job has patch lists.
    waiting: Vec<Spill>,
    patches: bool,
}

impl<'w, 'j> Npz<'w, 'j> {
    fn new(job: &'j SurfaceJob, out: &'w mut dyn Write) -> Result<Self, OutputError> {
        let mut npz = NpzWriter::new(out);
        npz.begin("uv", Dtype::F64, &[job.vertex_count(), 2])?;
        let patches = job.has_patch_lists();
        let arrays = job_planes(job).len() + 1 + usize::from(patches);
        Ok(Self {
            npz,
            job,
            waiting: (0..arrays).map(|_| Spill::new()).collect(),
            patches,
        })
    }
}

impl<F: Number> Sink<F> for Npz<'_, '_> {
    fn part(&mut self, part: &ChunkPart, s: &SurfaceSamples<F>) -> Result<(), OutputError> {
        self.npz.write(bytemuck::cast_slice(&s.uv))?;
        let planes = named_planes(s);
        let (files, rest) = self.waiting.split_at_mut(planes.len());
        for (file, (_, _, plane)) in files.iter_mut().zip(&planes) {
            file.write_all(bytemuck::cast_slice(plane))?;
        }
        // Indices into the whole vertex array.
        let offset = self.job.vertex_offsets()[part.surface()] as i64;
        if let Some(t) = &s.triangles {
            let shifted: Vec<i64> = t.iter().flatten().map(|&i| i64::from(i) + offset).collect();
            rest[0].write_all(bytemuck::cast_slice(&shifted))?;
        }
        if self.patches {
            let patch: Vec<i64> = match &s.patch {
                Some(p) => p.iter().map(|&p| i64::from(p)).collect(),
                None => vec![-1; s.len()],
            };
            rest[1].write_all(bytemuck::cast_slice(&patch))?;
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), OutputError> {
        let Self {
            mut npz,
            job,
            mut waiting,
            patches,
        } = *self;
        npz.end()?;
        let dim = job.surfaces()[0].table().dim() as u64;
        let vertices = job.vertex_count();
        let mut waiting = waiting.iter_mut();
        let mut copy = |npz: &mut NpzWriter<&mut dyn Write>, name, dtype, shape: &[u64]| {
            let spill = waiting.next().expect("a spill per waiting array");
            npz.array_from(name, dtype, shape, spill)
        };
        for name in job_planes(job) {
            let width = if name == "normals" { 3 } else { dim };
            copy(&mut npz, name, Dtype::of::<F>(), &[vertices, width])?;
        }
        copy(
            &mut npz,
            "triangles",
            Dtype::I64,
            &[job.triangle_count(), 3],
        )?;
        npz.offsets("surface_offsets", job.vertex_offsets())?;
        npz.offsets("triangle_offsets", job.triangle_offsets())?;
        if patches {
            copy(&mut npz, "patch", Dtype::I64, &[vertices])?;
        }
        npz.finish()?;
        Ok(())
    }
}

/// Wavefront .obj: an object a surface.
struct Obj<'w> {
    obj: ObjWriter<'w>,
}

impl<F: Number> Sink<F> for Obj<'_> {
    fn part(&mut self, part: &ChunkPart, s: &SurfaceSamples<F>) -> Result<(), OutputError> {
        if part.is_first() {
            self.obj.begin(&mesh_name(part))?;
        }
        self.obj.piece(&mesh_of(part, s))?;
        if part.is_last() {
            self.obj.end()?;
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), OutputError> {
        Ok(())
    }
}

/// glTF 2.0 binary: a mesh a surface.
struct Glb<'w> {
    glb: GlbWriter,
    out: &'w mut dyn Write,
}

impl<F: Number> Sink<F> for Glb<'_> {
    fn part(&mut self, part: &ChunkPart, s: &SurfaceSamples<F>) -> Result<(), OutputError> {
        if part.is_first() {
            self.glb.begin(&mesh_name(part), s.normals.is_some());
        }
        self.glb.piece(&mesh_of(part, s))?;
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), OutputError> {
        self.glb.finish(self.out)?;
        Ok(())
    }
}

/// A surface's mesh name in the mesh files.
fn mesh_name(part: &ChunkPart) -> String {
    format!("surface-{}", part.surface())
}

/// A part's mesh (or piece of one) as the mesh files take it.
fn mesh_of<'s, F: Number>(part: &ChunkPart, s: &'s SurfaceSamples<F>) -> Mesh<'s, F> {
    Mesh {
        name: mesh_name(part),
        positions: &s.points,
        normals: s.normals.as_deref(),
        triangles: s.triangles.as_deref().unwrap_or_default(),
    }
}
