//! Surfaces against independent truths: every kind's patches equal the curve rule applied along
//! u and then along v (evaluated through the curve API, a separate path), the interpolating
//! surface passes through its net and reproduces a bicubic, a rational torus lies on the torus
//! with the torus's normals, per-segment meshes have the contract's shape (a closed torus of
//! bspline is watertight by construction), patch lists weld along shared edges, normals stay
//! finite and right at a collapsed edge, and bad input is named.

use crate::shapes::torus_surface;
use crate::support::{Rng, surface_job, surface_samples};
use splinegpu::surface::{
    Net, PatchTable, Surface, SurfaceKind, SurfacePlan, SurfaceSamples, SurfaceSampling,
    unit_normal,
};
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, EvalJob, Points, Sampling,
};

/// A random net of `rows` x `cols` points in `dim` dimensions.
fn net(rng: &mut Rng, rows: usize, cols: usize, dim: usize, lo: f64, hi: f64) -> Net {
    let coords = (0..rows * cols * dim).map(|_| rng.range(lo, hi)).collect();
    Net::new(dim, rows, cols, coords).unwrap()
}

/// The curve kind of each direction of `kind`, for the independent evaluation.
fn curve_kinds(kind: &SurfaceKind) -> [CurveKind; 2] {
    match kind {
        SurfaceKind::Uniform { basis, ends } => ends.map(|ends| CurveKind::Uniform {
            basis: basis.clone(),
            ends,
        }),
        SurfaceKind::Bezier => [CurveKind::Bezier, CurveKind::Bezier],
        SurfaceKind::Interpolating { conditions, u, v } => [
            CurveKind::Interpolating {
                condition: conditions[0].clone(),
                t: u.clone(),
            },
            CurveKind::Interpolating {
                condition: conditions[1].clone(),
                t: v.clone(),
            },
        ],
        SurfaceKind::Nurbs {
            knots_u, knots_v, ..
        } => [
            CurveKind::Nurbs {
                knots: knots_u.clone(),
                weights: None,
            },
            CurveKind::Nurbs {
                knots: knots_v.clone(),
                weights: None,
            },
        ],
        SurfaceKind::BezierPatches { .. } => unreachable!("a patch list has no directions"),
    }
}

