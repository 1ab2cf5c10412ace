//! Rotation-minimizing frames at a curve's cross-sections, by the double reflection of Wang,
//! Jüttler, Zheng and Liu (ACM TOG 27(1), 2008), closed up on loops.
//!
//! At cross-section j: the unit tangent T_j, a normal N_j ⟂ T_j, and B_j = T_j × N_j. N_0 is
//! `up` made perpendicular to T_0 (or the coordinate axis least aligned with T_0). Then, with
//! x_j = C(t_j):
//!
//! ```text
//! v1 = x_{j+1} - x_j,  c1 = v1·v1,  r = N_j - (2/c1)(v1·N_j) v1,  t = T_j - (2/c1)(v1·T_j) v1
//! v2 = T_{j+1} - t,    c2 = v2·v2,  N_{j+1} = r - (2/c2)(v2·r) v2
//! ```
//!
//! (a reflection is left out where its c is 0), and N_{j+1} is made perpendicular to T_{j+1}
//! and normalized again. Each step is a reflection in the plane bisecting x_j and x_{j+1}
//! followed by one taking the reflected tangent onto T_{j+1}: two reflections, a rotation,
//! whose error against the exact rotation-minimizing frame is O(h^4) per step.
//!
//! A closed curve's frame carried once around meets N_0 turned by some α about T_0; every
//! N_j is then turned about T_j by -α s_j / L (s_j the arc length to t_j, L the curve's), so
//! that the last cross-section's frame is the first's ([`close_up`]).

use bsplines::lanes::Isa;

use crate::error::InputError;

/// A 3-vector.
pub type Vec3 = [f64; 3];

pub(crate) fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
#[must_use]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn axpy(a: f64, x: Vec3, y: Vec3) -> Vec3 {
    [a * x[0] + y[0], a * x[1] + y[1], a * x[2] + y[2]]
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    axpy(-1.0, b, a)
}

/// `v` / |v|, or `None` where |v| is 0 (or not finite).
#[inline]
pub(crate) fn unit(v: Vec3) -> Option<Vec3> {
    let length = dot(v, v).sqrt();
    if !(length > 0.0 && length.is_finite()) {
        return None;
    }
    // One division a vector where its reciprocal is finite (a normal length), three else.
    Some(if length >= f64::MIN_POSITIVE {
        let inverse = 1.0 / length;
        v.map(|x| x * inverse)
    } else {
        v.map(|x| x / length)
    })
}

/// `v` made perpendicular to the unit vector `t` and normalized (`None` where nothing is left).
fn perpendicular(v: Vec3, t: Vec3) -> Option<Vec3> {
    unit(axpy(-dot(v, t), t, v))
}

/// The unit tangent C'/|C'| from the first and second derivatives at a cross-section. Where
/// C' = 0 (a cusp, a doubled point) it is the limit of C'(t)/|C'(t)| as t approaches from
/// above, C''/|C''| (from below at the end of the range, `at_end`: -C''/|C''|); `None` where
/// C'' is 0 too.
#[must_use]
pub fn unit_tangent(d1: Vec3, d2: Vec3, at_end: bool) -> Option<Vec3> {
    unit(d1).or_else(|| unit(d2).map(|t| if at_end { t.map(|x| -x) } else { t }))
}

/// The tangents of every cross-section (`unit_tangent` of each; the last is at the end of the
/// range), a cross-section without one taking its neighbour's (the one before, or for the
/// first, the first that has one); a curve without any direction takes x.
#[must_use]
pub fn tangents(d1: &[Vec3], d2: &[Vec3]) -> Vec<Vec3> {
    let last = d1.len().saturating_sub(1);
    let found: Vec<Option<Vec3>> = (0..d1.len())
        .map(|j| unit_tangent(d1[j], d2[j], j == last && j > 0))
        .collect();
    let first = found
        .iter()
        .flatten()
        .next()
        .copied()
        .unwrap_or([1.0, 0.0, 0.0]);
    let mut previous = first;
    found
        .into_iter()
        .map(|t| {
            previous = t.unwrap_or(previous);
            previous
        })
        .collect()
}

