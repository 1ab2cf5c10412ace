//! The f32 answers of closest points on surfaces and rays (the GPU's, and its kernel's twin's)
//! against the certified f64 ones. Shared by path with the GPU harness (tests/gpu/) and the
//! twin's unit tests (src/gpu/queries/).

use crate::shapes::{teapot, torus_surface};
use crate::support::Rng;
use splinegpu::query::{RayHit, SurfaceIndex, SurfacePoint};
use splinegpu::surface::{Net, PatchTable, Surface, SurfaceKind};

const R: f64 = 3.0;
const SMALL: f64 = 1.0;

/// Closest points answered in f32 (query points D values each).
pub(crate) type Closest = dyn Fn(&SurfaceIndex<'_>, &[f64]) -> Vec<SurfacePoint>;

/// Rays answered in f32 (6 values each).
pub(crate) type Rays = dyn Fn(&SurfaceIndex<'_>, &[f64]) -> Vec<Option<RayHit>>;

/// Closest points (`closest`) and rays (`rays`) answered in f32, on the GPU or by its twin,
/// against the certified f64 answers on the torus (rational), random nets and the teapot (a
/// patch list): each distance within 2e-5 E + 1e-5 |q|∞ of the certified one (the contract's
/// GPU bound is the patch's position bound, at least 1e-5 E, plus 1e-5 (E + |q|∞)); each ray
/// hits where the certified search hits, nowhere nearer by more than that, and misses where it
/// misses; a ray through the torus's hole meets nothing.
pub(crate) fn check_against_the_certified_answers(closest: &Closest, rays: &Rays) {
    let mut rng = Rng(33);
    let c = [10.0, -5.0, 2.0];
    let coords: Vec<f64> = (0..6 * 5)
        .flat_map(|ij| [(ij / 5) as f64, (ij % 5) as f64, 0.0])
        .map(|x| x + rng.range(-0.6, 0.6))
        .collect();
    let net = Surface::new(
        SurfaceKind::Uniform {
            basis: splinegpu::Basis::CatmullRom,
            ends: [splinegpu::Ends::Repeat; 2],
        },
        Net::new(3, 6, 5, coords).unwrap(),
    )
    .unwrap();
    let sets: [(&str, Vec<PatchTable>, f64); 3] = [
        ("torus", vec![torus_surface(R, SMALL, c).fit()], 8.0),
        ("net", vec![net.fit()], 7.0),
        ("teapot", vec![teapot().fit()], 7.0),
    ];
    for (name, tables, e) in &sets {
        let index = SurfaceIndex::new(tables).unwrap();
        let centre = if *name == "torus" { c } else { [2.0, 2.0, 1.0] };
        let mut queries = Vec::new();
        for _ in 0..60 {
            queries.extend([
                centre[0] + rng.range(-6.0, 6.0),
                centre[1] + rng.range(-6.0, 6.0),
                centre[2] + rng.range(-3.0, 3.0),
            ]);
        }
        let cpu = index.closest_many(&queries).unwrap();
        let found = closest(&index, &queries);
        for (i, (ours, theirs)) in found.iter().zip(&cpu).enumerate() {
            let q = &queries[3 * i..][..3];
            let bound = 2e-5 * e + 1e-5 * q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(
                (ours.distance - theirs.distance).abs() <= bound,
                "{name}: query {i} {q:?}: GPU {ours:?}, certified {theirs:?}"
            );
            assert_eq!(ours.patch.is_some(), theirs.patch.is_some());
        }
        // Rays from a sphere around the set toward random points of its box.
        let mut ray_list = Vec::new();
        for _ in 0..60 {
            let o = [
                centre[0] + rng.range(-9.0, 9.0),
                centre[1] + rng.range(-9.0, 9.0),
                centre[2] + rng.range(-9.0, 9.0),
            ];
            let target = [
                centre[0] + rng.range(-3.0, 3.0),
                centre[1] + rng.range(-3.0, 3.0),
                centre[2] + rng.range(-1.0, 1.0),
            ];
            ray_list.extend(o);
            ray_list.extend((0..3).map(|k| target[k] - o[k]));
        }
        let cpu = index.rays_many(&ray_list).unwrap();
        let found = rays(&index, &ray_list);
        for (i, (ours, theirs)) in found.iter().zip(&cpu).enumerate() {
            let o = &ray_list[6 * i..][..3];
            let bound = 2e-5 * e + 1e-5 * o.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            match (ours, theirs) {
                (None, None) => {}
                (Some(ours), Some(theirs)) => assert!(
                    (ours.s - theirs.s).abs() <= bound,
                    "{name}: ray {i}: GPU {ours:?}, certified {theirs:?}"
                ),
                _ => panic!("{name}: ray {i}: GPU {ours:?}, certified {theirs:?}"),
            }
        }
    }
    // The torus' closed forms: through the hole nothing, the outer equator along a diameter.
    let tables = [torus_surface(R, SMALL, c).fit()];
    let index = SurfaceIndex::new(&tables).unwrap();
    let through = [
        c[0],
        c[1],
        c[2] + 10.0,
        0.0,
        0.0,
        -1.0, //
        c[0] - 10.0,
        c[1],
        c[2],
        2.0,
        0.0,
        0.0,
    ];
    let found = rays(&index, &through);
    assert!(found[0].is_none(), "{:?}", found[0]);
    let hit = found[1].as_ref().unwrap();
    assert!((hit.s - (10.0 - R - SMALL)).abs() <= 2e-4, "{hit:?}");
}
