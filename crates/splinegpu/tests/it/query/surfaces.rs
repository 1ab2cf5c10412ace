//! Closest points on surfaces and rays, against closed forms on an exact rational torus (the
//! distance to a torus is |√((ρ − R)² + z²) − r|; a ray along a diameter first meets the outer
//! equator; one down the axis passes through the hole; one along the top grazes it), a flat
//! patch, the teapot, and a dense sampling of random nets (the certified distance is never
//! more than ε above the nearest sample).

use crate::shapes::{teapot, torus_surface};
use crate::support::Rng;
use splinegpu::query::SurfaceIndex;
use splinegpu::surface::{Net, PatchTable, Surface, SurfaceKind};

const R: f64 = 3.0;
const SMALL: f64 = 1.0;

/// The distance from p to the torus of radii R, SMALL about `c` (axis z).
fn torus_distance(p: [f64; 3], c: [f64; 3]) -> f64 {
    let (x, y, z) = (p[0] - c[0], p[1] - c[1], p[2] - c[2]);
    ((x.hypot(y) - R).hypot(z) - SMALL).abs()
}

#[test]
fn closest_points_on_a_torus_are_its_closed_form() {
    let c = [10.0, -5.0, 2.0];
    let tables = [torus_surface(R, SMALL, c).fit()];
    let index = SurfaceIndex::new(&tables).unwrap();
    let mut rng = Rng(9);
    let mut queries: Vec<[f64; 3]> = (0..40)
        .map(|_| {
            [
                c[0] + rng.range(-6.0, 6.0),
                c[1] + rng.range(-6.0, 6.0),
                c[2] + rng.range(-3.0, 3.0),
            ]
        })
        .collect();
    // On the axis every point of a circle ties; at the tube's centre line, a circle too.
    queries.extend([
        [c[0], c[1], c[2] + 2.0],
        [c[0], c[1], c[2]],
        [c[0] + R, c[1], c[2]],
    ]);
    for (i, q) in queries.iter().enumerate() {
        let hit = index.closest(q, i).unwrap();
        let want = torus_distance(*q, c);
        let eps = 1e-9 * (8.0 + q.iter().fold(0.0f64, |m, x| m.max(x.abs())));
        assert!(
            (hit.distance - want).abs() <= eps,
            "query {i} {q:?}: {} vs {want}",
            hit.distance
        );
        // The point is on the torus, at that distance.
        let p = [hit.point[0], hit.point[1], hit.point[2]];
        assert!(torus_distance(p, c) <= 1e-9, "{hit:?}");
        let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
        assert!((d - hit.distance).abs() <= 1e-12 * (1.0 + d));
        assert_eq!((hit.surface, hit.patch), (0, None));
    }
}

#[test]
fn rays_meet_a_torus_where_the_closed_form_says() {
    let c = [1.0, 2.0, 3.0];
    let tables = [torus_surface(R, SMALL, c).fit()];
    let index = SurfaceIndex::new(&tables).unwrap();
    let eps = 1e-9 * (8.0 + 15.0);
    // Along a diameter from outside: the outer equator at x = -(R + r), normal along x.
    let hit = index
        .first_hit(&[c[0] - 10.0, c[1], c[2], 2.0, 0.0, 0.0], 0)
        .unwrap()
        .unwrap();
    assert!((hit.s - (10.0 - R - SMALL)).abs() <= eps, "{hit:?}");
    assert!((hit.normal[0].abs() - 1.0).abs() < 1e-9, "{hit:?}");
    // From inside the tube's ring, outward: the inner equator at x = R - r... from the centre.
    let hit = index
        .first_hit(&[c[0], c[1], c[2], 1.0, 0.0, 0.0], 1)
        .unwrap()
        .unwrap();
    assert!((hit.s - (R - SMALL)).abs() <= eps, "{hit:?}");
    // Down the axis: through the hole, nothing.
    assert!(
        index
            .first_hit(&[c[0], c[1], c[2] + 10.0, 0.0, 0.0, -1.0], 2)
            .unwrap()
            .is_none()
    );
    // Grazing the top of the tube (z = r): it touches at x = -R.
    let hit = index
        .first_hit(&[c[0] - 10.0, c[1], c[2] + SMALL, 1.0, 0.0, 0.0], 3)
        .unwrap()
        .unwrap();
    assert!((hit.s - (10.0 - R)).abs() <= 1e-4, "{hit:?}");
    // Pointing away: nothing.
    assert!(
        index
            .first_hit(&[c[0] - 10.0, c[1], c[2], -1.0, 0.0, 0.0], 4)
            .unwrap()
            .is_none()
    );
    // Starting on the surface: s = 0.
    let hit = index
        .first_hit(&[c[0] - R - SMALL, c[1], c[2], 1.0, 0.0, 0.0], 5)
        .unwrap()
        .unwrap();
    assert!(hit.s <= eps, "{hit:?}");
    // A zero direction is refused naming the ray.
    let e = index.first_hit(&[0.0; 6], 7).unwrap_err().to_string();
    assert!(e.contains("rays[7]"), "{e}");
}

