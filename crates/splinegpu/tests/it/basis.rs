//! The memo's (seed 000) matrix identities, and properties every basis must have.

use glam::{DMat4, DVec4};
use splinegpu::Basis;
use splinegpu::basis::{
    Rows, beta_rows, bezier_rows, bspline_rows, cardinal_rows, tensioned_bspline_rows,
};

fn max_abs_diff(a: &Rows, b: &Rows) -> f64 {
    let mut worst: f64 = 0.0;
    for r in 0..4 {
        for c in 0..4 {
            worst = worst.max((a[r][c] - b[r][c]).abs());
        }
    }
    worst
}

#[test]
fn catmull_rom_is_cardinal_half_with_corrected_last_row() {
    // The memo prints 1/2 [-1 3 -3 1; 2 -5 4 -1; -1 0 1 0; 0 1 0 0]; the last row must be
    // [0 2 0 0] (seeds README), else P(0) = x_0 / 2.
    let printed: Rows = [
        [-0.5, 1.5, -1.5, 0.5],
        [1.0, -2.5, 2.0, -0.5],
        [-0.5, 0.0, 0.5, 0.0],
        [0.0, 1.0, 0.0, 0.0],
    ];
    assert_eq!(cardinal_rows(0.5), printed);
    assert_eq!(Basis::CatmullRom.try_rows().unwrap(), printed);
}

#[test]
fn cardinal_is_m1_inverse_times_m2() {
    // C_a = M_1^-1 M_2 (memo, "The Cardinal Splines"), built here by glam from the two
    // constraint matrices as the memo prints them.
    for a in [0.0, 0.25, 0.5, 1.0, 2.5, -0.7] {
        let m1 = DMat4::from_cols_array_2d(&[
            [0.0, 0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0, 1.0],
            [0.0, 0.0, 1.0, 0.0],
            [3.0, 2.0, 1.0, 0.0],
        ])
        .transpose();
        let m2 = DMat4::from_cols_array_2d(&[
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [-a, 0.0, a, 0.0],
            [0.0, -a, 0.0, a],
        ])
        .transpose();
        let expected = (m1.inverse() * m2).transpose().to_cols_array_2d();
        assert!(
            max_abs_diff(&cardinal_rows(a), &expected) < 1e-14,
            "a = {a}"
        );
    }
}

#[test]
fn beta_one_zero_is_bspline() {
    assert!(max_abs_diff(&beta_rows(1.0, 0.0).unwrap(), &bspline_rows()) < 1e-15);
}

#[test]
fn tensioned_bspline_one_is_bspline() {
    assert!(max_abs_diff(&tensioned_bspline_rows(1.0), &bspline_rows()) < 1e-15);
}

#[test]
fn tensioned_bspline_is_beta_with_bias_one() {
    // B_a = B_{1, 12(1-a)/a} (memo, "The Beta Splines").
    for a in [0.1, 0.5, 0.75, 1.0, 2.0, 7.5] {
        let beta = beta_rows(1.0, 12.0 * (1.0 - a) / a).unwrap();
        assert!(
            max_abs_diff(&tensioned_bspline_rows(a), &beta) < 1e-13,
            "a = {a}"
        );
    }
}

#[test]
fn bezier_rows_are_bernstein_polynomials() {
    let m = bezier_rows();
    for u in [0.0, 0.2, 0.5, 0.9, 1.0] {
        let uu = [u * u * u, u * u, u, 1.0];
        let bernstein = [
            (1.0 - u) * (1.0 - u) * (1.0 - u),
            3.0 * u * (1.0 - u) * (1.0 - u),
            3.0 * u * u * (1.0 - u),
            u * u * u,
        ];
        for (j, b) in bernstein.iter().enumerate() {
            let w: f64 = (0..4).map(|r| uu[r] * m[r][j]).sum();
            assert!((w - b).abs() < 1e-15, "u = {u}, j = {j}");
        }
    }
}

#[test]
fn every_basis_reproduces_constants() {
    // U·M·[1 1 1 1]^T = 1 for every u: rows 0..2 of M sum to 0 and row 3 to 1. A window of
    // four equal points gives that point (translation invariance).
    let bases = [
        Basis::Cardinal { tension: 0.3 },
        Basis::CatmullRom,
        Basis::BSpline,
        Basis::TensionedBSpline { tension: 0.6 },
        Basis::Beta {
            bias: 1.7,
            tension: 3.0,
        },
        Basis::Matrix(bezier_rows()),
    ];
    for basis in bases {
        let m = basis.try_rows().unwrap();
        for (r, row) in m.iter().enumerate() {
            let sum: f64 = row.iter().sum();
            let expected = if r == 3 { 1.0 } else { 0.0 };
            assert!(
                (sum - expected).abs() < 1e-14,
                "{basis:?} row {r} sums to {sum}"
            );
        }
    }
}

#[test]
fn to_dmat4_keeps_the_memo_rows() {
    let m = Basis::BSpline.to_dmat4().unwrap();
    let rows = bspline_rows();
    for (r, row) in rows.iter().enumerate() {
        assert_eq!(m.row(r), DVec4::from_array(*row));
    }
}

#[test]
fn beta_with_zero_d_is_an_error() {
    // d = b2 + 2b1^3 + 4b1^2 + 4b1 + 2 is 0 for b1 = -1, b2 = 0 (the memo's appendix would
    // accept this: it only rejects bias == 0 && tension == 0).
    let e = Basis::Beta {
        bias: -1.0,
        tension: 0.0,
    }
    .try_rows()
    .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("tension"));
    assert!(e.message.contains("d = "), "{e}");
    // bias 0, tension 0 is fine: d = 2.
    assert!(
        Basis::Beta {
            bias: 0.0,
            tension: 0.0
        }
        .try_rows()
        .is_ok()
    );
}

#[test]
fn non_finite_parameters_are_errors() {
    let cases = [
        (Basis::Cardinal { tension: f64::NAN }, "tension"),
        (
            Basis::TensionedBSpline {
                tension: f64::INFINITY,
            },
            "tension",
        ),
        (Basis::TensionedBSpline { tension: 0.0 }, "tension"),
        (
            Basis::Beta {
                bias: f64::NAN,
                tension: 0.0,
            },
            "bias",
        ),
        (
            Basis::Beta {
                bias: 1.0,
                tension: f64::NEG_INFINITY,
            },
            "tension",
        ),
    ];
    for (basis, field) in cases {
        let e = basis.try_rows().unwrap_err();
        assert_eq!(e.field.as_deref(), Some(field), "{basis:?}");
    }
    let mut m = bspline_rows();
    m[2][1] = f64::NAN;
    let e = Basis::Matrix(m).try_rows().unwrap_err();
    assert!(e.to_string().contains("matrix[2][1]"), "{e}");
}

#[test]
fn an_overflowing_beta_parameter_is_the_one_named() {
    // bias^3 overflows: "bias" is named (it was blamed on "tension").
    let e = beta_rows(1e300, 0.0).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("bias"), "{e}");
    assert!(e.message.contains("1e300"), "{e}");
    let e = beta_rows(1e100, f64::MAX).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("tension"), "{e}");
    let e = beta_rows(-1.0, 0.0).unwrap_err();
    assert!(e.message.contains("degenerate"), "{e}");
}
