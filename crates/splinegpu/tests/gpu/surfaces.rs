//! Surfaces on the GPU against the f64 reference, under the contract's surface promise
//! (`splinegpu::accuracy::surface_gpu_bound`): every kind in one call, nets near 1e5, knot
//! spacing ratios of 1e3, a rational torus, the teapot's certified mesh with its poles, all
//! derivatives and normals, and the renderer's recording. Run under the GPU harness (lavapipe in CI).

use crate::shapes::{teapot, torus_surface};
use crate::support::{Rng, gpu, surface_job};
use splinegpu::accuracy::surface_gpu_bound;
use splinegpu::surface::{
    Net, PatchTable, Surface, SurfaceKind, SurfacePlan, SurfaceSamples, SurfaceSampling,
};
use splinegpu::{Basis, Derivatives, EndCondition, Ends};

fn net(rng: &mut Rng, rows: usize, cols: usize, center: f64) -> Net {
    let coords = (0..rows * cols * 3)
        .map(|_| center + rng.range(-2.0, 2.0))
        .collect();
    Net::new(3, rows, cols, coords).unwrap()
}

/// Every kind, some near 1e5, uneven knots, each with its sampling.
fn surfaces() -> Vec<(Surface, SurfaceSampling)> {
    let mut rng = Rng(50);
    let mut out = Vec::new();
    for (center, basis, ends) in [
        (0.0, Basis::BSpline, [Ends::Closed, Ends::Closed]),
        (1e5, Basis::CatmullRom, [Ends::Control, Ends::Repeat]),
        (
            -3e4,
            Basis::Beta {
                bias: 1.5,
                tension: 2.0,
            },
            [Ends::Repeat, Ends::Closed],
        ),
    ] {
        let kind = SurfaceKind::Uniform { basis, ends };
        let surface = Surface::new(kind, net(&mut rng, 6, 5, center)).unwrap();
        out.push((surface, SurfaceSampling::PerSegment([5, 4])));
    }
    out.push((
        Surface::new(SurfaceKind::Bezier, net(&mut rng, 7, 4, 1e5)).unwrap(),
        SurfaceSampling::Tolerance(0.05),
    ));
    // Knot spacings 1e3 apart along u and v.
    let kind = SurfaceKind::Interpolating {
        conditions: [EndCondition::NotAKnot, EndCondition::Natural],
        u: Some(vec![0.0, 1e-3, 1.0, 1.001, 2.0, 3.0]),
        v: Some(vec![0.0, 1.0, 1e3, 1e3 + 1.0, 2e3]),
    };
    out.push((
        Surface::new(kind, net(&mut rng, 6, 5, 0.0)).unwrap(),
        SurfaceSampling::PerSegment([6, 6]),
    ));
    let kind = SurfaceKind::Nurbs {
        knots_u: vec![0.0, 0.0, 0.0, 0.0, 1e-3, 1.0, 1.0, 1.0, 1.0],
        knots_v: vec![5.0, 5.0, 5.0, 5.0, 6.0, 6.0, 6.0, 6.0],
        weights: Some((0..20).map(|i| 0.5 + f64::from(i % 7) * 0.25).collect()),
    };
    out.push((
        Surface::new(kind, net(&mut rng, 5, 4, 1e5)).unwrap(),
        SurfaceSampling::PerSegment([7, 3]),
    ));
    out.push((
        torus_surface(3.0, 1.0, [1e5, 0.0, -1e5]),
        SurfaceSampling::Tolerance(1e-2),
    ));
    out.push((teapot(), SurfaceSampling::Tolerance(6e-3)));
    out
}

