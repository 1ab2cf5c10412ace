//! Triangle meshes in the files a viewer opens as they are: Wavefront .obj (an object per mesh)
//! and glTF 2.0 binary (.glb, through the gltf crate's schema types and container, rather than
//! hand-written offsets and padding). Both are streamed: a mesh comes in pieces (a surface
//! larger than a chunk), each written as it comes, what must come later waiting in a
//! [`Spill`]. Surfaces and the curves' geometry both write through here.

use std::collections::BTreeMap;
use std::io::{self, Write};

use crate::spill::Spill;

use gltf::json;
use gltf::json::validation::{Checked::Valid, USize64};

/// One mesh: 3 coordinates a vertex (a flat mesh's z is 0), a unit normal a vertex where it
/// has normals, and counter-clockwise triangles indexing its own vertices.
#[derive(Debug)]
pub struct Mesh<'a, F> {
    /// The object's or node's name.
    pub name: String,
    /// 3 values a vertex.
    pub positions: &'a [F],
    /// 3 values a vertex, when the mesh has normals.
    pub normals: Option<&'a [F]>,
    /// Indices into the mesh's vertices.
    pub triangles: &'a [[u32; 3]],
}

impl<F> Mesh<'_, F> {
    fn vertices(&self) -> usize {
        self.positions.len() / 3
    }
}

/// A Wavefront .obj file written mesh by mesh, each mesh in one piece or several: `o name`,
/// then the `v` lines of every piece as they come, the `vn` and `f` lines after them (they
/// wait in spills: a face may name a vertex of a later piece); indices counted across the
/// file from 1.
pub struct ObjWriter<'w> {
    out: &'w mut dyn Write,
    /// The file's index of the open mesh's first vertex.
    first: u64,
    /// The open mesh's vertices so far.
    vertices: u64,
    normals: Spill,
    faces: Spill,
    number: zmij::Buffer,
}

impl std::fmt::Debug for ObjWriter<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ObjWriter")
            .field("first", &self.first)
            .finish_non_exhaustive()
    }
}

impl<'w> ObjWriter<'w> {
    /// Starts the file with a comment line saying what it holds.
    ///
    /// # Errors
    /// Any I/O error of `out`.
    pub fn new(out: &'w mut dyn Write, what: &str) -> io::Result<Self> {
        writeln!(out, "# splinegpu {what}")?;
        Ok(Self {
            out,
            first: 1,
            vertices: 0,
            normals: Spill::new(),
            faces: Spill::new(),
            number: zmij::Buffer::new(),
        })
    }

    /// Writes one mesh, whole, as an object of its own.
    ///
    /// # Errors
    /// Any I/O error of the output.
    pub fn mesh<F: zmij::Float + Copy>(&mut self, mesh: &Mesh<'_, F>) -> io::Result<()> {
        self.begin(&mesh.name)?;
        self.piece(mesh)?;
        self.end()
    }

    /// Opens an object named `name`, whose pieces follow.
    ///
    /// # Errors
    /// Any I/O error of the output.
    pub fn begin(&mut self, name: &str) -> io::Result<()> {
        writeln!(self.out, "o {name}")
    }

    /// A piece of the open object: its vertices follow the pieces' before, its triangles
    /// index the whole object's vertices (`piece.name` is not used).
    ///
    /// # Errors
    /// Any I/O error of the output or of a spill.
    pub fn piece<F: zmij::Float + Copy>(&mut self, piece: &Mesh<'_, F>) -> io::Result<()> {
        let number = &mut self.number;
        let mut rows = |out: &mut dyn Write, tag: &[u8], values: &[F]| -> io::Result<()> {
            let mut line = Vec::with_capacity(64);
            for p in values.chunks_exact(3) {
                line.clear();
                line.extend_from_slice(tag);
                for x in p {
                    line.push(b' ');
                    line.extend_from_slice(number.format(*x).as_bytes());
                }
                line.push(b'\n');
                out.write_all(&line)?;
            }
            Ok(())
        };
        rows(self.out, b"v", piece.positions)?;
        if let Some(normals) = piece.normals {
            rows(&mut self.normals, b"vn", normals)?;
        }
        for t in piece.triangles {
            let [a, b, c] = t.map(|i| self.first + u64::from(i));
            if piece.normals.is_some() {
                writeln!(self.faces, "f {a}//{a} {b}//{b} {c}//{c}")?;
            } else {
                writeln!(self.faces, "f {a} {b} {c}")?;
            }
        }
        self.vertices += piece.vertices() as u64;
        Ok(())
    }

