//! The certified surface mesh: every point of every triangle within tol of the surface
//! (measured at many points of each triangle against the exact surface), watertight (shared
//! edges meshed once: closed nets have every edge in two triangles, welded patch lists no
//! boundary but their outer one), within the contract's triangle cap (measured against the true
//! maxima of the second derivatives), bounds that are bounds, and the Utah teapot.

use std::collections::HashMap;

use crate::shapes::teapot;
use crate::support::{Rng, surface_samples};
use splinegpu::Derivatives;
use splinegpu::surface::{Net, PatchTable, Surface, SurfaceKind, SurfacePlan, SurfaceSampling};

/// Barycentric places inside a triangle: its corners, edge midpoints, centroid and a grid.
fn barycentric() -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    let n = 6;
    for i in 0..=n {
        for j in 0..=n - i {
            let (a, b) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            out.push([a, b, 1.0 - a - b]);
        }
    }
    out.push([1.0 / 3.0; 3]);
    out
}

/// A triangle in its patch: the patch, its corners' local (u, v) and their positions.
type PatchTriangle = (usize, [[f64; 2]; 3], [Vec<f64>; 3]);

/// The largest distance between the surface and the flat triangles at the places of
/// [`barycentric`], each triangle's corners given in one patch's local (u, v): (patch,
/// [corner local uv; 3], [corner position; 3]).
fn worst_gap(table: &PatchTable, triangles: &[PatchTriangle]) -> f64 {
    let weights = barycentric();
    let mut at = Vec::new();
    let mut flat = Vec::new();
    for (p, uv, corners) in triangles {
        for w in &weights {
            let u = w[0] * uv[0][0] + w[1] * uv[1][0] + w[2] * uv[2][0];
            let v = w[0] * uv[0][1] + w[1] * uv[1][1] + w[2] * uv[2][1];
            at.push((*p, [u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)]));
            flat.push(
                (0..3)
                    .map(|k| w[0] * corners[0][k] + w[1] * corners[1][k] + w[2] * corners[2][k])
                    .collect::<Vec<f64>>(),
            );
        }
    }
    // Evaluate every place on its patch: as a patch list's (p, u, v), or a net's global (u, v).
    let mut derivs: splinegpu::surface::Derivs = Default::default();
    at.iter()
        .zip(&flat)
        .map(|(&(p, [u, v]), f)| {
            table.patch(p).local_derivatives(u, v, &mut derivs);
            (0..3)
                .map(|k| (derivs[0][k] - f[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

/// A plan's triangles with their patch and local corners (nets: the patch of the centroid; a
/// patch list's as the plan says).
fn triangles_in_patches(
    table: &PatchTable,
    plan: &SurfacePlan,
    points: &[f64],
) -> Vec<PatchTriangle> {
    let triangles = plan.triangles.as_ref().unwrap();
    let corner = |i: u32| points[3 * i as usize..3 * i as usize + 3].to_vec();
    match table.knots() {
        Some(knots) => triangles
            .iter()
            .map(|t| {
                let uv = t.map(|i| plan.vertices[i as usize].uv);
                let locate = |d: usize, x: f64| {
                    let k = knots[d];
                    k.partition_point(|&y| y <= x).clamp(1, k.len() - 1) - 1
                };
                // Wrapped cells (closed directions) take their first corner's patch.
                let centroid = [0, 1].map(|d| (uv[0][d] + uv[1][d] + uv[2][d]) / 3.0);
                let closed = table.closed();
                let wraps = |d: usize| {
                    closed[d]
                        && uv.iter().any(|c| c[d] == knots[d][0])
                        && uv.iter().any(|c| c[d] > knots[d][knots[d].len() - 2])
                };
                let (iu, iv) = (locate(0, centroid[0]), locate(1, centroid[1]));
                let iu = if wraps(0) { knots[0].len() - 2 } else { iu };
                let iv = if wraps(1) { knots[1].len() - 2 } else { iv };
                let p = iu * (knots[1].len() - 1) + iv;
                let local = uv.map(|c| {
                    let mut l = [0.0; 2];
                    for (d, i) in [(0, iu), (1, iv)] {
                        let (a, b) = (knots[d][i], knots[d][i + 1]);
                        let mut x = c[d];
                        if wraps(d) && x == knots[d][0] {
                            x = knots[d][knots[d].len() - 1];
                        }
                        l[d] = (x - a) / (b - a);
                    }
                    l
                });
                (p, local, t.map(corner))
            })
            .collect(),
        None => plan
            .patch_triangles(table)
            .unwrap()
            .into_iter()
            .zip(triangles)
            .map(|((p, local), t)| (p as usize, local, t.map(corner)))
            .collect(),
    }
}

/// Every edge's number of triangles.
fn edge_counts(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), usize> {
    let mut edges = HashMap::new();
    for t in triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    edges
}

/// The true maxima of |S_uu|, |S_uv|, |S_vv| over a patch, sampled densely (from below).
fn sampled_maxima(table: &PatchTable, p: usize) -> [f64; 3] {
    let patch = table.patch(p);
    let mut derivs: splinegpu::surface::Derivs = Default::default();
    let mut out = [0.0f64; 3];
    let n = 40;
    for i in 0..=n {
        for j in 0..=n {
            patch.local_derivatives(
                f64::from(i) / f64::from(n),
                f64::from(j) / f64::from(n),
                &mut derivs,
            );
            for (m, o) in out.iter_mut().enumerate() {
                let norm = derivs[3 + m].iter().map(|x| x * x).sum::<f64>().sqrt();
                *o = o.max(norm);
            }
        }
    }
    out
}

/// The contract's cap: twice the sum over patches of 2 n_u n_v with the true maxima.
fn cap(table: &PatchTable, tol: f64) -> usize {
    (0..table.len())
        .map(|p| {
            let [uu, uv, vv] = sampled_maxima(table, p);
            let n = |m: f64| ((m / (4.0 * tol)).sqrt().ceil()).max(1.0) as usize;
            2 * 2 * n(uu + uv) * n(vv + uv)
        })
        .sum()
}

/// Meshes `surface` within each tol, checks the certificate and the cap; returns the plans.
fn certify(surface: &Surface, tols: &[f64], what: &str) -> Vec<(f64, SurfacePlan)> {
    let table = surface.fit();
    let mut plans = Vec::new();
    for &tol in tols {
        let plan = SurfacePlan::new(&table, &SurfaceSampling::Tolerance(tol)).unwrap();
        let samples = surface_samples(
            &table,
            &SurfaceSampling::Tolerance(tol),
            Derivatives::None,
            false,
        );
        let triangles = triangles_in_patches(&table, &plan, &samples.points);
        let gap = worst_gap(&table, &triangles);
        assert!(
            gap <= tol * (1.0 + 1e-9),
            "{what} at {tol}: a triangle is {gap} from the surface"
        );
        let count = plan.triangles.as_ref().unwrap().len();
        let limit = cap(&table, tol);
        eprintln!(
            "{what} at tol {tol}: {count} triangles (cap {limit}), worst gap {:.3} tol",
            gap / tol
        );
        assert!(
            count <= limit,
            "{what} at {tol}: {count} triangles, cap {limit}"
        );
        plans.push((tol, plan));
    }
    plans
}

fn random_net(rng: &mut Rng, rows: usize, cols: usize) -> Net {
    let mut coords = Vec::new();
    for i in 0..rows {
        for j in 0..cols {
            // A wavy sheet: curvature that varies from patch to patch.
            let (x, y) = (i as f64, j as f64);
            coords.extend([
                x,
                y,
                rng.range(-1.0, 1.0) * (1.0 + (x * 0.7).sin().abs() * 3.0),
            ]);
        }
    }
    Net::new(3, rows, cols, coords).unwrap()
}

#[test]
fn net_meshes_are_within_tol_under_the_cap_and_closed_ones_watertight() {
    let mut rng = Rng(40);
    for ends in [
        [splinegpu::Ends::Control; 2],
        [splinegpu::Ends::Closed, splinegpu::Ends::Repeat],
    ] {
        let kind = SurfaceKind::Uniform {
            basis: splinegpu::Basis::CatmullRom,
            ends,
        };
        let surface = Surface::new(kind, random_net(&mut rng, 7, 6)).unwrap();
        certify(
            &surface,
            &[0.3, 0.03, 0.003],
            &format!("catmull-rom {ends:?}"),
        );
    }
    let kind = SurfaceKind::Uniform {
        basis: splinegpu::Basis::BSpline,
        ends: [splinegpu::Ends::Closed; 2],
    };
    let surface = Surface::new(kind, random_net(&mut rng, 6, 5)).unwrap();
    for (_, plan) in certify(&surface, &[0.1, 0.01], "closed bspline") {
        let edges = edge_counts(plan.triangles.as_ref().unwrap());
        assert!(
            edges.values().all(|&n| n == 2),
            "an edge not in exactly two triangles"
        );
    }
}

/// A flat field with one sharp bump: the bump's patches need many cells, the rest one. A mesh
/// giving every patch of a row (column) the row's largest count made 2.07x the contract's cap
/// here; graded, each patch keeps its own counts and the mesh is within the cap, within tol,
/// and watertight (every inner edge in two triangles).
#[test]
fn one_sharp_bump_in_a_flat_field_stays_within_the_cap() {
    let n = 16;
    let mut coords = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let bump = if (i, j) == (n / 2, n / 2) { 40.0 } else { 0.0 };
            coords.extend([i as f64, j as f64, bump]);
        }
    }
    let kind = SurfaceKind::Uniform {
        basis: splinegpu::Basis::CatmullRom,
        ends: [splinegpu::Ends::Control; 2],
    };
    let surface = Surface::new(kind, Net::new(3, n, n, coords).unwrap()).unwrap();
    for (tol, plan) in certify(&surface, &[0.1, 0.01], "one bump") {
        let edges = edge_counts(plan.triangles.as_ref().unwrap());
        assert!(edges.values().all(|&k| k == 1 || k == 2), "{tol}");
        let boundary = edges.values().filter(|&&k| k == 1).count();
        // The field's outer sides are flat: one cell each, 4 (n - 3) patches round the net.
        assert_eq!(boundary, 4 * (n - 3), "{tol}: T-junctions inside");
    }
}

#[test]
fn rational_bounds_are_bounds_within_4x_and_the_torus_mesh_is_certified() {
    let surface = crate::shapes::torus_surface(3.0, 1.0, [0.0; 3]);
    let worst = bounds_over_maxima(&surface.fit());
    eprintln!("torus: bounds at most {worst:.2}x the sampled maxima");
    assert!(worst <= 4.0, "rational bounds {worst}x the true maxima");
    certify(&surface, &[0.05, 0.005], "nurbs torus");
}

#[test]
fn polynomial_bounds_are_bounds() {
    let mut rng = Rng(41);
    let surface = Surface::new(SurfaceKind::Bezier, random_net(&mut rng, 7, 7)).unwrap();
    bounds_over_maxima(&surface.fit());
}

/// Asserts that every patch's second-derivative bounds lie above its sampled maxima, and
/// returns the largest ratio of the two.
fn bounds_over_maxima(table: &PatchTable) -> f64 {
    let mut worst = 0.0f64;
    for p in 0..table.len() {
        let bound = table.patch(p).second_derivative_bounds();
        let truth = sampled_maxima(table, p);
        for m in 0..3 {
            assert!(
                bound[m] >= truth[m] * (1.0 - 1e-12),
                "patch {p}: {bound:?} below {truth:?}"
            );
            if truth[m] > 1e-9 {
                worst = worst.max(bound[m] / truth[m]);
            }
        }
    }
    worst
}

/// A 7 x 7 Bezier net as a list of its four patches, one corner of the net scaled up so that
/// the patches need different counts.
fn uneven_patch_list() -> Surface {
    let mut rng = Rng(42);
    let mut coords = random_net(&mut rng, 7, 7).coords().to_vec();
    for i in 0..3 {
        for j in 0..3 {
            coords[(i * 7 + j) * 3 + 2] *= 20.0;
        }
    }
    let patches = (0..4)
        .map(|q| {
            let (pu, pv) = (q / 2, q % 2);
            std::array::from_fn(|k| (3 * pu + k / 4) * 7 + 3 * pv + k % 4)
        })
        .collect();
    Surface::new(
        SurfaceKind::BezierPatches { patches },
        Net::new(3, 49, 1, coords).unwrap(),
    )
    .unwrap()
}

/// Graded patch lists: each patch keeps its own counts (they differ here), and every inner
/// edge is still meshed once: the edges in one triangle are the outer boundary's alone, as
/// many as the four outer sides' own counts sum to (a T-junction would leave inner edges in
/// one triangle).
#[test]
fn graded_patch_lists_share_every_inner_edge_and_mesh_it_once() {
    let surface = uneven_patch_list();
    let table = surface.fit();
    for (tol, plan) in certify(&surface, &[0.5, 0.05], "uneven patch list") {
        let counts: Vec<[u32; 2]> = plan.cells.clone();
        assert!(counts.iter().any(|c| c != &counts[0]), "{tol}: {counts:?}");
        for (p, got) in counts.iter().enumerate() {
            // The contract's n_u, n_v from the patch's bounds.
            let [uu, uv, vv] = table.patch(p).second_derivative_bounds();
            let n = |m: f64| ((m / (4.0 * tol)).sqrt().ceil()).max(1.0) as u32;
            assert_eq!(
                *got,
                [n(uu + uv), n(vv + uv)],
                "{tol}: patch {p}'s own counts"
            );
        }
        let edges = edge_counts(plan.triangles.as_ref().unwrap());
        assert!(edges.values().all(|&n| n == 1 || n == 2));
        let boundary = edges.values().filter(|&&n| n == 1).count() as u32;
        // Patches 0 1 / 2 3 (u down, v across): the outer sides along u are 0's and 2's at
        // v = 0, 1's and 3's at v = 1; along v, 0's and 1's at u = 0, 2's and 3's at u = 1.
        let outer = (counts[0][0] + counts[2][0])
            + (counts[1][0] + counts[3][0])
            + (counts[0][1] + counts[1][1])
            + (counts[2][1] + counts[3][1]);
        assert_eq!(
            boundary, outer,
            "{tol}: T-junctions leave inner edges in one triangle"
        );
    }
}

#[test]
fn bad_tolerances_are_named() {
    let table = uneven_patch_list().fit();
    for tol in [0.0, -1.0, f64::NAN] {
        let err = SurfacePlan::new(&table, &SurfaceSampling::Tolerance(tol)).unwrap_err();
        assert_eq!(err.field.as_deref(), Some("tolerance"));
    }
    let err = SurfacePlan::new(&table, &SurfaceSampling::Tolerance(1e-12))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("\"sampling\"") && err.contains("more than 2^20") && err.contains("(patch 0)"),
        "{err}"
    );
    // A count past 1e16 is printed in scientific form, not as its 300 digits.
    let err = SurfacePlan::new(&table, &SurfaceSampling::Tolerance(1e-300))
        .unwrap_err()
        .to_string();
    assert!(err.len() < 200 && err.contains("e"), "{err}");
}

#[test]
fn the_teapots_certified_mesh_beats_the_smallest_uniform_grid_that_meets_tol() {
    let surface = teapot();
    let table = surface.fit();
    let extent = surface.net().extent();
    let tol = 1e-3 * extent;
    let plans = certify(&surface, &[tol], "teapot");
    let plan = &plans[0].1;
    // The smallest k whose k x k grid on every patch meets tol by the same certificate.
    let k = (0..table.len())
        .map(|p| {
            let [uu, uv, vv] = sampled_maxima(&table, p);
            let n = |m: f64| ((m / (4.0 * tol)).sqrt().ceil()).max(1.0) as usize;
            n(uu + uv).max(n(vv + uv))
        })
        .max()
        .unwrap();
    let uniform = table.len() * 2 * k * k;
    let certified = plan.triangles.as_ref().unwrap().len();
    eprintln!("teapot at 1e-3 of its extent: {certified} triangles, uniform {k} x {k}: {uniform}");
    assert!(certified < uniform);
    // Watertight where the data share edges: no edge in more than two triangles but the
    // collapsed ones at the lid's top and the bottom's centre.
    let edges = edge_counts(plan.triangles.as_ref().unwrap());
    let samples = surface_samples(
        &table,
        &SurfaceSampling::Tolerance(tol),
        Derivatives::None,
        true,
    );
    for (&(a, b), &n) in &edges {
        if n > 2 {
            let (pa, pb) = (
                &samples.points[3 * a as usize..],
                &samples.points[3 * b as usize..],
            );
            let on_axis = |p: &[f64]| p[0] == 0.0 && p[1] == 0.0;
            assert!(
                on_axis(pa) || on_axis(pb),
                "edge ({a}, {b}) in {n} triangles off the poles"
            );
        }
    }
    // Normals everywhere finite and of unit length, the poles' included.
    let normals = samples.normals.as_ref().unwrap();
    for n in normals.chunks_exact(3) {
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((length - 1.0).abs() < 1e-12, "{n:?}");
    }
}

/// A job counts a tolerance sampling from its cells (the patches' bounds) without making the
/// plan, and makes the plan from them when the surface is evaluated: the counts are the
/// plan's, the samples those of a job that kept every plan, on welded patch lists (the
/// teapot, whose patches share edges) and on nets, open and closed.
#[test]
fn tolerance_counts_from_the_cells_are_the_plans() {
    use splinegpu::surface::SurfaceJob;
    let mut rng = Rng(61);
    let torus = crate::shapes::torus_surface(3.0, 1.0, [0.0; 3]).fit();
    let net = Surface::new(SurfaceKind::Bezier, random_net(&mut rng, 7, 10))
        .unwrap()
        .fit();
    let surfaces = [
        (teapot().fit(), 1e-3),
        (teapot().fit(), 0.05),
        (torus, 1e-2),
        (net, 0.1),
    ];
    for (table, tol) in surfaces {
        let sampling = SurfaceSampling::Tolerance(tol);
        let plan = SurfacePlan::new(&table, &sampling).unwrap();
        let fresh = || SurfaceJob::new(Derivatives::First, true);
        let mut counted = fresh().keeping_plans_up_to(0);
        let mut kept = fresh().keeping_plans_up_to(usize::MAX);
        counted
            .push_many(vec![(table.clone(), sampling.clone())])
            .unwrap();
        kept.push(table, sampling).unwrap();
        let triangles = plan.triangles.as_ref().map_or(0, Vec::len) as u64;
        assert_eq!(counted.vertex_offsets(), &[0, plan.vertices.len() as u64]);
        assert_eq!(counted.triangle_offsets(), &[0, triangles]);
        assert_eq!(counted.vertex_offsets(), kept.vertex_offsets());
        assert_eq!(counted.evaluate_cpu(), kept.evaluate_cpu(), "tol {tol}");
    }
}
