//! How numbers and tables are written in the markdown.

/// A number in one-digit scientific notation (`0` for zero).
pub fn e(x: f64) -> String {
    if x == 0.0 {
        "0".to_owned()
    } else if !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:.1e}")
    }
}

/// A relative deviation as a signed percentage.
pub fn pct(x: f64) -> String {
    format!("{:+.2}%", 100.0 * x)
}

/// Milliseconds with `digits` decimals, `–` for NaN (the reference's).
pub fn ms(x: f64, digits: usize) -> String {
    if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.digits$}")
    }
}
