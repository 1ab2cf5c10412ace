//! FITPACK's smoothing of gridded data, regrid (Dierckx 1993, ch. 9; fpregr, fpgrre), step
//! for step as SciPy's `RectBivariateSpline(x, y, z, s=s)` runs it: the tensor-product
//! spline s(x, y) of degrees kx, ky with
//!     fp = sum_ij (z_ij - s(x_i, y_j))^2 <= s
//! on the fewest knots FITPACK's search finds, then the smoothest on those knots with
//! fp = s.
//!
//! A fit on given knots (`grid_fit`, fpgrre) is separable: the x-direction observation
//! matrix is rotated into a triangle R_x (the rows of the k-th derivative jumps at the inner
//! knots, weighted 1/p, rotated in too when smoothing) with the same rotations applied to the
//! columns of z, then the y direction likewise on the result, and (R_y) C (R_x)' = H is
//! solved by back substitution twice. The knots grow as curfit's (`curfit::add_knot` on each
//! direction's residual shares), in the direction whose next count of knots is the smaller
//! (alternating on ties), until fp <= s; p is then found as curfit finds it, from p = 1.

use crate::curfit::{
    self, Door, add_knot, basis, discontinuity, find_p, givens, knots_to_add, rotate,
};
use crate::fitpack::TOLERANCE;

/// Gridded data: x (mx, strictly increasing), y (my, strictly increasing), z (mx rows of my)
/// and the rectangle [xb, xe] x [yb, ye] around them.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a> {
    /// The x values.
    pub x: &'a [f64],
    /// The y values.
    pub y: &'a [f64],
    /// The values, z[i * my + j] at (x_i, y_j).
    pub z: &'a [f64],
    /// The rectangle: xb, xe, yb, ye.
    pub bounds: [f64; 4],
}

/// A tensor-product fit: the knots in x and y, the coefficients ((len(tx) - kx - 1) rows of
/// len(ty) - ky - 1), fp and FITPACK's ier (-2 the polynomial, -1 interpolation, 0 fp within
/// s/1000 of s, 1 the knots' room ran out, 2 and 3 the search for p stopped short).
#[derive(Clone, Debug)]
pub struct GridSpline {
    /// Knots in x.
    pub tx: Vec<f64>,
    /// Knots in y.
    pub ty: Vec<f64>,
    /// Coefficients, c[ix * ny1 + iy].
    pub c: Vec<f64>,
    /// sum_ij (z_ij - s(x_i, y_j))^2.
    pub fp: f64,
    /// FITPACK's ier.
    pub ier: i32,
}

/// One direction's B-splines at its data: k + 1 values a point, and the knot interval each
/// point is in (counted from the first).
struct Direction {
    values: Vec<f64>,
    interval: Vec<usize>,
}

fn direction(x: &[f64], t: &[f64], k: usize) -> Direction {
    let (k1, n) = (k + 1, t.len());
    let nk1 = n - k1;
    let (mut values, mut interval) = (vec![0.0; x.len() * k1], vec![0; x.len()]);
    let (mut l, mut number) = (k, 0);
    let mut h = [0.0; 6];
    for (it, &arg) in x.iter().enumerate() {
        while !(arg < t[l + 1] || l + 1 == nk1) {
            l += 1;
            number += 1;
        }
        basis(t, k, arg, l, &mut h);
        values[it * k1..(it + 1) * k1].copy_from_slice(&h[..k1]);
        interval[it] = number;
    }
    Direction { values, interval }
}

/// Back substitution of an upper triangular band (fpback): a (rows, stored `stride` wide),
/// `band` columns in use; z replaced by the solution.
fn back_band(a: &[f64], stride: usize, band: usize, z: &mut [f64]) {
    let rows = z.len();
    for i in (0..rows).rev() {
        let mut store = z[i];
        for l in 1..band.min(rows - i) {
            store -= z[i + l] * a[i * stride + l];
        }
        z[i] = store / a[i * stride];
    }
}

/// A direction's triangle as it is rotated: the upper triangular band `a` (stride k + 2)
/// and its rows' right-hand sides (`width` a row). It has k + 1 rows more than the
/// coefficients, as FITPACK's storage has: a row's band reaches past the last coefficient,
/// and where the fit is not finite (knots that coincide) a rotation lands there.
struct Rotated {
    a: Vec<f64>,
    rows: Vec<f64>,
    width: usize,
}

