//! What every file of the presentation shares in looks: each mode's
//! colour, the Pareto front's colour, and figures written for people.

use crate::shading::Shading;

/// Each mode's colour in the plot and the page (matplotlib's tab10).
pub(crate) fn mode_colour(mode: Shading) -> (u8, u8, u8) {
    match mode {
        Shading::Flat => (31, 119, 180),
        Shading::Gouraud => (44, 160, 44),
        Shading::Phong => (214, 39, 40),
        Shading::Raytrace => (148, 103, 189),
        Shading::Forward => (140, 86, 75),
    }
}

/// The colour that marks the Pareto front everywhere.
pub(crate) const PARETO_COLOUR: (u8, u8, u8) = (255, 127, 14);

/// A figure for people: 4 significant digits, scientific outside
/// [0.001, 100000), `0` for zero.
pub(crate) fn figure(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{x:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let digits = 3 - a.log10().floor() as i32;
    let s = format!("{x:.*}", digits.max(0) as usize);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::figure;

    #[test]
    fn figures_keep_four_significant_digits() {
        assert_eq!(figure(0.0), "0");
        assert_eq!(figure(12.3456), "12.35");
        assert_eq!(figure(0.0123456), "0.01235");
        assert_eq!(figure(1234.6), "1235");
        assert_eq!(figure(2.0), "2");
        assert_eq!(figure(0.00001234), "1.234e-5");
        assert_eq!(figure(0.0005), "5e-4");
        assert_eq!(figure(2.5e6), "2.5e6");
        assert_eq!(figure(-0.5), "-0.5");
        assert_eq!(figure(f64::NAN), "NaN");
    }
}