    /// Closes the open object: its normals and faces after its vertices.
    ///
    /// # Errors
    /// Any I/O error of the output or of a spill.
    pub fn end(&mut self) -> io::Result<()> {
        self.normals.drain_into(self.out)?;
        self.faces.drain_into(self.out)?;
        self.first += std::mem::take(&mut self.vertices);
        Ok(())
    }
}

/// Values as glTF's little-endian f32.
fn f32_bytes<F: Copy + Into<f64>>(values: &[F]) -> impl Iterator<Item = [u8; 4]> + '_ {
    values.iter().map(|&x| (x.into() as f32).to_le_bytes())
}

/// A mesh of a .glb as it is written: its name, counts, whether it has normals, and its
/// positions' bounds (glTF's accessor min and max).
#[derive(Debug)]
struct GlbMesh {
    name: String,
    vertices: u64,
    triangles: u64,
    normals: bool,
    low: [f32; 3],
    high: [f32; 3],
}

/// A glTF 2.0 binary file written mesh by mesh, each mesh in one piece or several. glTF holds
/// positions and normals as f32 and indices as u32: one buffer (every mesh's positions, then
/// every mesh's normals, then every mesh's indices, each array a view), a mesh (one triangle
/// primitive) and a node per mesh, one scene. The JSON that leads the file needs the
/// positions' bounds, known only when every piece has come: the binary chunk waits in three
/// spills until [`GlbWriter::finish`]. A mesh with no vertex (a dash pattern may leave a curve
/// nothing) is left out: glTF's accessors hold at least one element.
#[derive(Debug, Default)]
pub struct GlbWriter {
    meshes: Vec<GlbMesh>,
    positions: Spill,
    normals: Spill,
    indices: Spill,
}

impl GlbWriter {
    /// No mesh yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one mesh, whole.
    ///
    /// # Errors
    /// Any I/O error of a spill.
    pub fn mesh<F: Copy + Into<f64>>(&mut self, mesh: &Mesh<'_, F>) -> io::Result<()> {
        self.begin(&mesh.name, mesh.normals.is_some());
        self.piece(mesh)
    }

    /// Opens a mesh named `name` (with normals when `normals`), whose pieces follow.
    pub fn begin(&mut self, name: &str, normals: bool) {
        self.meshes.push(GlbMesh {
            name: name.to_owned(),
            vertices: 0,
            triangles: 0,
            normals,
            low: [f32::INFINITY; 3],
            high: [f32::NEG_INFINITY; 3],
        });
    }

    /// A piece of the open mesh: its vertices follow the pieces' before, its triangles index
    /// the whole mesh's vertices (`piece.name` is not used).
    ///
    /// # Errors
    /// Any I/O error of a spill.
    ///
    /// # Panics
    /// If no mesh is open.
    pub fn piece<F: Copy + Into<f64>>(&mut self, piece: &Mesh<'_, F>) -> io::Result<()> {
        let mesh = self.meshes.last_mut().expect("a mesh is open");
        let mut block = Vec::with_capacity(1 << 16);
        let mut put = |spill: &mut Spill, values: &mut dyn Iterator<Item = [u8; 4]>| {
            for bytes in values {
                block.extend_from_slice(&bytes);
                if block.len() >= 1 << 16 {
                    spill.write_all(&block)?;
                    block.clear();
                }
            }
            spill.write_all(&block)?;
            block.clear();
            io::Result::Ok(())
        };
        for p in piece.positions.chunks_exact(3) {
            for (k, &x) in p.iter().enumerate() {
                let x = x.into() as f32;
                mesh.low[k] = mesh.low[k].min(x);
                mesh.high[k] = mesh.high[k].max(x);
            }
        }
        put(&mut self.positions, &mut f32_bytes(piece.positions))?;
        if mesh.normals {
            put(
                &mut self.normals,
                &mut f32_bytes(piece.normals.unwrap_or_default()),
            )?;
        }
        let indices = piece.triangles.iter().flatten().map(|i| i.to_le_bytes());
        put(&mut self.indices, &mut indices.into_iter())?;
        mesh.vertices += piece.vertices() as u64;
        mesh.triangles += piece.triangles.len() as u64;
        Ok(())
    }