impl Rotated {
    fn zeroed(coefficients: usize, k: usize, width: usize) -> Self {
        let rows = coefficients + k + 1;
        Self {
            a: vec![0.0; rows * (k + 2)],
            rows: vec![0.0; rows * width],
            width,
        }
    }
}

/// Rotates one direction's rows into `out`: its data rows (the B-splines of each point, in
/// order, with their right-hand sides from `rhs(point)`) and, when smoothing (`jumps`: the
/// jump rows and 1/p), each jump row / p after the data rows of the interval before it
/// (right-hand side zero). Returns the band in use (k + 1, or k + 2 once a jump row is in).
fn triangle(
    dir: &Direction,
    k: usize,
    jumps: Option<(&[[f64; 7]], f64)>,
    out: &mut Rotated,
    mut rhs: impl FnMut(usize, &mut [f64]),
) -> usize {
    let (k1, k2, width) = (k + 1, k + 2, out.width);
    let mut band = k1;
    let mut right = vec![0.0; width];
    let mut h = [0.0; 7];
    let mut nrold = 0;
    for (it, &number) in dir.interval.iter().enumerate() {
        loop {
            let first_row;
            if nrold == number {
                h[band - 1] = 0.0;
                h[..k1].copy_from_slice(&dir.values[it * k1..(it + 1) * k1]);
                rhs(it, &mut right);
                first_row = number;
            } else {
                let Some((rows, pinv)) = jumps else {
                    nrold += 1;
                    continue;
                };
                band = k2;
                for (hv, b) in h.iter_mut().zip(&rows[nrold][..k2]) {
                    *hv = b * pinv;
                }
                right.fill(0.0);
                first_row = nrold;
            }
            for i in 0..band {
                let row = first_row + i;
                let piv = h[i];
                if piv == 0.0 {
                    continue;
                }
                let rotation = givens(piv, &mut out.a[row * k2]);
                let rhs_row = &mut out.rows[row * width..(row + 1) * width];
                for (r, q) in right.iter_mut().zip(rhs_row) {
                    rotate(rotation, r, q);
                }
                let band_row = &mut out.a[row * k2 + 1..row * k2 + band - i];
                for (hv, a) in h[i + 1..band].iter_mut().zip(band_row) {
                    rotate(rotation, hv, a);
                }
            }
            if nrold == number {
                break;
            }
            nrold += 1;
        }
    }
    band
}