/// A flat bicubic Bezier patch over [0, 3]² at z = 0 (x = 3u, y = 3v): a point above it is at
/// its height, straight below.
#[test]
fn a_flat_patch_answers_straight_below() {
    let coords: Vec<f64> = (0..16)
        .flat_map(|ij| [(ij / 4) as f64, (ij % 4) as f64, 0.0])
        .collect();
    let surface = Surface::new(SurfaceKind::Bezier, Net::new(3, 4, 4, coords).unwrap()).unwrap();
    let tables = [surface.fit()];
    let index = SurfaceIndex::new(&tables).unwrap();
    let hit = index.closest(&[1.0, 2.0, 5.0], 0).unwrap();
    assert!((hit.distance - 5.0).abs() < 1e-12, "{hit:?}");
    assert!(
        (hit.u - 1.0 / 3.0).abs() < 1e-6 && (hit.v - 2.0 / 3.0).abs() < 1e-6,
        "{hit:?}"
    );
    let ray = index
        .first_hit(&[1.0, 2.0, 5.0, 0.0, 0.0, -3.0], 0)
        .unwrap()
        .unwrap();
    assert!(
        (ray.s - 5.0).abs() < 1e-9 && ray.normal[2].abs() > 1.0 - 1e-12,
        "{ray:?}"
    );
    assert!(
        (ray.u - 1.0 / 3.0).abs() < 1e-9 && (ray.v - 2.0 / 3.0).abs() < 1e-9,
        "{ray:?}"
    );
}

/// The least distance from q to dense samples of every patch (61 x 61 each).
fn sampled(table: &PatchTable, q: &[f64]) -> f64 {
    let mut d = splinegpu::surface::Derivs::default();
    d.iter_mut().for_each(|x| x.resize(q.len(), 0.0));
    let mut best = f64::INFINITY;
    for p in 0..table.len() {
        let patch = table.patch(p);
        for a in 0..=60 {
            for b in 0..=60 {
                patch.local_derivatives(a as f64 / 60.0, b as f64 / 60.0, &mut d);
                let g: f64 = d[0].iter().zip(q).map(|(x, y)| (x - y) * (x - y)).sum();
                best = best.min(g);
            }
        }
    }
    best.sqrt()
}

#[test]
fn random_nets_and_the_teapot_against_dense_samples() {
    let mut rng = Rng(21);
    for round in 0..4 {
        let coords: Vec<f64> = (0..6 * 5)
            .flat_map(|ij| {
                let (i, j) = ((ij / 5) as f64, (ij % 5) as f64);
                [i, j, 0.0]
            })
            .map(|x| x + rng.range(-0.6, 0.6))
            .collect();
        let surface = Surface::new(
            SurfaceKind::Uniform {
                basis: splinegpu::Basis::CatmullRom,
                ends: [splinegpu::Ends::Repeat; 2],
            },
            Net::new(3, 6, 5, coords).unwrap(),
        )
        .unwrap();
        let tables = [surface.fit()];
        let index = SurfaceIndex::new(&tables).unwrap();
        for i in 0..12 {
            let q = [
                rng.range(-1.0, 6.0),
                rng.range(-1.0, 5.0),
                rng.range(-2.0, 2.0),
            ];
            let hit = index.closest(&q, i).unwrap();
            let eps = 1e-9 * (7.0 + 6.0);
            assert!(
                hit.distance <= sampled(&tables[0], &q) + eps,
                "round {round} query {q:?}: {hit:?}"
            );
        }
    }
    let tables = [teapot().fit()];
    let index = SurfaceIndex::new(&tables).unwrap();
    for q in [
        [0.0, 0.0, 4.0],
        [3.5, 0.2, 1.0],
        [-2.0, 1.0, 0.5],
        [0.1, 0.1, 1.5],
    ] {
        let hit = index.closest(&q, 0).unwrap();
        assert!(
            hit.distance <= sampled(&tables[0], &q) + 1e-8,
            "{q:?}: {hit:?}"
        );
        assert!(hit.patch.is_some());
    }
}