    /// Writes the file: the JSON, then the binary chunk from the spills.
    ///
    /// # Errors
    /// Any I/O error of `out` (a closed pipe keeps its kind, `BrokenPipe`) or of a spill, or a
    /// file over the format's 4 GiB.
    pub fn finish(mut self, out: &mut dyn Write) -> io::Result<()> {
        let mut root = json::Root::default();
        let written: Vec<&GlbMesh> = self.meshes.iter().filter(|m| m.vertices > 0).collect();
        let vec3_bytes = |m: &GlbMesh| 12 * m.vertices;
        // Where each array's region starts: positions, normals, indices.
        let positions: u64 = written.iter().map(|m| vec3_bytes(m)).sum();
        let normals: u64 = written
            .iter()
            .filter(|m| m.normals)
            .map(|m| vec3_bytes(m))
            .sum();
        let indices: u64 = written.iter().map(|m| 12 * m.triangles).sum();
        let bin_length = positions + normals + indices;
        let mut at = [0, positions, positions + normals];
        let buffer = json::Index::<json::Buffer>::new(0);
        let mut view = |root: &mut json::Root,
                        region: usize,
                        length: u64,
                        target: json::buffer::Target,
                        stride: Option<usize>| {
            // Every view is a whole number of 4-byte values: no padding between them.
            let offset = at[region];
            at[region] += length;
            root.push(json::buffer::View {
                buffer,
                byte_length: USize64(length),
                byte_offset: Some(USize64(offset)),
                byte_stride: stride.map(json::buffer::Stride),
                name: None,
                target: Some(Valid(target)),
                extensions: None,
                extras: Default::default(),
            })
        };
        let accessor = |root: &mut json::Root,
                        view: json::Index<json::buffer::View>,
                        count: u64,
                        component: json::accessor::ComponentType,
                        type_: json::accessor::Type,
                        bounds: Option<([f32; 3], [f32; 3])>| {
            root.push(json::Accessor {
                buffer_view: Some(view),
                byte_offset: Some(USize64(0)),
                count: USize64(count),
                component_type: Valid(json::accessor::GenericComponentType(component)),
                extensions: None,
                extras: Default::default(),
                type_: Valid(type_),
                min: bounds.map(|b| json::Value::from(b.0.to_vec())),
                max: bounds.map(|b| json::Value::from(b.1.to_vec())),
                name: None,
                normalized: false,
                sparse: None,
            })
        };
        let mut nodes = Vec::new();
        for mesh in &written {
            let array = json::buffer::Target::ArrayBuffer;
            let f32_type = json::accessor::ComponentType::F32;
            let vec3 = json::accessor::Type::Vec3;
            let v = view(&mut root, 0, vec3_bytes(mesh), array, Some(12));
            let bounds = Some((mesh.low, mesh.high));
            let a = accessor(&mut root, v, mesh.vertices, f32_type, vec3, bounds);
            let mut attributes = BTreeMap::new();
            attributes.insert(Valid(json::mesh::Semantic::Positions), a);
            if mesh.normals {
                let v = view(&mut root, 1, vec3_bytes(mesh), array, Some(12));
                let a = accessor(&mut root, v, mesh.vertices, f32_type, vec3, None);
                attributes.insert(Valid(json::mesh::Semantic::Normals), a);
            }
            let element = json::buffer::Target::ElementArrayBuffer;
            let v = view(&mut root, 2, 12 * mesh.triangles, element, None);
            let indices = accessor(
                &mut root,
                v,
                3 * mesh.triangles,
                json::accessor::ComponentType::U32,
                json::accessor::Type::Scalar,
                None,
            );
            let primitive = root.push(json::Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(mesh.name.clone()),
                primitives: vec![json::mesh::Primitive {
                    attributes,
                    extensions: None,
                    extras: Default::default(),
                    indices: Some(indices),
                    material: None,
                    mode: Valid(json::mesh::Mode::Triangles),
                    targets: None,
                }],
                weights: None,
            });
            nodes.push(root.push(json::Node {
                mesh: Some(primitive),
                name: Some(mesh.name.clone()),
                ..Default::default()
            }));
        }
        root.push(json::Buffer {
            byte_length: USize64(bin_length),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        let scene = root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes,
        });
        root.scene = Some(scene);
        let mut text = json::serialize::to_vec(&root).map_err(io::Error::other)?;
        // The JSON chunk is padded with spaces to 4 bytes (glTF 2.0, "Binary glTF Layout").
        text.resize(text.len().next_multiple_of(4), b' ');
        let length = 12 + 8 + text.len() as u64 + 8 + bin_length;
        let length = u32::try_from(length)
            .map_err(|_| io::Error::other("a .glb file holds at most 4 GiB"))?;
        let mut head = Vec::with_capacity(20);
        head.extend_from_slice(b"glTF");
        head.extend_from_slice(&2u32.to_le_bytes());
        head.extend_from_slice(&length.to_le_bytes());
        head.extend_from_slice(&(text.len() as u32).to_le_bytes());
        head.extend_from_slice(b"JSON");
        out.write_all(&head)?;
        out.write_all(&text)?;
        out.write_all(&(bin_length as u32).to_le_bytes())?;
        out.write_all(b"BIN\0")?;
        self.positions.drain_into(out)?;
        self.normals.drain_into(out)?;
        self.indices.drain_into(out)
    }
}
