//! Triangle meshes in the files a viewer opens as they are: Wavefront .obj (streamed, an
//! object per mesh) and glTF 2.0 binary (.glb, through the gltf crate's schema types and
//! container, rather than hand-written offsets and padding). Surfaces and the curves' geometry
//! both write through here.

use std::collections::BTreeMap;
use std::io::{self, Write};

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

/// A Wavefront .obj file written mesh by mesh: `o name`, `v`, `vn`, `f` lines, indices
/// counted across the file from 1.
pub struct ObjWriter<'w> {
    out: &'w mut dyn Write,
    first: u64,
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
        Ok(Self { out, first: 1 })
    }

    /// Writes one mesh as an object of its own.
    ///
    /// # Errors
    /// Any I/O error of the output.
    pub fn mesh<F: zmij::Float + Copy>(&mut self, mesh: &Mesh<'_, F>) -> io::Result<()> {
        let out = &mut *self.out;
        let mut number = zmij::Buffer::new();
        writeln!(out, "o {}", mesh.name)?;
        let mut rows = |tag: &[u8], values: &[F]| -> io::Result<()> {
            for p in values.chunks_exact(3) {
                out.write_all(tag)?;
                for x in p {
                    out.write_all(b" ")?;
                    out.write_all(number.format(*x).as_bytes())?;
                }
                out.write_all(b"\n")?;
            }
            Ok(())
        };
        rows(b"v", mesh.positions)?;
        if let Some(normals) = mesh.normals {
            rows(b"vn", normals)?;
        }
        for t in mesh.triangles {
            let [a, b, c] = t.map(|i| self.first + u64::from(i));
            if mesh.normals.is_some() {
                writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
            } else {
                writeln!(out, "f {a} {b} {c}")?;
            }
        }
        self.first += mesh.vertices() as u64;
        Ok(())
    }
}

/// glTF holds positions and normals as f32 and indices as u32: one buffer, a view per array,
/// a mesh (one triangle primitive) and a node per mesh, one scene. A mesh with no vertex (a
/// dash pattern may leave a curve nothing) is left out: glTF's accessors hold at least one
/// element.
///
/// # Errors
/// Any I/O error of `out` (a closed pipe keeps its kind, `BrokenPipe`), or a file over the
/// format's 4 GiB.
pub fn write_glb<F: Copy + Into<f64>>(
    meshes: &[Mesh<'_, F>],
    out: &mut dyn Write,
) -> io::Result<()> {
    // The JSON first, from the counts alone (and the positions' bounds): every view's offset
    // is known before a byte of the binary chunk is, so the binary chunk is streamed, mesh by
    // mesh, and memory stays near one write buffer however large the meshes are.
    let mut root = json::Root::default();
    let mut nodes = Vec::new();
    let mut bin_length = 0u64;
    let buffer = json::Index::<json::Buffer>::new(0);
    let mut view = |root: &mut json::Root,
                    length: u64,
                    target: json::buffer::Target,
                    stride: Option<usize>| {
        // Every view is a whole number of 4-byte values: no padding between them.
        let offset = bin_length;
        bin_length += length;
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
                    count: usize,
                    component: json::accessor::ComponentType,
                    type_: json::accessor::Type,
                    bounds: Option<([f32; 3], [f32; 3])>| {
        root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: Some(USize64(0)),
            count: USize64(count as u64),
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
    let written: Vec<&Mesh<'_, F>> = meshes.iter().filter(|m| m.vertices() > 0).collect();
    for mesh in &written {
        let (mut low, mut high) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in mesh.positions.chunks_exact(3) {
            for k in 0..3 {
                let x = p[k].into() as f32;
                low[k] = low[k].min(x);
                high[k] = high[k].max(x);
            }
        }
        let array = json::buffer::Target::ArrayBuffer;
        let count = mesh.vertices();
        let vec3_bytes = 12 * count as u64;
        let v = view(&mut root, vec3_bytes, array, Some(12));
        let mut attributes = BTreeMap::new();
        let f32_type = json::accessor::ComponentType::F32;
        let vec3 = json::accessor::Type::Vec3;
        let a = accessor(&mut root, v, count, f32_type, vec3, Some((low, high)));
        attributes.insert(Valid(json::mesh::Semantic::Positions), a);
        if mesh.normals.is_some() {
            let v = view(&mut root, vec3_bytes, array, Some(12));
            let a = accessor(&mut root, v, count, f32_type, vec3, None);
            attributes.insert(Valid(json::mesh::Semantic::Normals), a);
        }
        let element = json::buffer::Target::ElementArrayBuffer;
        let v = view(&mut root, 12 * mesh.triangles.len() as u64, element, None);
        let u32_type = json::accessor::ComponentType::U32;
        let indices = accessor(
            &mut root,
            v,
            3 * mesh.triangles.len(),
            u32_type,
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
    let length =
        u32::try_from(length).map_err(|_| io::Error::other("a .glb file holds at most 4 GiB"))?;
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
    // The binary chunk, in the views' order, through one buffer.
    let mut chunk = Vec::with_capacity(1 << 16);
    let put = |chunk: &mut Vec<u8>, bytes: [u8; 4], out: &mut dyn Write| -> io::Result<()> {
        chunk.extend_from_slice(&bytes);
        if chunk.len() >= 1 << 16 {
            out.write_all(chunk)?;
            chunk.clear();
        }
        Ok(())
    };
    for mesh in &written {
        for &x in mesh.positions {
            put(&mut chunk, (x.into() as f32).to_le_bytes(), out)?;
        }
        for &x in mesh.normals.unwrap_or(&[]) {
            put(&mut chunk, (x.into() as f32).to_le_bytes(), out)?;
        }
        for &i in mesh.triangles.iter().flatten() {
            put(&mut chunk, i.to_le_bytes(), out)?;
        }
    }
    out.write_all(&chunk)
}