/// The worst error over the bound per derivative (S, Su, Sv, Suu, Suv, Svv), and the worst
/// normal angle where the contract promises one.
fn compare(
    table: &PatchTable,
    plan: &SurfacePlan,
    cpu: &SurfaceSamples,
    gpu: &SurfaceSamples<f32>,
    worst: &mut [f64; 7],
) {
    let dim = table.dim();
    let planes = [
        (&cpu.points, &gpu.points),
        (cpu.du.as_ref().unwrap(), gpu.du.as_ref().unwrap()),
        (cpu.dv.as_ref().unwrap(), gpu.dv.as_ref().unwrap()),
        (cpu.duu.as_ref().unwrap(), gpu.duu.as_ref().unwrap()),
        (cpu.duv.as_ref().unwrap(), gpu.duv.as_ref().unwrap()),
        (cpu.dvv.as_ref().unwrap(), gpu.dvv.as_ref().unwrap()),
    ];
    for (i, vertex) in plan.vertices.iter().enumerate() {
        let patch = table.patch(vertex.patch as usize);
        for (m, (c, g)) in planes.iter().enumerate() {
            for k in 0..dim {
                let (want, got) = (c[i * dim + k], f64::from(g[i * dim + k]));
                let bound = surface_gpu_bound(&patch, table.extent(), m, k, want);
                let ratio = (got - want).abs() / bound;
                worst[m] = worst[m].max(ratio);
                assert!(
                    ratio <= 1.0,
                    "vertex {i} (patch {}, {:?}) derivative {m} coordinate {k}: gpu {got}, \
                     cpu {want}, bound {bound}",
                    vertex.patch,
                    vertex.local
                );
            }
        }
        let (cn, gn) = (cpu.normals.as_ref().unwrap(), gpu.normals.as_ref().unwrap());
        let g: Vec<f64> = gn[3 * i..3 * i + 3].iter().map(|&x| f64::from(x)).collect();
        let length = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        assert!((length - 1.0).abs() < 1e-5, "vertex {i}: |n| = {length}");
        let (du, dv) = (
            &cpu.du.as_ref().unwrap()[3 * i..],
            &cpu.dv.as_ref().unwrap()[3 * i..],
        );
        let cross = [
            du[1] * dv[2] - du[2] * dv[1],
            du[2] * dv[0] - du[0] * dv[2],
            du[0] * dv[1] - du[1] * dv[0],
        ];
        let norm = |v: &[f64]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        // The contract's degenerate points (a collapsed edge, a pole): |Su x Sv| at most 1e-10
        // s_u s_v in local u, v. There it promises a finite unit normal; the GPU's is the limit
        // taken a thousandth of the way in, so it stays near the reference's.
        let [lu, lv] = patch.length();
        let [su, sv] = patch.derivative_sizes();
        let dot = |g: &[f64]| (0..3).map(|k| g[k] * cn[3 * i + k]).sum::<f64>() / length;
        if norm(&cross) * lu * lv <= 1e-10 * su * sv {
            let angle = dot(&g).clamp(-1.0, 1.0).acos();
            assert!(
                angle < 0.05,
                "vertex {i} (patch {}, {:?}, uv {:?}): degenerate normal {angle} radians off: \
                 gpu {g:?}, cpu {:?}; du {:?} dv {:?}",
                vertex.patch,
                vertex.local,
                vertex.uv,
                &cn[3 * i..3 * i + 3],
                &du[..3],
                &dv[..3]
            );
            continue;
        }
        if norm(&cross) >= 1e-2 * norm(&du[..3]) * norm(&dv[..3]) {
            let angle = dot(&g).clamp(-1.0, 1.0).acos();
            worst[6] = worst[6].max(angle / 1e-3);
            assert!(
                angle <= 1e-3,
                "vertex {i} (patch {}, {:?}, uv {:?}): normal {angle} radians off (gpu {g:?}, cpu \
                 {:?}); du {:?} dv {:?}",
                vertex.patch,
                vertex.local,
                vertex.uv,
                &cn[3 * i..3 * i + 3],
                &du[..3],
                &dv[..3]
            );
        }
    }
}

