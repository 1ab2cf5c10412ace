//! Kochanek–Bartels curves: the special cases the contract names (Catmull-Rom, the cardinal
//! spline), an independent evaluation of the contract's formulas with per-point T, C, B and
//! uneven keys, the GPU within the promise, and the input rules.

use crate::support::{Rng, assert_gpu_matches_cpu, cpu_at};
use splinegpu::kinds::KindFields;
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, PerPoint, Points, Sampling, Tcb,
};

fn kb(ends: Ends, tcb: Tcb, t: Option<Vec<f64>>, points: Points) -> Curve {
    Curve::new(CurveKind::KochanekBartels { ends, tcb, t }, points).unwrap()
}

fn uniform(basis: Basis, ends: Ends, points: Points) -> Curve {
    Curve::new(CurveKind::Uniform { basis, ends }, points).unwrap()
}

/// The two tables' coefficients agree to `tol` of their size.
fn same_segments(a: &Curve, b: &Curve, tol: f64, what: &str) {
    let (a, b) = (a.fit(), b.fit());
    assert_eq!(a.knots(), b.knots(), "{what}: knots");
    for s in 0..a.len() {
        for (x, y) in a.segment(s).power().iter().zip(b.segment(s).power()) {
            for (x, y) in x.iter().zip(y) {
                assert!(
                    (x - y).abs() <= tol * (1.0 + y.abs()),
                    "{what}: segment {s}: {x} vs {y}"
                );
            }
        }
    }
}

#[test]
fn zero_tension_continuity_and_bias_is_catmull_rom_and_zero_cb_is_cardinal() {
    let mut rng = Rng(12);
    for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
        let points = rng.points(7, 3, -5.0, 5.0);
        let zero = kb(ends, Tcb::default(), None, points.clone());
        let catmull = uniform(Basis::CatmullRom, ends, points.clone());
        same_segments(&zero, &catmull, 1e-14, &format!("{ends:?} catmull-rom"));
        for tension in [-0.7, 0.25, 1.0] {
            let tcb = Tcb {
                tension: PerPoint::All(tension),
                ..Tcb::default()
            };
            let cardinal = Basis::Cardinal {
                tension: (1.0 - tension) / 2.0,
            };
            same_segments(
                &kb(ends, tcb, None, points.clone()),
                &uniform(cardinal, ends, points.clone()),
                1e-14,
                &format!("{ends:?} cardinal {tension}"),
            );
        }
    }
}

/// The contract's formulas, written out again here: the value and dP/dt of point-windowed
/// Kochanek–Bartels `segment` at u, coordinate k.
struct Direct<'a> {
    p: &'a [f64],
    dim: usize,
    n: usize,
    ends: Ends,
    tcb: [&'a [f64]; 3],
    t: &'a [f64],
}

impl Direct<'_> {
    fn point(&self, j: isize) -> usize {
        let n = self.n as isize;
        (match self.ends {
            Ends::Closed => j.rem_euclid(n),
            _ => j.clamp(0, n - 1),
        }) as usize
    }

    fn delta(&self, j: isize) -> f64 {
        let last = self.t.len() as isize - 2;
        let j = match self.ends {
            Ends::Closed => j.rem_euclid(last + 1),
            _ => j.clamp(0, last),
        } as usize;
        self.t[j + 1] - self.t[j]
    }

    /// The segment from P_i to P_{i+1} (i is the segment's index, plus 1 with control ends).
    fn at(&self, i: usize, u: f64, k: usize) -> (f64, f64) {
        let i = i as isize;
        let v = |j: isize| self.p[self.point(j) * self.dim + k];
        let [tn, cn, bn] = self.tcb;
        let (a, b) = (self.point(i), self.point(i + 1));
        let d = (1.0 - tn[a]) * (1.0 + bn[a]) * (1.0 + cn[a]) / 2.0 * (v(i) - v(i - 1))
            + (1.0 - tn[a]) * (1.0 - bn[a]) * (1.0 - cn[a]) / 2.0 * (v(i + 1) - v(i));
        let e = (1.0 - tn[b]) * (1.0 + bn[b]) * (1.0 - cn[b]) / 2.0 * (v(i + 1) - v(i))
            + (1.0 - tn[b]) * (1.0 - bn[b]) * (1.0 + cn[b]) / 2.0 * (v(i + 2) - v(i + 1));
        let here = self.delta(i);
        let d = d * 2.0 * here / (self.delta(i - 1) + here);
        let e = e * 2.0 * here / (here + self.delta(i + 1));
        // The Hermite basis in u.
        let (h00, h10, h01, h11) = (
            2.0 * u * u * u - 3.0 * u * u + 1.0,
            u * u * u - 2.0 * u * u + u,
            -2.0 * u * u * u + 3.0 * u * u,
            u * u * u - u * u,
        );
        let value = h00 * v(i) + h10 * d + h01 * v(i + 1) + h11 * e;
        let du = (6.0 * u * u - 6.0 * u) * v(i)
            + (3.0 * u * u - 4.0 * u + 1.0) * d
            + (-6.0 * u * u + 6.0 * u) * v(i + 1)
            + (3.0 * u * u - 2.0 * u) * e;
        (value, du / here)
    }
}