/// One fit on the knots tx, ty (fpgrre): least squares (p None) or smoothing with weight 1/p
/// on the jumps. Returns the coefficients, fp and each direction's residual shares (the
/// residual of a point on an inner knot split between its two intervals).
fn grid_fit(
    grid: &Grid<'_>,
    (kx, ky): (usize, usize),
    tx: &[f64],
    ty: &[f64],
    p: Option<f64>,
) -> (Vec<f64>, f64, Vec<f64>, Vec<f64>) {
    let (mx, my) = (grid.x.len(), grid.y.len());
    let (nk1x, nk1y) = (tx.len() - kx - 1, ty.len() - ky - 1);
    let dx = direction(grid.x, tx, kx);
    let dy = direction(grid.y, ty, ky);
    let jumps = |t: &[f64], k: usize| match p {
        Some(_) if t.len() != 2 * (k + 1) => discontinuity(t, k),
        _ => Vec::new(),
    };
    let (jumps_x, jumps_y) = (jumps(tx, kx), jumps(ty, ky));
    // x: the rows of z rotated with the x-direction rows (nk1x rows of my).
    let mut rx = Rotated::zeroed(nk1x, kx, my);
    let band_x = triangle(
        &dx,
        kx,
        p.map(|p| (jumps_x.as_slice(), 1.0 / p)),
        &mut rx,
        |it, right| {
            right.copy_from_slice(&grid.z[it * my..(it + 1) * my]);
        },
    );
    // y: the columns of those rotated with the y-direction rows (nk1y rows of nk1x).
    let mut ry = Rotated::zeroed(nk1y, ky, nk1x);
    let band_y = triangle(
        &dy,
        ky,
        p.map(|p| (jumps_y.as_slice(), 1.0 / p)),
        &mut ry,
        |it, right| {
            for (j, r) in right.iter_mut().enumerate() {
                *r = rx.rows[j * my + it];
            }
        },
    );
    // (R_y) C (R_x)' = H, C stored as c[ix * nk1y + iy] (FITPACK's order).
    let mut c = vec![0.0; nk1x * nk1y];
    let mut column = vec![0.0; nk1y];
    for ix in 0..nk1x {
        for (iy, v) in column.iter_mut().enumerate() {
            *v = ry.rows[iy * nk1x + ix];
        }
        back_band(&ry.a, ky + 2, band_y, &mut column);
        c[ix * nk1y..(ix + 1) * nk1y].copy_from_slice(&column);
    }
    let mut row = vec![0.0; nk1x];
    for iy in 0..nk1y {
        for (ix, v) in row.iter_mut().enumerate() {
            *v = c[ix * nk1y + iy];
        }
        back_band(&rx.a, kx + 2, band_x, &mut row);
        for (ix, v) in row.iter().enumerate() {
            c[ix * nk1y + iy] = *v;
        }
    }
    // Residuals: fp and each direction's shares.
    let (kx1, ky1) = (kx + 1, ky + 1);
    let mut fp = 0.0;
    let (mut fpx, mut fpy) = (vec![0.0; tx.len()], vec![0.0; ty.len()]);
    let mut nroldx = 0;
    for i1 in 0..mx {
        let numx = dx.interval[i1];
        let mut nroldy = 0;
        for i2 in 0..my {
            let numy = dy.interval[i2];
            let mut term = 0.0;
            for l1 in 0..kx1 {
                let fac = dx.values[i1 * kx1 + l1];
                let base = (numx + l1) * nk1y + numy;
                for l2 in 0..ky1 {
                    term += fac * dy.values[i2 * ky1 + l2] * c[base + l2];
                }
            }
            let term = (grid.z[i1 * my + i2] - term).powi(2);
            fp += term;
            fpx[numx] += term;
            fpy[numy] += term;
            let half = term * 0.5;
            if numy != nroldy {
                fpy[numy] -= half;
                fpy[numy - 1] += half;
            }
            nroldy = numy;
            if numx != nroldx {
                fpx[numx] -= half;
                fpx[numx - 1] += half;
            }
        }
        nroldx = numx;
    }
    (c, fp, fpx, fpy)
}

/// The knots of interpolation in one direction (`curfit`'s), inside the ends `t` has.
fn interpolation_knots(x: &[f64], k: usize, t: &mut Vec<f64>) {
    *t = curfit::interpolation_knots(x, k, t[0], t[t.len() - 1]);
}

/// One direction's knot search state: knots, data counts per interval, the count added last
/// and the fall of fp it brought.
struct Axis {
    t: Vec<f64>,
    nrdata: Vec<usize>,
    nplus: usize,
    reduction: f64,
}