/// N_0: `up` minus its part along T_0, normalized, which must keep at least 1e-6 of |up|;
/// without `up`, the coordinate axis e with the smallest |e · T_0| (the first of equals).
///
/// # Errors
/// `up` not 3 finite numbers, or (nearly) parallel to T_0 (the error names "up").
pub fn first_normal(t0: Vec3, up: Option<Vec3>) -> Result<Vec3, InputError> {
    let Some(up) = up else {
        let axis = (0..3)
            .min_by(|&a, &b| t0[a].abs().total_cmp(&t0[b].abs()))
            .unwrap_or(0);
        let mut e = [0.0; 3];
        e[axis] = 1.0;
        return Ok(perpendicular(e, t0).unwrap_or([0.0, 1.0, 0.0]));
    };
    if !up.iter().all(|x| x.is_finite()) {
        return Err(InputError::field(
            "up",
            format!("must be 3 finite numbers, got {up:?}"),
        ));
    }
    let length = dot(up, up).sqrt();
    let part = axpy(-dot(up, t0), t0, up);
    if length == 0.0 || dot(part, part).sqrt() < 1e-6 * length {
        return Err(InputError::field(
            "up",
            format!("{up:?} is parallel to the curve's first tangent {t0:?}"),
        ));
    }
    Ok(unit(part).expect("checked above"))
}

/// The normals N_j carried from `n0` along the cross-sections at `positions` with unit
/// `tangents`, by double reflection (the module's docs).
///
/// A step is linear in the normal it carries: with w = v2 - (2/c1)(v1·v2) v1 (v2 reflected in
/// the first plane), the two reflections take n to
///
/// ```text
/// n - a v1 - b v2,   a = (2/c1)(v1·n),   b = (2/c2)(w·n)
/// ```
///
/// whose two dots do not wait on each other. v1, v2, w and the two ratios depend on the
/// cross-sections alone (made for every step first), so the chain of steps, each waiting on
/// the one before, is two dots and three multiply-adds long. The carried vector keeps its
/// rounding-level part along the tangent (a step takes T_j onto T_{j+1}, so that part neither
/// grows nor turns across); each N_j is it made perpendicular to T_j and normalized where it is
/// written. The carried vector is made unit again only where its length leaves [1/2, 2]
/// (rounding moves it by about 1e-16 a step).
#[must_use]
pub fn rotation_minimizing(positions: &[Vec3], tangents: &[Vec3], n0: Vec3) -> Vec<Vec3> {
    // The steps first, each on its own: their divisions overlap.
    let steps: Vec<Step> = (1..positions.len())
        .map(|j| Step::new(positions[j - 1], positions[j], tangents[j - 1], tangents[j]))
        .collect();
    let mut normals = Vec::with_capacity(positions.len());
    let mut carried = n0;
    for j in 0..positions.len() {
        if j == 0 {
            normals.push(n0);
            continue;
        }
        let t1 = tangents[j];
        let turned = steps[j - 1].apply(carried);
        let across = axpy(-dot(turned, t1), t1, turned);
        let normal = match unit(across) {
            Some(normal) => {
                let size = dot(turned, turned);
                carried = if (0.25..=4.0).contains(&size) {
                    turned
                } else {
                    normal
                };
                normal
            }
            None => {
                let normal = resumed(normals[j - 1], t1);
                carried = normal;
                normal
            }
        };
        normals.push(normal);
    }
    normals
}

/// One double-reflection step from cross-section (x0, t0) to (x1, t1) as the linear map
/// n ↦ n - (k1 v1·n) v1 - (k2 w·n) v2 (k = 2/c; a reflection whose c is 0 left out: its k
/// is 0).
struct Step {
    v1: Vec3,
    k1: f64,
    v2: Vec3,
    k2: f64,
    w: Vec3,
}

impl Step {
    fn new(x0: Vec3, x1: Vec3, t0: Vec3, t1: Vec3) -> Self {
        let v1 = sub(x1, x0);
        let c1 = dot(v1, v1);
        let k1 = if c1 > 0.0 { 2.0 / c1 } else { 0.0 };
        let v2 = sub(t1, axpy(-k1 * dot(v1, t0), v1, t0));
        let c2 = dot(v2, v2);
        let k2 = if c2 > 0.0 { 2.0 / c2 } else { 0.0 };
        let w = axpy(-k1 * dot(v1, v2), v1, v2);
        Self { v1, k1, v2, k2, w }
    }