pub(crate) fn gpu_surfaces_of_every_kind_in_one_call_keep_the_promise() {
    let Some(gpu) = gpu() else { return };
    let surfaces = surfaces();
    let tables: Vec<PatchTable> = surfaces.iter().map(|(s, _)| s.fit()).collect();
    let pairs: Vec<_> = tables.iter().zip(surfaces.iter().map(|(_, s)| s)).collect();
    let job = surface_job(&pairs, Derivatives::Second, true);
    let on_gpu = gpu.evaluate_surfaces(&job).unwrap();
    let on_cpu = job.evaluate_cpu();
    let mut worst = [0.0f64; 7];
    let names = [
        "bspline closed x closed",
        "catmull-rom near 1e5",
        "beta near -3e4",
        "bezier net near 1e5, tolerance",
        "interpolating, spacings 1e3 apart",
        "rational nurbs near 1e5",
        "rational torus at 1e5, tolerance",
        "teapot, tolerance",
    ];
    for (((surface, cpu), g), name) in job.surfaces().iter().zip(&on_cpu).zip(&on_gpu).zip(names) {
        assert_eq!(g.uv, cpu.uv);
        assert_eq!(g.triangles, cpu.triangles);
        let mut own = [0.0f64; 7];
        compare(surface.table(), &surface.plan(), cpu, g, &mut own);
        eprintln!(
            "{name}: worst fraction of the bound {:.3?}, normals {:.3} of 1e-3 rad",
            &own[..6],
            own[6]
        );
        for (w, o) in worst.iter_mut().zip(own) {
            *w = w.max(o);
        }
    }
    eprintln!(
        "surfaces on the GPU: worst fraction of the bound {:.3?} (S, Su, Sv, Suu, Suv, Svv), \
         normals {:.3} of 1e-3 rad",
        &worst[..6],
        worst[6]
    );
}

pub(crate) fn gpu_surfaces_without_derivatives_give_positions_only() {
    let Some(gpu) = gpu() else { return };
    let (surface, sampling) = surfaces().swap_remove(1);
    let table = surface.fit();
    let job = surface_job(&[(&table, &sampling)], Derivatives::None, false);
    let plan = job.surfaces()[0].plan();
    let g = &gpu.evaluate_surfaces(&job).unwrap()[0];
    assert!(g.du.is_none() && g.normals.is_none());
    let cpu = &job.evaluate_cpu()[0];
    for (i, (c, g)) in cpu.points.iter().zip(&g.points).enumerate() {
        let patch = table.patch(plan.vertices[i / 3].patch as usize);
        assert!(
            (f64::from(*g) - c).abs() <= surface_gpu_bound(&patch, table.extent(), 0, i % 3, *c)
        );
    }
}

/// Reads `bytes` of `buffer` back (the test's own readback; the renderer path reads nothing).
pub(crate) fn read_back(
    gpu: &splinegpu::GpuContext,
    buffer: &splinegpu::wgpu::Buffer,
    bytes: u64,
) -> Vec<f32> {
    use splinegpu::wgpu;
    let download = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("test download"),
        size: bytes,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &download, 0, bytes);
    gpu.queue().submit([encoder.finish()]);
    download
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.unwrap());
    gpu.device()
        .poll(wgpu::PollType::wait_indefinitely())
        .unwrap();
    let view = download.slice(..).get_mapped_range().unwrap();
    bytemuck::cast_slice::<u8, f32>(&view).to_vec()
}