/// FITPACK's regrid with s > 0 on the grid, degrees kx, ky (1 to 5), room for nxest and
/// nyest knots, at most `maxit` iterations for p, from the polynomial (iopt = 0). The caller
/// has checked the data as regrid does (x and y strictly increasing inside the rectangle,
/// len(x) > kx, len(y) > ky, z finite).
pub fn smoothing_fit(
    grid: &Grid<'_>,
    (kx, ky): (usize, usize),
    s: f64,
    (nxest, nyest): (usize, usize),
    maxit: usize,
) -> GridSpline {
    let (mx, my) = (grid.x.len(), grid.y.len());
    let [xb, xe, yb, ye] = grid.bounds;
    let (nminx, nminy) = (2 * kx + 2, 2 * ky + 2);
    let (nmaxx, nmaxy) = (mx + kx + 1, my + ky + 1);
    let (nxe, nye) = (nxest.min(nmaxx), nyest.min(nmaxy));
    let acc = TOLERANCE * s;
    let polynomial = |b: f64, e: f64, k: usize| {
        let mut t = vec![b; k + 1];
        t.resize(2 * k + 2, e);
        t
    };
    let mut ax = Axis {
        t: polynomial(xb, xe, kx),
        nrdata: vec![mx - 2],
        nplus: 0,
        reduction: 0.0,
    };
    let mut ay = Axis {
        t: polynomial(yb, ye, ky),
        nrdata: vec![my - 2],
        nplus: 0,
        reduction: 0.0,
    };
    let (mut ier, mut lastdi, mut fp0, mut fpold) = (0, 0_i8, 0.0, 0.0);
    let done = |ax: &Axis, ay: &Axis, c, fp, ier| GridSpline {
        tx: ax.t.clone(),
        ty: ay.t.clone(),
        c,
        fp,
        ier,
    };
    let mut fpms;
    let mut last;
    let mut rounds = 0;
    loop {
        if ax.t.len() == nminx && ay.t.len() == nminy {
            ier = -2;
        }
        for (axis, (b, e, k)) in [(&mut ax, (xb, xe, kx)), (&mut ay, (yb, ye, ky))] {
            let n = axis.t.len();
            axis.t[..=k].fill(b);
            axis.t[n - k - 1..].fill(e);
        }
        let (c, fp, fpx, fpy) = grid_fit(grid, (kx, ky), &ax.t, &ay.t, None);
        if ier == -2 {
            fp0 = fp;
        }
        fpms = fp - s;
        if fpms.abs() < acc {
            return done(&ax, &ay, c, fp, ier);
        }
        last = (c, fp);
        if fpms < 0.0 || rounds == mx + my {
            break;
        }
        if ax.t.len() == nmaxx && ay.t.len() == nmaxy {
            return done(&ax, &ay, last.0, 0.0, -1);
        }
        if ax.t.len() == nxe && ay.t.len() == nye {
            return done(&ax, &ay, last.0, last.1, 1);
        }
        ier = 0;
        match lastdi.cmp(&0) {
            std::cmp::Ordering::Less => ax.reduction = fpold - fp,
            std::cmp::Ordering::Greater => ay.reduction = fpold - fp,
            std::cmp::Ordering::Equal => {}
        }
        fpold = fp;
        let next = |axis: &Axis, nmin: usize| {
            if axis.t.len() == nmin {
                1
            } else {
                knots_to_add(axis.nplus, fpms, axis.reduction, acc)
            }
        };
        let (nplx, nply) = (next(&ax, nminx), next(&ay, nminy));
        // x where its count is the smaller (or equal and y went last), unless x is full.
        let mut in_x = nplx < nply || (nplx == nply && lastdi >= 0);
        if in_x && ax.t.len() == nxe {
            in_x = false;
        } else if !in_x && ay.t.len() == nye {
            in_x = true;
        }
        let (axis, values, nplus, fpint, nmax, ne, k) = if in_x {
            lastdi = -1;
            (&mut ax, grid.x, nplx, fpx, nmaxx, nxe, kx)
        } else {
            lastdi = 1;
            (&mut ay, grid.y, nply, fpy, nmaxy, nye, ky)
        };
        axis.nplus = nplus;
        let nrint = axis.t.len() - 2 * k - 1;
        let mut fpint = fpint[..nrint].to_vec();
        let mut interpolating = false;
        for _ in 0..nplus {
            if !add_knot(values, &mut axis.t, k, &mut fpint, &mut axis.nrdata) {
                // fpknot finds no interval with a point inside: FITPACK counts a knot all the
                // same (the end's, its interval empty), and regrid goes on so until the knots
                // of interpolation take over.
                let end = axis.t[axis.t.len() - 1];
                axis.t.push(end);
                fpint.push(0.0);
                axis.nrdata.push(0);
            }
            if axis.t.len() == nmax {
                interpolation_knots(values, k, &mut axis.t);
                interpolating = true;
                break;
            }
            if axis.t.len() == ne {
                break;
            }
        }
        if interpolating && in_x && kx % 2 == 1 {
            // fpregr's own path: after x's knots of interpolation for odd kx it goes on to
            // write y's over the y knots it has (their count kept, their order as it falls).
            let mut interpolation = ay.t.clone();
            interpolation_knots(grid.y, ky, &mut interpolation);
            let n = ay.t.len();
            for (i, v) in interpolation.into_iter().enumerate().take(my).skip(ky + 1) {
                if i < n {
                    ay.t[i] = v;
                }
            }
        }
        rounds += 1;
    }
    if ier == -2 {
        return done(&ax, &ay, last.0, last.1, ier);
    }
    let spline_for = |p: f64| {
        let (c, fp, _, _) = grid_fit(grid, (kx, ky), &ax.t, &ay.t, Some(p));
        (c, fp)
    };
    let (c, fp, ier) = find_p(
        spline_for,
        1.0,
        (fp0, fpms),
        (s, acc),
        Door::Parcur.steps(),
        maxit,
    );
    done(&ax, &ay, c, fp, ier)
}