/// Per-point tension, continuity and bias on uneven keys against the contract's formula on
/// the CPU, every curve in one job.
fn per_point_tcb_checked() -> EvalJob {
    let mut rng = Rng(31);
    let mut job = EvalJob::new(Derivatives::Second);
    for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
        let n = 8;
        let dim = 2;
        let points = rng.points(n, dim, -10.0, 10.0);
        let each = |rng: &mut Rng| (0..n).map(|_| rng.range(-0.8, 0.8)).collect::<Vec<f64>>();
        let (tn, cn, bn) = (each(&mut rng), each(&mut rng), each(&mut rng));
        let keys = if ends == Ends::Closed { n + 1 } else { n };
        let mut t = vec![1.5];
        for j in 1..keys {
            t.push(t[j - 1] + 10f64.powf(rng.range(-2.0, 2.0)));
        }
        let tcb = Tcb {
            tension: PerPoint::Each(tn.clone()),
            continuity: PerPoint::Each(cn.clone()),
            bias: PerPoint::Each(bn.clone()),
        };
        let curve = kb(ends, tcb, Some(t.clone()), points.clone());
        let direct = Direct {
            p: points.coords(),
            dim,
            n,
            ends,
            tcb: [&tn, &cn, &bn],
            t: &t,
        };
        let (first, segments) = match ends {
            Ends::Control => (1, n - 3),
            Ends::Repeat => (0, n - 1),
            Ends::Closed => (0, n),
        };
        assert_eq!(curve.t_range(), (t[first], t[first + segments]));
        let mut at = Vec::new();
        let mut expected = Vec::new();
        for i in first..first + segments {
            for u in [0.0, 0.3, 0.77] {
                at.push(t[i] + u * (t[i + 1] - t[i]));
                expected.push((0..dim).map(|k| direct.at(i, u, k)).collect::<Vec<_>>());
            }
        }
        let ours = cpu_at(&curve, &at);
        let c = ours.curve(0);
        for (i, want) in expected.iter().enumerate() {
            for (k, (value, slope)) in want.iter().enumerate() {
                let (got, got_slope) = (c.points[i * dim + k], c.d1.unwrap()[i * dim + k]);
                assert!(
                    (got - value).abs() <= 1e-10 * (1.0 + value.abs()),
                    "{ends:?} value {i}"
                );
                assert!(
                    (got_slope - slope).abs() <= 1e-9 * (1.0 + slope.abs()),
                    "{ends:?} slope {i}: {got_slope} vs {slope}"
                );
            }
        }
        job.push(&curve, &Sampling::PerSegment(9)).unwrap();
        job.push(&curve, &Sampling::Tolerance(1e-3)).unwrap();
    }
    job
}

#[test]
fn per_point_tcb_on_uneven_keys_is_the_contracts_formula() {
    per_point_tcb_checked();
}

#[allow(
    dead_code,
    reason = "a trial of the GPU harness (tests/gpu/main.rs), which includes this file"
)]
pub(crate) fn per_point_tcb_on_uneven_keys_meets_the_gpu_promise() {
    assert_gpu_matches_cpu(&per_point_tcb_checked());
}

#[test]
fn kochanek_bartels_input_rules_are_located() {
    let named = |name: &str, fields: KindFields, n: usize| {
        let kind = CurveKind::named(name, fields)?;
        let coords = (0..2 * n).map(|v| f64::from(v as u32 % 7)).collect();
        Curve::new(kind, Points::new(2, coords).unwrap())
    };
    let closed = |t: Vec<f64>| KindFields {
        ends: Some(Ends::Closed),
        t: Some(t),
        ..KindFields::default()
    };
    let cases: Vec<(Result<Curve, splinegpu::InputError>, &str)> = vec![
        (
            named("kochanek-bartels", closed(vec![0.0, 1.0, 2.0]), 3),
            "(4), got 3",
        ),
        (
            named("kochanek-bartels", closed(vec![0.0, 1.0, 1.0, 3.0]), 3),
            "t[2] = 1 follows",
        ),
        (
            named(
                "kochanek-bartels",
                KindFields {
                    tension: Some(PerPoint::Each(vec![0.0, 0.5])),
                    ..KindFields::default()
                },
                4,
            ),
            "\"tension\" must have one value per point (4), got 2",
        ),
        (
            named(
                "kochanek-bartels",
                KindFields {
                    continuity: Some(PerPoint::All(f64::INFINITY)),
                    ..KindFields::default()
                },
                4,
            ),
            "\"continuity\" must be a finite number",
        ),
        (
            named("kochanek-bartels", KindFields::default(), 3),
            "at least 4 points",
        ),
        (
            named(
                "cardinal",
                KindFields {
                    tension: Some(PerPoint::Each(vec![0.5; 4])),
                    ..KindFields::default()
                },
                4,
            ),
            "\"tension\" must be a number for a \"cardinal\" curve",
        ),
        (
            named(
                "catmull-rom",
                KindFields {
                    continuity: Some(PerPoint::All(0.5)),
                    ..KindFields::default()
                },
                4,
            ),
            "\"continuity\" is not a field of a \"catmull-rom\" curve",
        ),
    ];
    for (result, expected) in cases {
        let message = result.unwrap_err().to_string();
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
}