    /// The step applied to `n` (of any length). Rounding aside, a normal across t0 comes out
    /// across t1.
    #[inline]
    fn apply(&self, n: Vec3) -> Vec3 {
        let (a, b) = (self.k1 * dot(self.v1, n), self.k2 * dot(self.w, n));
        axpy(-b, self.v2, axpy(-a, self.v1, n))
    }
}

/// The normal after a step whose reflected normal has no part across t1 (a step across a
/// cusp): the last normal made perpendicular to t1, or else t1's own first normal.
fn resumed(n0: Vec3, t1: Vec3) -> Vec3 {
    perpendicular(n0, t1).unwrap_or_else(|| first_normal(t1, None).expect("no up to refuse"))
}

/// One double-reflection step from cross-section (x0, t0, n0) to (x1, t1): the reflected
/// normal made perpendicular to t1 and normalized again (where it has no part across t1, as
/// [`resumed`]).
fn reflected_twice(x0: Vec3, x1: Vec3, t0: Vec3, t1: Vec3, n0: Vec3) -> Vec3 {
    perpendicular(Step::new(x0, x1, t0, t1).apply(n0), t1).unwrap_or_else(|| resumed(n0, t1))
}

/// The angle about `t1` by which the double-reflection step from (x0, t0) to (x1, t1) turns a
/// normal beyond the minimal rotation taking `t0` onto `t1` (the rotation about t0 × t1): the
/// same for every normal, a step being a rotation. Used to bound the frames' error
/// (`geometry::tolerance`); the tangents are within a right angle of each other there.
pub(crate) fn step_twist(x0: Vec3, x1: Vec3, t0: Vec3, t1: Vec3) -> f64 {
    let n0 = first_normal(t0, None).expect("no up to refuse");
    let reflected = reflected_twice(x0, x1, t0, t1, n0);
    // Rodrigues with k = t0 × t1, c = t0 · t1: R v = c v + k × v + k (k · v) / (1 + c).
    let (k, c) = (cross(t0, t1), dot(t0, t1));
    if c <= 0.0 {
        return std::f64::consts::PI;
    }
    let minimal = axpy(
        dot(k, n0) / (1.0 + c),
        k,
        axpy(1.0, cross(k, n0), n0.map(|x| x * c)),
    );
    let minimal = perpendicular(minimal, t1).unwrap_or(minimal);
    angle_about(t1, minimal, reflected)
}

/// `v` (⟂ the unit `axis`) turned by `angle` (|angle| <= π) about `axis`:
/// v cos a + (axis × v) sin a.
#[inline(always)]
fn turned(v: Vec3, axis: Vec3, angle: f64) -> Vec3 {
    let (sin, cos) = sin_cos_within_pi(angle);
    axpy(sin, cross(axis, v), v.map(|x| x * cos))
}

/// 1 / ((2k)(2k + 1)), k = 1..=10: the ratios of the sine's Taylor terms.
const SIN_TERMS: [f64; 10] = {
    let mut terms = [0.0; 10];
    let mut k = 0;
    while k < 10 {
        let two_k = 2.0 * (k + 1) as f64;
        terms[k] = 1.0 / (two_k * (two_k + 1.0));
        k += 1;
    }
    terms
};

/// 1 / ((2k - 1)(2k)), k = 1..=11: the ratios of the cosine's Taylor terms.
const COS_TERMS: [f64; 11] = {
    let mut terms = [0.0; 11];
    let mut k = 0;
    while k < 11 {
        let two_k = 2.0 * (k + 1) as f64;
        terms[k] = 1.0 / ((two_k - 1.0) * two_k);
        k += 1;
    }
    terms
};