#[cfg(test)]
mod tests {
    use super::{Grid, GridSpline, smoothing_fit};
    use crate::curfit::basis;

    /// s(x_i, y_j) for every grid point, by the B-splines of each direction (knots in order).
    fn values(fit: &GridSpline, (kx, ky): (usize, usize), x: &[f64], y: &[f64]) -> Vec<f64> {
        let ny1 = fit.ty.len() - ky - 1;
        let at = |t: &[f64], k: usize, v: f64| {
            let l = (k..t.len() - k - 1)
                .rfind(|&l| t[l] <= v)
                .unwrap_or(k)
                .min(t.len() - k - 2);
            let mut h = [0.0; 6];
            basis(t, k, v, l, &mut h);
            (l - k, h)
        };
        let mut out = Vec::new();
        for &xv in x {
            let (ix, hx) = at(&fit.tx, kx, xv);
            for &yv in y {
                let (iy, hy) = at(&fit.ty, ky, yv);
                let mut sum = 0.0;
                for (a, bx) in hx[..=kx].iter().enumerate() {
                    for (b, by) in hy[..=ky].iter().enumerate() {
                        sum += bx * by * fit.c[(ix + a) * ny1 + iy + b];
                    }
                }
                out.push(sum);
            }
        }
        out
    }

    /// A polynomial of degrees (3, 2) is its own least-squares polynomial (ier -2), fitted
    /// exactly; noisy data give a spline with fp within s/1000 of s, fp the residual at the
    /// grid.
    #[test]
    fn polynomials_are_kept_and_fits_meet_s() {
        let x: Vec<f64> = (0..12).map(|i| f64::from(i) * 0.3).collect();
        let y: Vec<f64> = (0..15).map(|j| f64::from(j) * 0.2 - 1.0).collect();
        let bounds = [x[0], x[11], y[0], y[14]];
        let cubic: Vec<f64> = x
            .iter()
            .flat_map(|&a| {
                y.iter()
                    .map(move |&b| a * a * a - 2.0 * a * b * b + b + 0.5)
            })
            .collect();
        let grid = Grid {
            x: &x,
            y: &y,
            z: &cubic,
            bounds,
        };
        let fit = smoothing_fit(&grid, (3, 2), 1e-3, (16, 18), 20);
        assert_eq!((fit.ier, fit.tx.len(), fit.ty.len()), (-2, 8, 6));
        for (got, want) in values(&fit, (3, 2), &x, &y).iter().zip(&cubic) {
            assert!((got - want).abs() < 1e-12, "{got} {want}");
        }
        let noisy: Vec<f64> = cubic
            .iter()
            .enumerate()
            .map(|(i, v)| v.sin() + 0.05 * ((i * 7919 % 101) as f64 / 50.0 - 1.0))
            .collect();
        let grid = Grid {
            x: &x,
            y: &y,
            z: &noisy,
            bounds,
        };
        for (kx, ky) in [(3, 3), (1, 2), (5, 1)] {
            let fit = smoothing_fit(&grid, (kx, ky), 0.05, (12 + kx + 1, 15 + ky + 1), 20);
            assert_eq!(fit.ier, 0, "{kx} {ky}");
            assert!((fit.fp - 0.05).abs() < 5e-5, "{kx} {ky}: {}", fit.fp);
            let residual: f64 = values(&fit, (kx, ky), &x, &y)
                .iter()
                .zip(&noisy)
                .map(|(s, z)| (z - s).powi(2))
                .sum();
            assert!(
                (residual - fit.fp).abs() < 1e-10,
                "{kx} {ky}: {residual} {}",
                fit.fp
            );
        }
    }
}
