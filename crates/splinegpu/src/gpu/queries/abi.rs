//! The closest-point kernel's ABI (`shaders/closest.wgsl`): its source, its workgroup size,
//! its search constants and the Pod twins of its structs, each named as its WGSL struct
//! (checked against naga's layout by the tests at the end).

use bytemuck::{Pod, Zeroable};

/// `shaders/closest.wgsl`.
pub(crate) const CLOSEST_WGSL: &str = include_str!("../../../shaders/closest.wgsl");

/// The kernel's workgroup size; `const WG_SIZE` in the shader.
pub(crate) const CLOSEST_WG_SIZE: u32 = 64;

/// The most halvings of a piece's parameter; `const MAX_LEVEL` in the shader.
#[cfg(test)]
pub(crate) const MAX_LEVEL: u32 = 20;

/// The tree walk's stack; `const TREE_STACK`.
#[cfg(test)]
pub(crate) const TREE_STACK: usize = 40;

/// A piece's stack; `const PIECE_STACK`.
#[cfg(test)]
pub(crate) const PIECE_STACK: usize = 24;

/// Newton steps polishing an answer; `const POLISH_STEPS`.
#[cfg(test)]
pub(crate) const POLISH_STEPS: u32 = 4;

/// The search's slack in the index's frame (where the curves' extent is 1): a box or a piece's
/// sub-interval is left when nothing in it can be nearer than the best distance d by more
/// than `SLACK_ABSOLUTE + SLACK_RELATIVE · d` (docs/queries.md, "On the GPU").
pub(crate) const SLACK_ABSOLUTE: f32 = 1e-6;

/// See [`SLACK_ABSOLUTE`]: f32's resolution of d (2^-24) in the index's frame.
pub(crate) const SLACK_RELATIVE: f32 = 6e-8;

/// The kernel's bindings, in order: the uniform, the tree's nodes, the nodes' boxes, the
/// pieces' boxes, the pieces' control points and the queries (read), the answers and the
/// points (read-write).
pub(crate) const CLOSEST_BINDINGS: [wgpu::BufferBindingType; 8] = [
    wgpu::BufferBindingType::Uniform,
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: false },
    wgpu::BufferBindingType::Storage { read_only: false },
];

/// `shaders/surface_queries.wgsl`: closest points on surfaces (entry point `closest`) and the
/// first hits of rays (`rays`).
pub(crate) const SURFACE_QUERIES_WGSL: &str = include_str!("../../../shaders/surface_queries.wgsl");

/// Its workgroup size; `const WG_SIZE` there.
pub(crate) const SURFACE_QUERIES_WG_SIZE: u32 = 64;

/// Its most halvings of a patch's parameters; `const MAX_LEVEL` there.
#[cfg(test)]
pub(crate) const SURFACE_MAX_LEVEL: u32 = 15;

/// Its patch stack; `const PATCH_STACK` there.
#[cfg(test)]
pub(crate) const PATCH_STACK: usize = 48;

/// Its Newton steps; `const POLISH_STEPS` there.
#[cfg(test)]
pub(crate) const SURFACE_POLISH_STEPS: u32 = 6;

/// Its answer's slot where a ray meets nothing; `const NONE` there.
pub(crate) const NO_HIT: u32 = u32::MAX;

/// Its bindings, in order: the uniform, the tree's nodes, the nodes' boxes, the patches'
/// boxes, the patches' nets and the queries (read), the answers (read-write).
pub(crate) const SURFACE_QUERIES_BINDINGS: [wgpu::BufferBindingType; 7] = [
    wgpu::BufferBindingType::Uniform,
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: false },
];

/// Per-dispatch uniforms. WGSL twin: `ClosestParams` in `shaders/closest.wgsl`, and
/// `SurfaceQueryParams` in `shaders/surface_queries.wgsl` (the same layout).
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct ClosestParams {
    pub query_count: u32,
    pub dim: u32,
    pub row_width: u32,
    pub node_count: u32,
    pub tolerance: f32,
    pub relative: f32,
    pub _padding: [u32; 2],
}

impl ClosestParams {
    /// A dispatch of `queries` points of `dim` coordinates in rows of `row_width` invocations,
    /// on a tree of `nodes` nodes.
    pub(crate) fn new(queries: usize, dim: usize, row_width: u32, nodes: usize) -> Self {
        Self {
            query_count: queries as u32,
            dim: dim as u32,
            row_width,
            node_count: nodes as u32,
            tolerance: SLACK_ABSOLUTE,
            relative: SLACK_RELATIVE,
            _padding: [0; 2],
        }
    }
}

/// One surface query's answer. WGSL twin: `SurfaceAnswer`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct SurfaceAnswer {
    pub slot: u32,
    pub u: f32,
    pub v: f32,
    pub value: f32,
}

/// A node of the tree. WGSL twin: `GpuNode` (in both query shaders).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuNode {
    pub first: u32,
    pub second: u32,
    pub leaf: u32,
    pub _padding: u32,
}

/// One query's answer. WGSL twin: `ClosestAnswer`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct ClosestAnswer {
    pub slot: u32,
    pub u: f32,
    pub distance2: f32,
    pub _padding: u32,
}

