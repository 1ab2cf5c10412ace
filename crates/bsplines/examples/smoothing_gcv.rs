//! A cubic smoothing spline of noisy data, lam chosen by generalised cross-validation (SciPy's
//! `make_smoothing_spline(x, y)`): 200 samples of sin(x) with Gaussian noise of σ = 0.1, the
//! lam GCV picks, and how far the spline lies from the noise-free curve against how far the
//! data do.
//!
//! `cargo run -p bsplines --example smoothing_gcv`

use bsplines::{Lam, Series, smoothing_spline};

mod noise;

fn main() -> Result<(), bsplines::InputError> {
    let mut noise = noise::Gaussian::new(7);
    let x: Vec<f64> = (0..200).map(|i| f64::from(i) * 0.05).collect();
    let truth: Vec<f64> = x.iter().map(|v| v.sin()).collect();
    let y: Vec<f64> = truth.iter().map(|v| v + 0.1 * noise.next()).collect();

    let fit = smoothing_spline(&Series::new(&x, &y), Lam::Gcv)?;
    let smoothed = fit.spline.evaluate(&x, 0);
    let rms = |a: &[f64]| {
        let sum: f64 = a.iter().zip(&truth).map(|(v, t)| (v - t).powi(2)).sum();
        (sum / a.len() as f64).sqrt()
    };
    println!("points            {}", x.len());
    println!("lam (GCV)         {:.6e}", fit.lams[0]);
    println!("knots             {}", fit.spline.knots().len());
    println!("rms(data - sin)   {:.4}", rms(&y));
    println!("rms(spline - sin) {:.4}", rms(&smoothed));
    Ok(())
}
