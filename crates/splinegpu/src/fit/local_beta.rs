//! Beta-splines with local bias and tension (the memo's "Future": B. Barsky and J. Beatty,
//! "Local control of bias and tension in Beta-splines", 1983): the discretely shaped
//! Beta-spline, each joint j carrying its own bias b1_j and tension b2_j.
//!
//! # The conditions
//!
//! Segment i is a cubic of the four points of its window (P_i .. P_{i+3} of the windowed
//! sequence), Q_i(u) = Σ_r q_{i,r}(u) P_{i+r}, u in [0, 1]. Joint j sits at the start of segment j
//! (L = Q_{j−1} ends there, R = Q_j starts there), where
//!
//! ```text
//! R(0) = L(1),   R'(0) = b1_j L'(1),   R''(0) = b1_j² L''(1) + b2_j L'(1),
//! ```
//!
//! for every choice of points, and the basis sums to 1 (translating the points translates the
//! curve). Since the points are arbitrary, each point's basis function B_k (the piecewise cubic
//! that multiplies P_k: zero but on the four segments k−3 .. k) meets the same conditions.
//!
//! # The derivation
//!
//! Write B_k's four pieces s0 .. s3 (on segments k−3 .. k) and its interior joints a, b, c (joints
//! k−2, k−1, k). At the joint before s0 and the one after s3 the other side is zero, so
//! s0 = A u³ and s3 = D (1−u)³. The conditions at a fix s1 from s0 up to its cubic term, and those
//! at c fix s2 from s3 up to its (1−u)³ term; with w = 1 − u and D = c1³ D̃:
//!
//! ```text
//! s1(u) = A (1 + 3 a1 u + (3 a1² + 3/2 a2) u²)       + e1 u³
//! s2(u) = D̃ (c1³ + 3 c1² w + (3 c1 + 3/2 c2) w²)     + e2 w³
//! ```
//!
//! The three conditions at b, s2(0) = s1(1), s2'(0) = b1 s1'(1), s2''(0) = b1² s1''(1) + b2 s1'(1),
//! are three homogeneous equations in (A, e1, D̃, e2): B_k is their null vector (the signed 3x3
//! minors), up to a scale. Its shape depends on joints k−2 .. k only.
//!
//! Segment i meets four basis functions: B_i as its last piece, c0 (1−u)³; B_{i+3} as its first,
//! c3 u³; B_{i+1} as its third piece s2 (joints i−1, i, i+1) and B_{i+2} as its second piece s1
//! (joints i, i+1, i+2), each times a scale c1, c2. The scales make the basis sum to 1: a cubic is
//! fixed by its values and first derivatives at u = 0 and 1, so
//!
//! ```text
//! c0 + c1 p1(0) + c2 p2(0) = 1,   −3 c0 + c1 p1'(0) + c2 p2'(0) = 0,
//! c3 + c1 p1(1) + c2 p2(1) = 1,    3 c3 + c1 p1'(1) + c2 p2'(1) = 0,
//! ```
//!
//! a 2x2 system in c1, c2 after eliminating c0 and c3. The scales a segment finds are the ones
//! its neighbours find (the partition of unity is unique), so each segment is fitted alone: its
//! basis depends on joints i−1 .. i+2, and joint j's values reach the segments j−2 .. j+1.
//!
//! With every joint's (b1, b2) equal, the matrix is the memo's B_{b1,b2} ([`beta_rows`]);
//! with b1 = 1, b2 = 0 it is the uniform B-spline. An open curve ("control", "repeat" ends)
//! takes its first and last joints' values as continuing past its ends (phantom joints).
//! docs/local-beta.md has the derivation with its checks.
//!
//! [`beta_rows`]: crate::basis::beta_rows

use crate::basis::Rows;
use crate::conventions::Ends;
use crate::conventions::PerPoint;
use crate::error::{InputError, Shown};

/// A joint's shape parameters: bias b1 and tension b2.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Joint {
    b1: f64,
    b2: f64,
}

/// Number of joints of a curve of `n` points with `ends`: the segments' ends (n − 2 for
/// "control", n for "repeat" and "closed", where joint j starts segment j).
#[must_use]
pub(crate) fn joint_count(ends: Ends, n: usize) -> usize {
    match ends {
        Ends::Closed => ends.segments(n),
        Ends::Control | Ends::Repeat => ends.segments(n) + 1,
    }
}

