//! FITPACK's smoothing for a target s (SciPy's `make_splrep(x, y, s=s)`): the spline with the
//! fewest knots FITPACK's search finds whose weighted residual fp meets s. 300 samples of
//! sin(x) with noise of σ = 0.1, so n·σ² = 3: below it the search places many knots and
//! follows the noise, above it few. Prints each s with its knots, fp and FITPACK's ier.
//!
//! `cargo run -p bsplines --example splrep`

use bsplines::{Series, Splrep, splrep};

mod noise;

fn main() -> Result<(), bsplines::InputError> {
    let mut noise = noise::Gaussian::new(11);
    let x: Vec<f64> = (0..300).map(|i| f64::from(i) * 0.03).collect();
    let y: Vec<f64> = x.iter().map(|v| v.sin() + 0.1 * noise.next()).collect();
    let data = Series::new(&x, &y);
    println!("{:>6} {:>6} {:>10} {:>4}", "s", "knots", "fp", "ier");
    for s in [0.3, 1.0, 3.0, 10.0, 30.0] {
        let fit = splrep(&data, 3, s, Splrep::default())?;
        let fitted = fit.spline.evaluate(&x, 0);
        let fp: f64 = fitted.iter().zip(&y).map(|(f, v)| (f - v).powi(2)).sum();
        println!(
            "{s:>6} {:>6} {fp:>10.4} {:>4}",
            fit.spline.knots().len(),
            fit.ier
        );
    }
    Ok(())
}
