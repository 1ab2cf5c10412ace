//! The WGSL kernel, checked with naga where no GPU is needed: it parses and validates, its
//! structs match their Rust twins byte for byte, and its workgroup size is `WG_SIZE`.

use std::mem::{offset_of, size_of};

use super::*;

fn module() -> (naga::Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(EVAL_WGSL).expect("eval.wgsl parses");
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("eval.wgsl validates");
    (module, info)
}

/// (size, [(member name, offset)]) of the WGSL struct `name`.
fn wgsl_struct(module: &naga::Module, name: &str) -> (u32, Vec<(String, u32)>) {
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name} in eval.wgsl"))
        .1;
    match &ty.inner {
        naga::TypeInner::Struct { members, span } => (
            *span,
            members
                .iter()
                .map(|m| (m.name.clone().unwrap(), m.offset))
                .collect(),
        ),
        other => panic!("{name} is not a struct: {other:?}"),
    }
}

macro_rules! assert_twin {
    ($module:expr, $wgsl:literal, $rust:ty, [$($field:ident),*]) => {{
                let (size, mut members) = wgsl_struct($module, $wgsl);
        // Padding members are checked by the size alone.
        members.retain(|(name, _)| !name.starts_with("_padding"));
        assert_eq!(size as usize, size_of::<$rust>(), "size of {}", $wgsl);
        let rust: Vec<(String, u32)> = vec![$((stringify!($field).to_string(), offset_of!($rust, $field) as u32)),*];
        assert_eq!(members, rust, "members of {}", $wgsl);
    }};
}

#[test]
fn every_wgsl_file_validates() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    let mut files = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let source = std::fs::read_to_string(&path).unwrap();
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::default(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
            files += 1;
        }
    }
    assert_eq!(
        files, 6,
        "eval.wgsl, store_only.wgsl, surface.wgsl, geometry.wgsl, closest.wgsl and surface_queries.wgsl"
    );
}

#[test]
fn structs_match_their_rust_twins() {
    let (module, _) = module();
    assert_twin!(
        &module,
        "Params",
        Params,
        [
            run_count,
            row_width,
            plane_stride,
            derivatives,
            out_base,
            first_run
        ]
    );
    assert_twin!(&module, "GpuSegment", GpuSegment, [coeff_offset, dim]);
    assert_twin!(
        &module,
        "Run",
        Run,
        [
            segment, segments, out_offset, count, mode, u0, du, first_loc, arc, first
        ]
    );
    assert_twin!(&module, "GpuLoc", GpuLoc, [segment, u]);
}

#[test]
fn workgroup_size_is_wg_size() {
    let (module, _) = module();
    let entry = module
        .entry_points
        .iter()
        .find(|e| e.name == ENTRY_POINT)
        .expect("entry point");
    assert_eq!(entry.stage, naga::ShaderStage::Compute);
    assert_eq!(entry.workgroup_size, [WG_SIZE, 1, 1]);
}

#[test]
fn run_modes_match_the_wgsl_constants() {
    let (module, _) = module();
    let constant = |name: &str| {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap();
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref other => panic!("{name} = {other:?}"),
        }
    };
    assert_eq!(constant("MODE_VECTOR"), MODE_VECTOR);
    assert_eq!(constant("MODE_EXPLICIT"), MODE_EXPLICIT);
    assert_eq!(constant("MODE_ARC"), MODE_ARC);
}

#[test]
fn lanes_and_mode_are_overrides() {
    let (module, _) = module();
    for name in [LANES_CONSTANT, MODE_CONSTANT, RATIONAL_CONSTANT] {
        assert!(
            module
                .overrides
                .iter()
                .any(|(_, o)| o.name.as_deref() == Some(name)),
            "{name}"
        );
    }
}

#[test]
fn bindings_match_the_rust_binding_list() {
    let (module, _) = module();
    let mut declared: Vec<(u32, String, naga::AddressSpace, u32)> = module
        .global_variables
        .iter()
        .filter_map(|(_, var)| {
            let binding = var.binding.as_ref()?;
            assert_eq!(binding.group, 0, "one bind group");
            // The bytes one binding holds at least: the struct's size, or one array element's.
            let least = match &module.types[var.ty].inner {
                naga::TypeInner::Array { stride, .. } => *stride,
                naga::TypeInner::Struct { span, .. } => *span,
                other => panic!("binding {} of type {other:?}", binding.binding),
            };
            let name = var.name.clone().unwrap();
            Some((binding.binding, name, var.space, least))
        })
        .collect();
    declared.sort_by_key(|d| d.0);
    assert_eq!(declared.len(), BINDINGS.len(), "{declared:?}");
    for (i, ((binding, name, space, least), (ty, role, min_size))) in
        declared.into_iter().zip(BINDINGS).enumerate()
    {
        assert_eq!(binding as usize, i, "bindings numbered 0, 1, ... in order");
        assert_eq!(name, role, "binding {i}");
        let expected = match ty {
            wgpu::BufferBindingType::Uniform => naga::AddressSpace::Uniform,
            wgpu::BufferBindingType::Storage { read_only } => naga::AddressSpace::Storage {
                access: if read_only {
                    naga::StorageAccess::LOAD
                } else {
                    naga::StorageAccess::LOAD | naga::StorageAccess::STORE
                },
            },
        };
        assert_eq!(space, expected, "binding {i} ({role})");
        assert_eq!(u64::from(least), min_size, "min_binding_size of {role}");
    }
}