/// Value and derivatives (order 0..=2 in u, then in v: S, Su, Sv, Suu, Suv, Svv) of a
/// tensor-product surface at (u, v), through the curve API: each column is a curve along u,
/// evaluated (with its u-derivative of order du) at u; those points make a curve along v.
fn through_curves(kind: &SurfaceKind, net: &Net, u: f64, v: f64) -> [Vec<f64>; 6] {
    let [along_u, along_v] = curve_kinds(kind);
    let (rows, cols) = net.shape();
    let dim = net.dim();
    let at = |curve: &Curve, t: f64, order: usize| -> Vec<f64> {
        let mut job = EvalJob::new(Derivatives::Second);
        job.push(curve, &Sampling::At(vec![t])).unwrap();
        let samples = splinegpu::evaluate_reference(&job);
        let c = samples.curve(0);
        match order {
            0 => c.points.to_vec(),
            1 => c.d1.unwrap().to_vec(),
            _ => c.d2.unwrap().to_vec(),
        }
    };
    let mut out: [Vec<f64>; 6] = Default::default();
    for (m, (ou, ov)) in [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
        .into_iter()
        .enumerate()
    {
        let mut column_values = Vec::with_capacity(cols * dim);
        for j in 0..cols {
            let column: Vec<f64> = (0..rows)
                .flat_map(|i| net.coords()[(i * cols + j) * dim..][..dim].to_vec())
                .collect();
            let curve = Curve::new(along_u.clone(), Points::new(dim, column).unwrap()).unwrap();
            column_values.extend(at(&curve, u, ou));
        }
        let curve = Curve::new(along_v.clone(), Points::new(dim, column_values).unwrap()).unwrap();
        out[m] = at(&curve, v, ov);
    }
    out
}

fn samples_at(surface: &Surface, at: &[[f64; 2]]) -> splinegpu::surface::SurfaceSamples {
    let table = surface.fit();
    surface_samples(
        &table,
        &SurfaceSampling::At(at.to_vec()),
        Derivatives::Second,
        false,
    )
}

/// Random (u, v) over a net's range, its corners and an interior knot pair included.
fn places(rng: &mut Rng, table: &PatchTable) -> Vec<[f64; 2]> {
    let [ku, kv] = table.knots().unwrap();
    let (u0, u1, v0, v1) = (ku[0], ku[ku.len() - 1], kv[0], kv[kv.len() - 1]);
    let mut at = vec![[u0, v0], [u1, v1], [u0, v1], [u1, v0], [ku[1], kv[1]]];
    at.extend((0..12).map(|_| [rng.range(u0, u1), rng.range(v0, v1)]));
    at
}

fn assert_tensor_product(kind: SurfaceKind, net: Net, what: &str) {
    let mut rng = Rng(7);
    let surface = Surface::new(kind.clone(), net.clone()).unwrap();
    let at = places(&mut rng, &surface.fit());
    let samples = samples_at(&surface, &at);
    let dim = net.dim();
    let planes = [
        Some(&samples.points),
        samples.du.as_ref(),
        samples.dv.as_ref(),
        samples.duu.as_ref(),
        samples.duv.as_ref(),
        samples.dvv.as_ref(),
    ];
    for (i, &[u, v]) in at.iter().enumerate() {
        let want = through_curves(&kind, &net, u, v);
        for (m, plane) in planes.iter().enumerate() {
            let got = &plane.unwrap()[i * dim..(i + 1) * dim];
            for k in 0..dim {
                // Not-a-knot ends over spacings 1000:1 amplify rounding in both paths.
                let scale = 1.0 + want[m][k].abs();
                assert!(
                    (got[k] - want[m][k]).abs() < 1e-8 * scale,
                    "{what}: ({u}, {v}) derivative {m} coordinate {k}: {} vs {}",
                    got[k],
                    want[m][k]
                );
            }
        }
    }
}

/// The evaluator's paths (polynomial patches of 1 to 4 coordinates with the dimension known at
/// compile time, wider and rational ones read at run time; grid rows that share their u-stage
/// and single vertices) against `Patch::derivatives` and `unit_normal` vertex by vertex, and
/// its f32 planes against its f64 values rounded.
#[test]
fn every_evaluator_path_agrees_with_the_patch_and_f32_is_f64_rounded() {
    let mut rng = Rng(11);
    let bspline = SurfaceKind::Uniform {
        basis: Basis::BSpline,
        ends: [Ends::Control, Ends::Closed],
    };
    let mut surfaces: Vec<Surface> = (1..=6)
        .map(|dim| Surface::new(bspline.clone(), net(&mut rng, 6, 7, dim, -3.0, 3.0)).unwrap())
        .collect();
    surfaces.push(torus_surface(3.0, 1.0, [1e3, -2e3, 5.0]));
    surfaces.push(net_as_patch_list(&net(&mut rng, 7, 7, 3, -1.0, 1.0)));
    for surface in &surfaces {
        let table = surface.fit();
        let dim = table.dim();
        let normals = dim == 3;
        let samplings = match table.knots() {
            Some(_) => vec![
                SurfaceSampling::PerSegment([3, 5]),
                SurfaceSampling::At(places(&mut rng, &table)),
            ],
            None => vec![SurfaceSampling::PerSegment([4, 4])],
        };
        for sampling in samplings {
            let what = format!("dim {dim}, {:?}", surface.kind());
            let plan = SurfacePlan::new(&table, &sampling).unwrap();
            let job = surface_job(&[(&table, &sampling)], Derivatives::Second, normals);
            let got = job.evaluate_cpu().remove(0);
            let planes = [
                Some(&got.points),
                got.du.as_ref(),
                got.dv.as_ref(),
                got.duu.as_ref(),
                got.duv.as_ref(),
                got.dvv.as_ref(),
            ];
            let mut want = Default::default();
            for (i, vertex) in plan.vertices.iter().enumerate() {
                let patch = table.patch(vertex.patch as usize);
                let [u, v] = vertex.local;
                patch.derivatives(u, v, &mut want);
                for (m, plane) in planes.iter().enumerate() {
                    let got = &plane.unwrap()[i * dim..(i + 1) * dim];
                    for (k, (&g, &w)) in got.iter().zip(&want[m]).enumerate() {
                        assert!(
                            (g - w).abs() <= 1e-12 * (1.0 + w.abs()),
                            "{what}: vertex {i} plane {m} coordinate {k}: {g} vs {w}"
                        );
                    }
                }
                if normals {
                    let mut local = Default::default();
                    patch.local_derivatives(u, v, &mut local);
                    let su = [local[1][0], local[1][1], local[1][2]];
                    let sv = [local[2][0], local[2][1], local[2][2]];
                    let w = unit_normal(&patch, u, v, su, sv);
                    let g = &got.normals.as_ref().unwrap()[i * 3..i * 3 + 3];
                    for k in 0..3 {
                        assert!(
                            (g[k] - w[k]).abs() < 1e-12,
                            "{what}: normal {i}: {g:?} vs {w:?}"
                        );
                    }
                }
            }
            // f32: the same f64 values, rounded once as they are stored.
            let mut narrow =
                SurfaceSamples::<f32>::for_plan(&table, &plan, Derivatives::Second, normals);
            job.evaluate_into(0, narrow.planes_mut()).unwrap();
            let rounded = |plane: &[f64]| plane.iter().map(|&x| x as f32).collect::<Vec<_>>();
            assert_eq!(narrow.points, rounded(&got.points), "{what}");
            assert_eq!(narrow.duv, got.duv.as_deref().map(rounded), "{what}");
            assert_eq!(
                narrow.normals,
                got.normals.as_deref().map(rounded),
                "{what}"
            );
            assert_eq!((narrow.uv, narrow.triangles), (got.uv, got.triangles));
        }
    }
}

#[test]
fn uniform_tensor_products_are_the_curve_rule_along_u_then_v() {
    let mut rng = Rng(1);
    for basis in crate::support::bases() {
        for ends in [
            [Ends::Control, Ends::Control],
            [Ends::Repeat, Ends::Closed],
            [Ends::Closed, Ends::Control],
        ] {
            let kind = SurfaceKind::Uniform {
                basis: basis.clone(),
                ends,
            };
            assert_tensor_product(
                kind,
                net(&mut rng, 6, 5, 3, -2.0, 2.0),
                &format!("{basis:?} {ends:?}"),
            );
        }
    }
}

#[test]
fn bezier_nets_nurbs_and_interpolating_surfaces_are_the_curve_rule_along_u_then_v() {
    let mut rng = Rng(2);
    assert_tensor_product(
        SurfaceKind::Bezier,
        net(&mut rng, 7, 4, 2, -1.0, 1.0),
        "bezier",
    );
    let kind = SurfaceKind::Nurbs {
        knots_u: vec![0.0, 0.0, 0.0, 0.0, 0.3, 2.0, 2.0, 2.0, 2.0],
        knots_v: vec![-1.0, -1.0, -1.0, -1.0, -0.5, -0.5, 0.25, 3.0, 3.0, 3.0, 3.0],
        weights: None,
    };
    assert_tensor_product(kind, net(&mut rng, 5, 7, 3, -3.0, 3.0), "nurbs");
    // Uneven parameters (spacing ratios to 1e3), every pair of conditions.
    let u = vec![0.0, 1e-3, 1.0, 1.5, 4.0];
    let v = vec![10.0, 10.5, 11.0, 511.0, 512.0, 1000.0];
    for cu in [EndCondition::Natural, EndCondition::NotAKnot] {
        for cv in [EndCondition::Natural, EndCondition::NotAKnot] {
            let kind = SurfaceKind::Interpolating {
                conditions: [cu.clone(), cv.clone()],
                u: Some(u.clone()),
                v: Some(v.clone()),
            };
            assert_tensor_product(
                kind,
                net(&mut rng, 5, 6, 3, -1.0, 1.0),
                &format!("{cu:?} {cv:?}"),
            );
        }
    }
    // Periodic along v: the net's first and last columns equal.
    let mut periodic = net(&mut rng, 4, 5, 2, -1.0, 1.0).coords().to_vec();
    for i in 0..4 {
        for k in 0..2 {
            periodic[(i * 5 + 4) * 2 + k] = periodic[(i * 5) * 2 + k];
        }
    }
    let kind = SurfaceKind::Interpolating {
        conditions: [EndCondition::NotAKnot, EndCondition::Periodic],
        u: None,
        v: Some(vec![0.0, 0.5, 2.0, 2.25, 3.0]),
    };
    assert_tensor_product(
        kind,
        Net::new(2, 4, 5, periodic).unwrap(),
        "periodic along v",
    );
}

#[test]
fn interpolating_surfaces_pass_through_the_net_and_not_a_knot_reproduces_a_bicubic() {
    let u = [0.0, 0.1, 0.5, 2.0, 2.2, 5.0];
    let v = [-1.0, 0.0, 0.001, 1.0, 3.0];
    let bicubic = |x: f64, y: f64| {
        1.5 - x + 0.25 * x * x * x * y - 2.0 * y * y * x * x + 0.1 * y * y * y + x * y
    };
    let coords: Vec<f64> = u
        .iter()
        .flat_map(|&x| v.iter().map(move |&y| bicubic(x, y)))
        .collect();
    let kind = SurfaceKind::Interpolating {
        conditions: [EndCondition::NotAKnot, EndCondition::NotAKnot],
        u: Some(u.to_vec()),
        v: Some(v.to_vec()),
    };
    let surface = Surface::new(kind, Net::new(1, 6, 5, coords).unwrap()).unwrap();
    let mut rng = Rng(3);
    let mut at: Vec<[f64; 2]> = u
        .iter()
        .flat_map(|&x| v.iter().map(move |&y| [x, y]))
        .collect();
    at.extend((0..30).map(|_| [rng.range(0.0, 5.0), rng.range(-1.0, 3.0)]));
    let samples = samples_at(&surface, &at);
    for (i, &[x, y]) in at.iter().enumerate() {
        let want = bicubic(x, y);
        assert!(
            (samples.points[i] - want).abs() < 1e-10 * (1.0 + want.abs()),
            "({x}, {y}): {} vs {want}",
            samples.points[i]
        );
        let duv = 0.75 * x * x - 8.0 * y * x + 1.0;
        assert!((samples.duv.as_ref().unwrap()[i] - duv).abs() < 1e-8 * (1.0 + duv.abs()));
    }
}

#[test]
fn a_rational_torus_lies_on_the_torus_with_its_normals_near_the_origin_and_at_1e5() {
    for center in [[0.0, 0.0, 0.0], [1e5, -2e5, 5e4]] {
        let (big, small) = (3.0, 1.0);
        let surface = torus_surface(big, small, center);
        let table = surface.fit();
        assert!(table.is_rational());
        let s = surface_samples(
            &table,
            &SurfaceSampling::PerSegment([7, 5]),
            Derivatives::Second,
            true,
        );
        let normals = s.normals.as_ref().unwrap();
        let mut worst = [0.0f64; 2];
        for i in 0..s.len() {
            let p: Vec<f64> = (0..3).map(|k| s.points[3 * i + k] - center[k]).collect();
            let ring = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let off = ((ring - big).powi(2) + p[2] * p[2]).sqrt() - small;
            worst[0] = worst[0].max(off.abs());
            // The torus's outward normal: from the tube's centre circle to the point.
            let c = [big * p[0] / ring, big * p[1] / ring, 0.0];
            let d: Vec<f64> = (0..3).map(|k| (p[k] - c[k]) / small).collect();
            let n = &normals[3 * i..3 * i + 3];
            let dot: f64 = (0..3).map(|k| n[k] * d[k]).sum();
            worst[1] = worst[1].max((1.0 - dot.abs()).abs());
            // Su x Sv agrees with the normal's side.
            let (du, dv) = (
                &s.du.as_ref().unwrap()[3 * i..],
                &s.dv.as_ref().unwrap()[3 * i..],
            );
            let cross = [
                du[1] * dv[2] - du[2] * dv[1],
                du[2] * dv[0] - du[0] * dv[2],
                du[0] * dv[1] - du[1] * dv[0],
            ];
            assert!((0..3).map(|k| cross[k] * n[k]).sum::<f64>() > 0.0);
        }
        let tol = 1e-12 * (1.0 + center[0].abs().max(center[1].abs()));
        assert!(
            worst[0] < tol,
            "center {center:?}: off the torus by {}",
            worst[0]
        );
        assert!(
            worst[1] < 1e-9,
            "center {center:?}: normal off by {}",
            worst[1]
        );
        // Closed? A nurbs circle is open in its knots: its first and last lines coincide.
        assert_eq!(s.len(), (4 * 7 + 1) * (4 * 5 + 1));
    }
}

#[test]
fn per_segment_grids_have_the_contracts_shape_and_a_closed_torus_is_watertight() {
    let mut rng = Rng(4);
    let kind = SurfaceKind::Uniform {
        basis: Basis::BSpline,
        ends: [Ends::Closed, Ends::Closed],
    };
    let table = Surface::new(kind, net(&mut rng, 5, 6, 3, -1.0, 1.0))
        .unwrap()
        .fit();
    let plan = SurfacePlan::new(&table, &SurfaceSampling::PerSegment([3, 2])).unwrap();
    // Closed both ways: (5 · 3) x (6 · 2) vertices, no last lines; two triangles per cell.
    assert_eq!(plan.vertices.len(), 15 * 12);
    let triangles = plan.triangles.as_ref().unwrap();
    assert_eq!(triangles.len(), 2 * 15 * 12);
    let mut edges = std::collections::HashMap::new();
    for t in triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    assert!(
        edges.values().all(|&n| n == 2),
        "an edge not shared by exactly two triangles"
    );
    // Vertex order: row-major, u outer, and the contract's triangle order in cell (0, 0).
    assert_eq!(plan.vertices[1].uv, [0.0, 0.5]);
    assert_eq!(plan.vertices[12].uv, [1.0 / 3.0, 0.0]);
    assert_eq!(triangles[0], [0, 12, 13]);
    assert_eq!(triangles[1], [0, 13, 1]);
    // Open directions keep their last lines: (segments k + 1) each.
    let kind = SurfaceKind::Uniform {
        basis: Basis::CatmullRom,
        ends: [Ends::Control, Ends::Repeat],
    };
    let table = Surface::new(kind, net(&mut rng, 5, 4, 2, -1.0, 1.0))
        .unwrap()
        .fit();
    let plan = SurfacePlan::new(&table, &SurfaceSampling::PerSegment([4, 4])).unwrap();
    assert_eq!(plan.vertices.len(), (2 * 4 + 1) * (3 * 4 + 1));
    assert_eq!(plan.vertices.last().unwrap().uv, [2.0, 3.0]);
    assert_eq!(plan.vertices.last().unwrap().local, [1.0, 1.0]);
}

/// A 7 x 7 Bezier net as a patch list of its four patches, sharing the net's indices.
fn net_as_patch_list(net: &Net) -> Surface {
    let mut patches = Vec::new();
    for pu in 0..2 {
        for pv in 0..2 {
            patches.push(std::array::from_fn(|k| {
                let (i, j) = (k / 4, k % 4);
                (3 * pu + i) * 7 + 3 * pv + j
            }));
        }
    }
    let flat = Net::new(net.dim(), 49, 1, net.coords().to_vec()).unwrap();
    Surface::new(SurfaceKind::BezierPatches { patches }, flat).unwrap()
}

#[test]
fn a_patch_list_welds_its_shared_edges_and_equals_its_net() {
    let mut rng = Rng(5);
    let grid = net(&mut rng, 7, 7, 3, -1.0, 1.0);
    let k = 5;
    let list = net_as_patch_list(&grid).fit();
    let plan = SurfacePlan::new(&list, &SurfaceSampling::PerSegment([k, k])).unwrap();
    // Welded: the net's (2k + 1)² vertices, no more.
    assert_eq!(plan.vertices.len(), (2 * k as usize + 1).pow(2));
    let s = surface_samples(
        &list,
        &SurfaceSampling::PerSegment([k, k]),
        Derivatives::None,
        true,
    );
    // Every vertex equals the net's surface at its place.
    let whole = Surface::new(SurfaceKind::Bezier, grid).unwrap();
    for (i, vertex) in plan.vertices.iter().enumerate() {
        let p = vertex.patch as usize;
        let [u, v] = vertex.local;
        let global = [(p / 2) as f64 + u, (p % 2) as f64 + v];
        let want = samples_at(&whole, &[global]);
        for c in 0..3 {
            assert!((s.points[3 * i + c] - want.points[c]).abs() < 1e-12);
        }
    }
    // Shared edges: each interior edge of the mesh in exactly two triangles, boundary in one.
    let mut edges = std::collections::HashMap::new();
    for t in plan.triangles.as_ref().unwrap() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let boundary = edges.values().filter(|&&n| n == 1).count();
    assert!(edges.values().all(|&n| n == 1 || n == 2));
    assert_eq!(boundary, 4 * 2 * k as usize);
    // A patch list takes one k, and "at" triples.
    assert!(SurfacePlan::new(&list, &SurfaceSampling::PerSegment([2, 3])).is_err());
    let at = SurfacePlan::new(&list, &SurfaceSampling::AtPatches(vec![(3, [0.5, 1.0])])).unwrap();
    assert_eq!(at.vertices[0].patch, 3);
    let err = SurfacePlan::new(&list, &SurfaceSampling::AtPatches(vec![(4, [0.5, 1.0])]))
        .unwrap_err()
        .to_string();
    assert!(err.contains("at[0] = [4, 0.5, 1]"), "{err}");
}

#[test]
fn normals_at_a_collapsed_edge_are_the_limit_from_inside() {
    // A dome: a Bezier patch whose u = 0 edge is one point (the apex), as the teapot's lid top.
    let mut coords = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            let r = f64::from(i) / 3.0;
            let angle = f64::from(j) * 0.4;
            coords.extend([r * angle.cos(), r * angle.sin(), 1.0 - r * r]);
        }
    }
    let net = Net::new(3, 4, 4, coords).unwrap();
    let table = Surface::new(SurfaceKind::Bezier, net).unwrap().fit();
    let at = vec![
        [0.0, 0.0],
        [0.0, 0.37],
        [0.0, 1.0],
        [1e-7, 0.37],
        [0.3, 0.37],
    ];
    let s = surface_samples(
        &table,
        &SurfaceSampling::At(at.clone()),
        Derivatives::First,
        true,
    );
    let n = s.normals.as_ref().unwrap();
    for i in 0..at.len() {
        let length: f64 = (0..3).map(|k| n[3 * i + k].powi(2)).sum::<f64>().sqrt();
        assert!((length - 1.0).abs() < 1e-12, "{:?}: |n| = {length}", at[i]);
    }
    // At the apex the limit along v = 0.37 and the normal just inside agree.
    let gap: f64 = (0..3)
        .map(|k| (n[3 + k] - n[9 + k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        gap < 1e-5,
        "apex normal {:?} vs inside {:?}",
        &n[3..6],
        &n[9..12]
    );
    // The apex of this dome: its normal leans toward the patch's side but points up.
    assert!(n[2] > 0.0 && n[5] > 0.0 && n[8] > 0.0);
}

#[test]
fn bad_surfaces_are_named() {
    let mut rng = Rng(6);
    let cases: Vec<(SurfaceKind, Net, &str)> = vec![
        (
            SurfaceKind::BezierPatches {
                patches: vec![
                    [0; 16],
                    std::array::from_fn(|k| if k == 5 { 99 } else { k }),
                ],
            },
            net(&mut rng, 16, 1, 3, 0.0, 1.0),
            "\"patches\" must index the 16 points: patches[1][5] = 99",
        ),
        (
            SurfaceKind::Nurbs {
                knots_u: vec![0.0; 7],
                knots_v: vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
                weights: None,
            },
            net(&mut rng, 4, 4, 3, 0.0, 1.0),
            "\"knots_u\"",
        ),
        (
            SurfaceKind::Nurbs {
                knots_u: vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
                knots_v: vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
                weights: Some(vec![1.0; 15]),
            },
            net(&mut rng, 4, 4, 3, 0.0, 1.0),
            "\"weights\" must be a net of 4 x 4 numbers, one per point, got 15 values",
        ),
        (
            SurfaceKind::Bezier,
            net(&mut rng, 5, 4, 3, 0.0, 1.0),
            "a bezier net needs 3k+1 points along u (k >= 1), got 5",
        ),
        (
            SurfaceKind::Interpolating {
                conditions: [EndCondition::Natural, EndCondition::Periodic],
                u: None,
                v: None,
            },
            net(&mut rng, 4, 4, 1, 0.0, 1.0),
            "must close up along v",
        ),
        (
            SurfaceKind::Interpolating {
                conditions: [EndCondition::Natural, EndCondition::Natural],
                u: Some(vec![0.0, 1.0, 1.0, 2.0]),
                v: None,
            },
            net(&mut rng, 4, 4, 1, 0.0, 1.0),
            "\"u\" must be strictly increasing: u[2] = 1 follows u[1] = 1",
        ),
        (
            SurfaceKind::Uniform {
                basis: Basis::BSpline,
                ends: [Ends::Control, Ends::Control],
            },
            net(&mut rng, 4, 3, 2, 0.0, 1.0),
            "needs at least 4 points along v for \"control\", got 3",
        ),
    ];
    for (kind, net, message) in cases {
        let err = Surface::new(kind, net).unwrap_err().to_string();
        assert!(err.contains(message), "{err} lacks {message}");
    }
    let err = Net::new(3, 2, 2, vec![0.0; 11]).unwrap_err().to_string();
    assert!(err.contains("net of 2 x 2 points"), "{err}");
    // (u, v) outside the range.
    let table = Surface::new(
        SurfaceKind::Uniform {
            basis: Basis::BSpline,
            ends: [Ends::Control, Ends::Control],
        },
        net(&mut rng, 5, 5, 3, 0.0, 1.0),
    )
    .unwrap()
    .fit();
    let err = SurfacePlan::new(&table, &SurfaceSampling::At(vec![[0.5, 0.5], [2.5, 1.0]]))
        .unwrap_err()
        .to_string();
    assert!(err.contains("[0, 2] x [0, 2]: at[1] = [2.5, 1]"), "{err}");
}

/// The contract's rule for a vertex on the line between two patches of a net: the patch that
/// starts there evaluates it (as a curve's joint sample is), and the last line the last patch
/// at 1; each patch of [`constant_patches`] shows its owner in the value.
#[test]
fn a_vertex_between_two_patches_is_the_later_patchs() {
    use crate::shapes::{CONSTANT_PATCH_OWNERS, constant_patches};
    use splinegpu::surface::SurfaceSampling;
    let samples = surface_samples(
        &constant_patches(),
        &SurfaceSampling::PerSegment([2, 2]),
        splinegpu::Derivatives::None,
        false,
    );
    let owner = CONSTANT_PATCH_OWNERS;
    for a in 0..5 {
        for b in 0..5 {
            let z = samples.points[3 * (5 * a + b) + 2];
            assert_eq!(z, 10.0 * owner[a] + owner[b], "vertex ({a}, {b})");
        }
    }
}