/// (sin x, cos x) for |x| <= π (a little more is fine), within 2e-15 of the exact values:
/// the Taylor series of y = x/2 (|y| <= π/2) to y^21 and y^22, whose first terms left out are
/// below 2e-18 there, then sin x = 2 sin y cos y and cos x = 1 - 2 sin² y. No range
/// reduction and no branch, so it inlines into the loop that turns every frame (libm's call
/// was an eighth of a tube's making).
#[inline(always)]
fn sin_cos_within_pi(x: f64) -> (f64, f64) {
    let y = 0.5 * x;
    let y2 = y * y;
    // 1 - y²/(2·3) (1 - y²/(4·5) (...)) and 1 - y²/(1·2) (1 - y²/(3·4) (...)), innermost first.
    let (mut sin, mut cos) = (1.0, 1.0);
    for inverse in SIN_TERMS.iter().rev() {
        sin = 1.0 - y2 * inverse * sin;
    }
    for inverse in COS_TERMS.iter().rev() {
        cos = 1.0 - y2 * inverse * cos;
    }
    let sin_y = y * sin;
    (2.0 * sin_y * cos, 1.0 - 2.0 * sin_y * sin_y)
}

/// The angle α in (-π, π] about the unit `axis` from `from` to `to` (both ⟂ `axis`).
fn angle_about(axis: Vec3, from: Vec3, to: Vec3) -> f64 {
    dot(cross(from, to), axis).atan2(dot(from, to))
}

/// Closes up a closed curve's frames: `normals` carried once around (the last cross-section
/// at the end of the range, where the curve is back at its start, so that T_last = T_0), with
/// `s` the arc length to each cross-section (s_last = L). N_last meets N_0 turned by α about
/// T_0; each N_j is turned about T_j by -α s_j / L, so that N_last = N_0 (to rounding).
pub fn close_up(tangents: &[Vec3], normals: &mut [Vec3], s: &[f64]) {
    // One of the crate's five unsafe blocks (the others are the CPU evaluator's and the mesh
    // writer's, the same dispatch, and memory/'s madvise and getrlimit): a function compiled
    // for an instruction set may only be called where the CPU has it.
    #[allow(
        unsafe_code,
        reason = "a function compiled for an instruction set is called only where the CPU has it"
    )]
    match Isa::widest() {
        Isa::Baseline => close_up_any(tangents, normals, s),
        // SAFETY: `Isa::widest` names AVX2 only where the CPU has it.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { close_up_avx2(tangents, normals, s) },
        // SAFETY: as for AVX2, with AVX-512F (and VL).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { close_up_avx512(tangents, normals, s) },
    }
}

/// [`close_up_any`] with AVX2 enabled (the turn and its sine inlined into it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn close_up_avx2(tangents: &[Vec3], normals: &mut [Vec3], s: &[f64]) {
    close_up_any(tangents, normals, s);
}

/// [`close_up_any`] with AVX-512F enabled, as [`close_up_avx2`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f")]
fn close_up_avx512(tangents: &[Vec3], normals: &mut [Vec3], s: &[f64]) {
    close_up_any(tangents, normals, s);
}

