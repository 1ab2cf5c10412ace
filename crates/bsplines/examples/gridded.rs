//! A bicubic interpolant of gridded values (SciPy's `RegularGridInterpolator(method="cubic")`):
//! f(x, y) = sin(x) cos(y) on an uneven 12 x 9 grid, evaluated between the nodes, with its
//! largest error against f.
//!
//! `cargo run -p bsplines --example gridded`

use bsplines::TensorSpline;

fn main() -> Result<(), bsplines::InputError> {
    let f = |x: f64, y: f64| x.sin() * y.cos();
    let xs: Vec<f64> = (0..12)
        .map(|i| (f64::from(i) / 11.0).powf(1.3) * 3.0)
        .collect();
    let ys: Vec<f64> = (0..9).map(|j| f64::from(j) * 0.25).collect();
    let values: Vec<f64> = xs
        .iter()
        .flat_map(|&x| ys.iter().map(move |&y| f(x, y)))
        .collect();
    let spline = TensorSpline::interpolate(&[&xs, &ys], &values, 1, 3)?;

    let points: Vec<f64> = (0..40)
        .flat_map(|i| {
            let x = 3.0 * f64::from(i) / 39.0;
            (0..40).flat_map(move |j| [x, 2.0 * f64::from(j) / 39.0])
        })
        .collect();
    let got = spline.evaluate(&points);
    let worst = points
        .chunks(2)
        .zip(&got)
        .map(|(p, v)| (v - f(p[0], p[1])).abs())
        .fold(0.0, f64::max);
    println!("grid              {} x {}", xs.len(), ys.len());
    println!("s(1.5, 1.0)       {:.6}", spline.evaluate(&[1.5, 1.0])[0]);
    println!("f(1.5, 1.0)       {:.6}", f(1.5, 1.0));
    println!("max |s - f|       {worst:.2e} over {} points", got.len());
    Ok(())
}