#[cfg(test)]
mod tests {
    use std::mem::{offset_of, size_of};

    use super::*;

    fn module() -> naga::Module {
        parsed(CLOSEST_WGSL)
    }

    fn parsed(source: &str) -> naga::Module {
        let module = naga::front::wgsl::parse_str(source).expect("the shader parses");
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .expect("the shader validates");
        module
    }

    #[test]
    fn the_surface_kernels_structs_and_constants_match() {
        let module = parsed(SURFACE_QUERIES_WGSL);
        let (size, members) = wgsl_struct(&module, "SurfaceQueryParams");
        let (closest_size, closest_members) = wgsl_struct(&parsed(CLOSEST_WGSL), "ClosestParams");
        assert_eq!((size, members), (closest_size, closest_members));
        let (size, members) = wgsl_struct(&module, "SurfaceAnswer");
        assert_eq!(size, size_of::<SurfaceAnswer>());
        assert_eq!(
            members,
            named(&[
                ("slot", offset_of!(SurfaceAnswer, slot)),
                ("u", offset_of!(SurfaceAnswer, u)),
                ("v", offset_of!(SurfaceAnswer, v)),
                ("value", offset_of!(SurfaceAnswer, value)),
            ])
        );
        let (size, _) = wgsl_struct(&module, "GpuNode");
        assert_eq!(size, size_of::<GpuNode>());
        for entry in &module.entry_points {
            assert_eq!(entry.workgroup_size, [SURFACE_QUERIES_WG_SIZE, 1, 1]);
        }
        let names: Vec<&str> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        assert_eq!(names, ["closest", "rays"]);
        let constant = |name: &str| constant(&module, name);
        assert_eq!(constant("NONE"), NO_HIT);
        assert_eq!(constant("MAX_LEVEL"), SURFACE_MAX_LEVEL);
        assert_eq!(constant("PATCH_STACK") as usize, PATCH_STACK);
        assert_eq!(constant("POLISH_STEPS"), SURFACE_POLISH_STEPS);
        assert_eq!(constant("TREE_STACK") as usize, TREE_STACK);
    }

    /// (size, [(member, offset)]) of the WGSL struct `name`, padding members left out.
    fn wgsl_struct(module: &naga::Module, name: &str) -> (usize, Vec<(String, usize)>) {
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no struct {name} in closest.wgsl"));
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("{name} is not a struct");
        };
        let members = members
            .iter()
            .map(|m| (m.name.clone().unwrap(), m.offset as usize))
            .filter(|(n, _)| !n.starts_with("_padding"))
            .collect();
        (*span as usize, members)
    }

    /// The u32 value of the WGSL constant `name`.
    fn constant(module: &naga::Module, name: &str) -> u32 {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no const {name}"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref other => panic!("{name} = {other:?}"),
        }
    }

    fn named(fields: &[(&str, usize)]) -> Vec<(String, usize)> {
        fields.iter().map(|(n, o)| ((*n).to_string(), *o)).collect()
    }

    #[test]
    fn structs_match_their_rust_twins() {
        let module = module();
        let (size, members) = wgsl_struct(&module, "ClosestParams");
        assert_eq!(size, size_of::<ClosestParams>());
        assert_eq!(
            members,
            named(&[
                ("query_count", offset_of!(ClosestParams, query_count)),
                ("dim", offset_of!(ClosestParams, dim)),
                ("row_width", offset_of!(ClosestParams, row_width)),
                ("node_count", offset_of!(ClosestParams, node_count)),
                ("tolerance", offset_of!(ClosestParams, tolerance)),
                ("relative", offset_of!(ClosestParams, relative)),
            ])
        );
        let (size, members) = wgsl_struct(&module, "GpuNode");
        assert_eq!(size, size_of::<GpuNode>());
        assert_eq!(
            members,
            named(&[
                ("first", offset_of!(GpuNode, first)),
                ("second", offset_of!(GpuNode, second)),
                ("leaf", offset_of!(GpuNode, leaf)),
            ])
        );
        let (size, members) = wgsl_struct(&module, "ClosestAnswer");
        assert_eq!(size, size_of::<ClosestAnswer>());
        assert_eq!(
            members,
            named(&[
                ("slot", offset_of!(ClosestAnswer, slot)),
                ("u", offset_of!(ClosestAnswer, u)),
                ("distance2", offset_of!(ClosestAnswer, distance2)),
            ])
        );
    }

    #[test]
    fn constants_match_the_shader() {
        let module = module();
        let constant = |name: &str| constant(&module, name) as usize;
        assert_eq!(constant("WG_SIZE"), CLOSEST_WG_SIZE as usize);
        assert_eq!(constant("MAX_LEVEL"), MAX_LEVEL as usize);
        assert_eq!(constant("TREE_STACK"), TREE_STACK);
        assert_eq!(constant("PIECE_STACK"), PIECE_STACK);
        assert_eq!(constant("POLISH_STEPS"), POLISH_STEPS as usize);
        let entry = &module.entry_points[0];
        assert_eq!(entry.workgroup_size, [CLOSEST_WG_SIZE, 1, 1]);
    }
}
