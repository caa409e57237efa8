//! What the benches share: a line through log(time) against log(error).

/// Least squares `log(time) = a + b log(error)` through `(time, error)`
/// points: `(a, b)`.
pub fn fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let xs: Vec<f64> = points.iter().map(|p| p.1.ln()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.0.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let b = sxy / sxx;
    (my - b * mx, b)
}