pub(crate) fn a_renderer_records_surfaces_into_its_own_buffers_and_refits_a_moving_net() {
    use splinegpu::wgpu;
    let Some(gpu) = gpu() else { return };
    let mut rng = Rng(60);
    let kind = SurfaceKind::Uniform {
        basis: Basis::BSpline,
        ends: [Ends::Closed, Ends::Closed],
    };
    let first = Surface::new(kind.clone(), net(&mut rng, 6, 5, 0.0)).unwrap();
    let teapot = teapot();
    let tables = [first.fit(), teapot.fit()];
    let samplings = [
        SurfaceSampling::PerSegment([4, 4]),
        SurfaceSampling::Tolerance(0.05),
    ];
    let job = surface_job(
        &[(&tables[0], &samplings[0]), (&tables[1], &samplings[1])],
        Derivatives::None,
        true,
    );
    let mut recording = gpu.surface_recording(&job).unwrap();
    let layout = recording.layout().clone();
    assert_eq!(
        recording.indices().len() as u32,
        *layout.index_starts.last().unwrap()
    );
    // The renderer's buffer: vertex data at an offset, as a vertex buffer would hold them.
    let offset = 256;
    let target = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("renderer vertices"),
        size: offset + layout.bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    for frame in 0..2 {
        if frame == 1 {
            // The net moves: refit, the plans stay.
            let moved = Surface::new(kind.clone(), net(&mut rng, 6, 5, 0.0))
                .unwrap()
                .fit();
            recording.refit(gpu, &[&moved, &tables[1]]).unwrap();
            let mut encoder = gpu.device().create_command_encoder(&Default::default());
            recording
                .record_into(gpu, &mut encoder, &target, offset)
                .unwrap();
            gpu.queue().submit([encoder.finish()]);
            let moved_job = surface_job(&[(&moved, &samplings[0])], Derivatives::None, true);
            let want = gpu.evaluate_surfaces(&moved_job).unwrap();
            let got = read_back(gpu, &target, offset + layout.bytes);
            let base = (offset / 4) as usize;
            let n = want[0].points.len();
            assert_eq!(&got[base..base + n], want[0].points.as_slice());
            continue;
        }
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        recording
            .record_into(gpu, &mut encoder, &target, offset)
            .unwrap();
        gpu.queue().submit([encoder.finish()]);
        let want = gpu.evaluate_surfaces(&job).unwrap();
        let got = read_back(gpu, &target, offset + layout.bytes);
        let base = (offset / 4) as usize;
        let points: Vec<f32> = want.iter().flat_map(|s| s.points.clone()).collect();
        let normals: Vec<f32> = want
            .iter()
            .flat_map(|s| s.normals.clone().unwrap())
            .collect();
        assert_eq!(&got[base..base + points.len()], points.as_slice());
        let at = base + (layout.normals.unwrap() / 4) as usize;
        assert_eq!(&got[at..at + normals.len()], normals.as_slice());
    }
    // Misuse is named.
    let err = recording.refit(gpu, &[&tables[1]]).unwrap_err().to_string();
    assert!(err.starts_with("surface 0: \"points\""), "{err}");
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    let small = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 64,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    assert!(recording.record_into(gpu, &mut encoder, &small, 0).is_err());
}

/// As on the CPU (tests/it/surface.rs): a vertex on the line between two patches is the later
/// patch's, the last line the last patch's at 1; each patch of `constant_patches` shows its
/// owner in the value.
pub(crate) fn a_vertex_between_two_patches_is_the_later_patchs_on_the_gpu() {
    use crate::shapes::{CONSTANT_PATCH_OWNERS, constant_patches};
    let Some(gpu) = gpu() else {
        return;
    };
    let (table, sampling) = (constant_patches(), SurfaceSampling::PerSegment([2, 2]));
    let job = surface_job(&[(&table, &sampling)], Derivatives::None, false);
    let g = &gpu.evaluate_surfaces(&job).unwrap()[0];
    let owner = CONSTANT_PATCH_OWNERS;
    for a in 0..5 {
        for b in 0..5 {
            let z = f64::from(g.points[3 * (5 * a + b) + 2]);
            assert_eq!(z, 10.0 * owner[a] + owner[b], "vertex ({a}, {b})");
        }
    }
}

/// Closest points on surfaces and rays on the GPU, against the certified answers
/// (tests/it/query/surface_checks.rs).
pub(crate) fn closest_points_and_rays_on_the_gpu_are_the_certified_ones_within_the_bound() {
    let gpu = gpu().expect("a GPU adapter");
    crate::surface_checks::check_against_the_certified_answers(
        &|index, queries| gpu.closest_on_surfaces(index, queries).unwrap(),
        &|index, rays| gpu.ray_hits(index, rays).unwrap(),
    );
}