/// `shaders/surface.wgsl`, parsed and validated.
fn surface_module() -> naga::Module {
    let module = naga::front::wgsl::parse_str(crate::gpu::surfaces::abi::SURFACE_WGSL)
        .expect("surface.wgsl parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("surface.wgsl validates");
    module
}

#[test]
fn surface_structs_match_their_rust_twins_and_the_workgroup_size() {
    use crate::gpu::surfaces::abi::{GpuPatch, GpuVertex, SURFACE_WG_SIZE, SurfaceParams};
    let module = surface_module();
    assert_twin!(
        &module,
        "SurfaceParams",
        SurfaceParams,
        [vertex_count, row_width, plane_stride, derivatives, normals]
    );
    assert_twin!(
        &module,
        "GpuPatch",
        GpuPatch,
        [coeff_offset, dim, rational, normal_offset, inv_du, inv_dv]
    );
    assert_twin!(&module, "GpuVertex", GpuVertex, [patch_index, out, u, v]);
    let entry = module
        .entry_points
        .iter()
        .find(|e| e.name == "main")
        .expect("entry point main");
    assert_eq!(entry.workgroup_size, [SURFACE_WG_SIZE, 1, 1]);
}

/// `shaders/geometry.wgsl`: its structs match their Rust twins, its workgroup size is
/// `GEOMETRY_WG_SIZE`, and its bindings are `GEOMETRY_BINDINGS` in order.
#[test]
fn geometry_structs_bindings_and_workgroup_size_match_their_rust_twins() {
    use crate::gpu::geometry::abi::{
        GEOMETRY_BINDINGS, GEOMETRY_WG_SIZE, GEOMETRY_WGSL, GeometryParams, GpuMeshCurve,
        GpuSection, GpuStrokeVertex, SHAPE_STROKE,
    };
    let module = naga::front::wgsl::parse_str(GEOMETRY_WGSL).expect("geometry.wgsl parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("geometry.wgsl validates");
    assert_twin!(
        &module,
        "GeometryParams",
        GeometryParams,
        [
            curve_count,
            row_width,
            out_base,
            stroke_vertex_count,
            stroke_row_width
        ]
    );
    assert_twin!(
        &module,
        "GpuMeshCurve",
        GpuMeshCurve,
        [
            first_block,
            block_vec4s,
            rational,
            first_section,
            sections,
            shape,
            sides,
            closed,
            first_vertex,
            origin_hi,
            origin_lo,
            n0,
            t_first
        ]
    );
    assert_twin!(
        &module,
        "GpuSection",
        GpuSection,
        [segment, u, along, first_vertex, cap_vertex, cap_sign]
    );
    assert_twin!(
        &module,
        "GpuStrokeVertex",
        GpuStrokeVertex,
        [curve, vertex, segment, u, v]
    );
    for name in ["main", "strokes"] {
        let entry = module
            .entry_points
            .iter()
            .find(|e| e.name == name)
            .unwrap_or_else(|| panic!("entry point {name}"));
        assert_eq!(entry.workgroup_size, [GEOMETRY_WG_SIZE, 1, 1], "{name}");
    }
    assert!(
        GEOMETRY_WGSL.contains(&format!("if curve.shape == {SHAPE_STROKE}u {{")),
        "SHAPE_STROKE is the Rust twin's"
    );
    assert!(
        GEOMETRY_WGSL.contains(&format!(
            "const NONE: u32 = 0x{:x}u;",
            crate::gpu::geometry::abi::NONE
        )),
        "NONE is the Rust twin's"
    );
    let mut spaces: Vec<(u32, naga::AddressSpace)> = module
        .global_variables
        .iter()
        .filter_map(|(_, var)| Some((var.binding.as_ref()?.binding, var.space)))
        .collect();
    spaces.sort_by_key(|b| b.0);
    let want: Vec<(u32, naga::AddressSpace)> = GEOMETRY_BINDINGS
        .iter()
        .enumerate()
        .map(|(i, ty)| {
            let space = match ty {
                wgpu::BufferBindingType::Uniform => naga::AddressSpace::Uniform,
                wgpu::BufferBindingType::Storage { read_only: true } => {
                    naga::AddressSpace::Storage {
                        access: naga::StorageAccess::LOAD,
                    }
                }
                wgpu::BufferBindingType::Storage { read_only: false } => {
                    naga::AddressSpace::Storage {
                        access: naga::StorageAccess::LOAD | naga::StorageAccess::STORE,
                    }
                }
            };
            (i as u32, space)
        })
        .collect();
    assert_eq!(spaces, want);
}