/// Every segment's basis matrix of a local Beta-spline of `n` points with `ends`, by rows as
/// the memo writes them (row r of M times the window gives the coefficient of u^(3−r)), once
/// the data are checked: enough points for the ends, bias and tension each a number or one
/// value per joint, every b1 > 0 and every b2 >= 0 (the basis then always exists).
///
/// # Errors
/// The first rule broken, naming its field and, for an array, the index.
pub(crate) fn checked_rows(
    ends: Ends,
    bias: &PerPoint,
    tension: &PerPoint,
    n: usize,
) -> Result<Vec<Rows>, InputError> {
    ends.check_points(n)?;
    let joints = joint_count(ends, n);
    bias.check("bias", joints, "joint")?;
    tension.check("tension", joints, "joint")?;
    let rule = |field: &str, values: &PerPoint, ok: fn(f64) -> bool, wanted: &str| match values {
        PerPoint::All(v) if !ok(*v) => Err(InputError::field(
            field,
            format!(
                "must be {wanted} when bias or tension is given per joint, got {}",
                Shown(*v)
            ),
        )),
        PerPoint::Each(values) => match values.iter().position(|v| !ok(*v)) {
            Some(j) => Err(InputError::field(
                field,
                format!(
                    "must be {wanted} at every joint: {field}[{j}] = {}",
                    Shown(values[j])
                ),
            )),
            None => Ok(()),
        },
        PerPoint::All(_) => Ok(()),
    };
    rule("bias", bias, |v| v > 0.0, "> 0")?;
    rule("tension", tension, |v| v >= 0.0, ">= 0")?;
    // b1 > 0 and b2 >= 0 always give a basis in exact arithmetic; values far out of scale
    // (b1 = 1e-120, say) can still overflow or cancel in f64, and that is the input's fault.
    let rows = segment_rows(ends, bias, tension, n);
    match rows
        .iter()
        .position(|m| m.iter().flatten().any(|v| !v.is_finite()))
    {
        Some(i) => Err(InputError::field(
            "bias",
            format!(
                "and \"tension\" at joints {} to {} give segment {i} a basis outside f64's range",
                i.saturating_sub(1),
                (i + 2).min(joints - 1)
            ),
        )),
        None => Ok(rows),
    }
}

/// Every segment's basis matrix (see [`checked_rows`]), of data whose counts and signs are
/// checked.
fn segment_rows(ends: Ends, bias: &PerPoint, tension: &PerPoint, n: usize) -> Vec<Rows> {
    let joints = joint_count(ends, n);
    // Joint j, with phantom joints past an open curve's ends and wrapping on a closed one.
    let joint = |j: isize| {
        let j = match ends {
            Ends::Closed => j.rem_euclid(joints as isize),
            Ends::Control | Ends::Repeat => j.clamp(0, joints as isize - 1),
        } as usize;
        Joint {
            b1: bias.at(j),
            b2: tension.at(j),
        }
    };
    (0..ends.segments(n) as isize)
        .map(|i| segment_basis([joint(i - 1), joint(i), joint(i + 1), joint(i + 2)]))
        .collect()
}

/// A polynomial on [0, 1] in ascending powers: p(u) = p[0] + p[1] u + p[2] u² + p[3] u³.
type Poly = [f64; 4];

/// The basis matrix of a segment whose joints i − 1 .. i + 2 are `joints` (the segment runs
/// from joints[1] to joints[2]).
fn segment_basis(joints: [Joint; 4]) -> Rows {
    let [before, start, end, after] = joints;
    let (_, p1) = middle_pieces(before, start, end);
    let (p2, _) = middle_pieces(start, end, after);
    let value = |p: &Poly, u: f64| p[0] + u * (p[1] + u * (p[2] + u * p[3]));
    let slope = |p: &Poly, u: f64| p[1] + u * (2.0 * p[2] + u * 3.0 * p[3]);
    // c1, c2 from the two equations left once c0 and c3 are eliminated (Cramer's rule).
    let (a11, a12) = (
        3.0 * value(&p1, 0.0) + slope(&p1, 0.0),
        3.0 * value(&p2, 0.0) + slope(&p2, 0.0),
    );
    let (a21, a22) = (
        slope(&p1, 1.0) - 3.0 * value(&p1, 1.0),
        slope(&p2, 1.0) - 3.0 * value(&p2, 1.0),
    );
    let det = a11 * a22 - a12 * a21;
    let c1 = (3.0 * a22 + 3.0 * a12) / det;
    let c2 = (-3.0 * a21 - 3.0 * a11) / det;
    let c0 = 1.0 - c1 * value(&p1, 0.0) - c2 * value(&p2, 0.0);
    let c3 = 1.0 - c1 * value(&p1, 1.0) - c2 * value(&p2, 1.0);
    // Columns: c0 (1−u)³, c1 p1, c2 p2, c3 u³; row r holds the coefficients of u^(3−r).
    let columns: [Poly; 4] = [
        [c0, -3.0 * c0, 3.0 * c0, -c0],
        p1.map(|v| c1 * v),
        p2.map(|v| c2 * v),
        [0.0, 0.0, 0.0, c3],
    ];
    std::array::from_fn(|r| std::array::from_fn(|c| columns[c][3 - r]))
}