/// [`close_up`] as the instruction set of its caller compiles it: the sections' turns side by
/// side in vector lanes.
#[inline(always)]
fn close_up_any(tangents: &[Vec3], normals: &mut [Vec3], s: &[f64]) {
    let (Some(&last), Some(&length)) = (normals.last(), s.last()) else {
        return;
    };
    if length <= 0.0 || !length.is_finite() {
        return;
    }
    let alpha = angle_about(tangents[0], normals[0], last);
    for ((n, &t), &s) in normals.iter_mut().zip(tangents).zip(s) {
        *n = turned(*n, t, -alpha * s / length);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_line_keeps_its_first_normal() {
        let positions: Vec<Vec3> = (0..10).map(|i| [0.0, 0.0, f64::from(i)]).collect();
        let tangents = vec![[0.0, 0.0, 1.0]; 10];
        let n0 = first_normal(tangents[0], None).unwrap();
        assert_eq!(n0, [1.0, 0.0, 0.0]);
        for n in rotation_minimizing(&positions, &tangents, n0) {
            assert_eq!(n, n0);
        }
    }

    /// On a circle in the plane z = 0 the rotation-minimizing frame is the one that keeps the
    /// normal z (the exact answer: zero torsion, no twist).
    #[test]
    fn a_planar_circle_keeps_the_normal_out_of_its_plane() {
        let m = 200;
        let angle = |j: usize| std::f64::consts::TAU * j as f64 / m as f64;
        let positions: Vec<Vec3> = (0..=m)
            .map(|j| [angle(j).cos(), angle(j).sin(), 0.0])
            .collect();
        let tangents: Vec<Vec3> = (0..=m)
            .map(|j| [-angle(j).sin(), angle(j).cos(), 0.0])
            .collect();
        let normals = rotation_minimizing(&positions, &tangents, [0.0, 0.0, 1.0]);
        for n in &normals {
            assert!((n[2] - 1.0).abs() < 1e-12, "{n:?}");
        }
    }

    /// A helix' rotation-minimizing frame turns against the Frenet frame at the rate of the
    /// torsion: after one turn of x = (cos u, sin u, h u), the carried normal differs from
    /// the first by the angle τ · length = 2π h / sqrt(1 + h²) about the tangent (mod 2π),
    /// and close_up takes it back onto the first.
    #[test]
    fn a_helix_turns_by_its_total_torsion_and_closing_up_undoes_it() {
        let (h, m) = (0.3, 4000);
        let u = |j: usize| std::f64::consts::TAU * j as f64 / m as f64;
        let positions: Vec<Vec3> = (0..=m)
            .map(|j| [u(j).cos(), u(j).sin(), h * u(j)])
            .collect();
        let norm = (1.0 + h * h).sqrt();
        let tangents: Vec<Vec3> = (0..=m)
            .map(|j| [-u(j).sin() / norm, u(j).cos() / norm, h / norm])
            .collect();
        // The principal normal -(cos u, sin u, 0) as N_0.
        let mut normals = rotation_minimizing(&positions, &tangents, [-1.0, 0.0, 0.0]);
        let exact = std::f64::consts::TAU * h / norm;
        // The Frenet normal at the end is N_0 again; the RMF normal lags it by the torsion's
        // integral, turned about the tangent by -exact.
        let got = angle_about(tangents[0], normals[0], normals[m]);
        assert!((got + exact).abs() < 1e-6, "{got} against {}", -exact);
        let s: Vec<f64> = (0..=m).map(|j| u(j) * norm).collect();
        close_up(&tangents, &mut normals, &s);
        let closed = angle_about(tangents[0], normals[0], normals[m]);
        assert!(closed.abs() < 1e-12, "{closed}");
    }

    /// The closing-up's sine and cosine against libm's over [-π, π] and at its ends.
    #[test]
    fn sin_cos_within_pi_meets_libm() {
        let mut worst: f64 = 0.0;
        let ends = [
            -std::f64::consts::PI,
            std::f64::consts::PI,
            0.0,
            -0.0,
            1e-300,
        ];
        let grid = (0..=100_000).map(|i| std::f64::consts::PI * (f64::from(i) / 50_000.0 - 1.0));
        for x in ends.into_iter().chain(grid) {
            let (sin, cos) = sin_cos_within_pi(x);
            worst = worst.max((sin - x.sin()).abs()).max((cos - x.cos()).abs());
        }
        assert!(worst < 2e-15, "{worst:e}");
        assert_eq!(sin_cos_within_pi(0.0), (0.0, 1.0));
    }

    #[test]
    fn a_cusp_takes_the_tangent_from_above_and_from_below_at_the_end() {
        assert_eq!(
            unit_tangent([0.0; 3], [0.0, 2.0, 0.0], false),
            Some([0.0, 1.0, 0.0])
        );
        assert_eq!(
            unit_tangent([0.0; 3], [0.0, 2.0, 0.0], true),
            Some([0.0, -1.0, 0.0])
        );
        assert_eq!(unit_tangent([0.0; 3], [0.0; 3], false), None);
    }

    #[test]
    fn an_up_along_the_tangent_is_refused_by_name() {
        let error = first_normal([0.0, 0.0, 1.0], Some([0.0, 0.0, 2.0])).unwrap_err();
        assert_eq!(error.field.as_deref(), Some("up"));
        assert!(first_normal([0.0, 0.0, 1.0], Some([f64::NAN, 0.0, 0.0])).is_err());
        let n = first_normal([0.0, 0.0, 1.0], Some([1.0, 0.0, 5.0])).unwrap();
        assert_eq!(n, [1.0, 0.0, 0.0]);
    }
}