/// The second and third pieces (s1, s2), up to one common scale, of the basis function whose
/// interior joints are `a`, `b`, `c` (see the module's derivation).
fn middle_pieces(a: Joint, b: Joint, c: Joint) -> (Poly, Poly) {
    // s1 = A·(1 + 3 a1 u + ka u²) + e1 u³; its value, slope and curvature at u = 1, each as
    // (coefficient of A, coefficient of e1).
    let ka = 3.0 * a.b1 * a.b1 + 1.5 * a.b2;
    let s1_value = (1.0 + 3.0 * a.b1 + ka, 1.0);
    let s1_slope = (3.0 * a.b1 + 2.0 * ka, 3.0);
    let s1_curve = (2.0 * ka, 6.0);
    // s2 = D̃·(g0 + g1 w + g2 w²) + e2 w³, w = 1 − u; at u = 0 (w = 1), d/du = −d/dw.
    let (g0, g1, g2) = (
        c.b1 * c.b1 * c.b1,
        3.0 * c.b1 * c.b1,
        3.0 * c.b1 + 1.5 * c.b2,
    );
    let s2_value = (g0 + g1 + g2, 1.0);
    let s2_slope = (-(g1 + 2.0 * g2), -3.0);
    let s2_curve = (2.0 * g2, 6.0);
    // The three conditions at b, in the unknowns (A, e1, D̃, e2).
    let rows = [
        [-s1_value.0, -s1_value.1, s2_value.0, s2_value.1],
        [
            -b.b1 * s1_slope.0,
            -b.b1 * s1_slope.1,
            s2_slope.0,
            s2_slope.1,
        ],
        [
            -(b.b1 * b.b1 * s1_curve.0 + b.b2 * s1_slope.0),
            -(b.b1 * b.b1 * s1_curve.1 + b.b2 * s1_slope.1),
            s2_curve.0,
            s2_curve.1,
        ],
    ];
    let [big_a, e1, d, e2] = null_vector(&rows);
    let s1 = [big_a, 3.0 * a.b1 * big_a, ka * big_a, e1];
    // (g0 + g1 w + g2 w²) D̃ + e2 w³ in powers of u.
    let w = [d * g0, d * g1, d * g2, e2];
    let s2 = [
        w[0] + w[1] + w[2] + w[3],
        -w[1] - 2.0 * w[2] - 3.0 * w[3],
        w[2] + 3.0 * w[3],
        -w[3],
    ];
    (s1, s2)
}

/// The null vector of a 3x4 matrix of rank 3: its signed 3x3 minors.
fn null_vector(m: &[[f64; 4]; 3]) -> [f64; 4] {
    let minor = |skip: usize| {
        let col: Vec<usize> = (0..4).filter(|&c| c != skip).collect();
        let e = |r: usize, c: usize| m[r][col[c]];
        e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1))
            - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0))
            + e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0))
    };
    [minor(0), -minor(1), minor(2), -minor(3)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{beta_rows, bspline_rows};

    fn worst(a: &Rows, b: &Rows) -> f64 {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn equal_joints_give_the_memo_matrix() {
        for b1 in [0.05, 0.5, 1.0, 1.7, 4.0, 30.0] {
            for b2 in [0.0, 0.3, 1.0, 7.5, 100.0] {
                let j = Joint { b1, b2 };
                let local = segment_basis([j; 4]);
                let memo = beta_rows(b1, b2).unwrap();
                assert!(
                    worst(&local, &memo) < 1e-12,
                    "b1 {b1} b2 {b2}: {local:?} != {memo:?}"
                );
            }
        }
    }

    #[test]
    fn unit_bias_zero_tension_is_the_uniform_bspline() {
        let j = Joint { b1: 1.0, b2: 0.0 };
        assert!(worst(&segment_basis([j; 4]), &bspline_rows()) < 1e-15);
    }

    #[test]
    fn null_vector_is_orthogonal_to_every_row() {
        let m = [
            [1.0, 2.0, -1.0, 0.5],
            [0.0, 3.0, 1.0, -2.0],
            [4.0, -1.0, 2.0, 1.0],
        ];
        let x = null_vector(&m);
        for row in &m {
            let dot: f64 = row.iter().zip(&x).map(|(a, b)| a * b).sum();
            assert!(dot.abs() < 1e-12, "{dot}");
        }
        assert!(x.iter().any(|v| v.abs() > 1.0));
    }
}
