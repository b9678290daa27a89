//! Exact times of impact, in cancellation-free form.

use std::hint::select_unpredictable;

use nalgebra::SVector;

/// The earliest `t >= 0` at which the gap `h + s t + a t²` closes (reaches
/// zero while not opening), or `None` if it never does. `h` is the gap now;
/// a slightly negative `h` (an overlap of rounding size) counts as zero, so
/// the event is immediate when the gap is closing.
///
/// Both roots are taken in the form that never subtracts nearly equal
/// numbers: `2h / (−s + √Δ)` when the gap is closing (`s < 0`), and
/// `(s + √Δ) / (−2a)` when it opens now but acceleration closes it later.
#[inline]
pub(crate) fn gap_closing_time(h: f64, s: f64, a: f64) -> Option<f64> {
    let h = if h > 0.0 { h } else { 0.0 };
    if a == 0.0 {
        return if s < 0.0 { Some(h / -s) } else { None };
    }
    let disc = s * s - 4.0 * a * h;
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    if s < 0.0 {
        Some(2.0 * h / (root - s))
    } else if a < 0.0 {
        Some((s + root) / (-2.0 * a))
    } else {
        None
    }
}

/// The time `t >= 0` from now at which two balls at relative position `r`
/// (second minus first) with relative velocity `w` touch (`|r + w t| =
/// sigma`), or `+∞` if they are not approaching or miss each other.
/// Uniform gravity does not enter: both balls fall alike.
///
/// `t = c / (−b + √(b² − w² c))`, `b = r·w < 0`, `c = r² − σ²`: the root of
/// smaller magnitude without cancellation. A pair that overlaps by rounding
/// (`c <= 0`) and approaches collides at once. Written without branches
/// (the outcome is a coin toss for the neighbours of a ball in a gas, and a
/// square root costs less than a mispredicted branch); the pair of a ball
/// with itself (`r = w = 0`) gives `+∞`.
#[inline]
pub(crate) fn pair_contact_time<const D: usize>(
    r: &SVector<f64, D>,
    w: &SVector<f64, D>,
    sigma: f64,
) -> f64 {
    let b = r.dot(w);
    let c = r.norm_squared() - sigma * sigma;
    let disc = b * b - w.norm_squared() * c;
    let t = c / (disc.max(0.0).sqrt() - b);
    let t = select_unpredictable(c > 0.0, t, 0.0);
    select_unpredictable((b < 0.0) & (disc >= 0.0), t, f64::INFINITY)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn gap_without_acceleration() {
        assert_eq!(gap_closing_time(2.0, -4.0, 0.0), Some(0.5));
        assert_eq!(gap_closing_time(2.0, 4.0, 0.0), None);
        assert_eq!(gap_closing_time(-1e-17, -1.0, 0.0), Some(0.0));
    }

    #[test]
    fn gap_with_acceleration() {
        // Falling from rest through h = 4.9 with g = 9.8: t = 1.
        let t = gap_closing_time(4.9, 0.0, -4.9).unwrap();
        assert!((t - 1.0).abs() < 1e-15);
        // Thrown up at 9.8 from the floor: back at t = 2.
        let t = gap_closing_time(0.0, 9.8, -4.9).unwrap();
        assert!((t - 2.0).abs() < 1e-15);
        // Thrown towards a wall it cannot reach against the acceleration.
        assert_eq!(gap_closing_time(10.0, -1.0, 1.0), None);
        // Reaches it before turning back: 10 - 8t + t² = 0 -> t = 4 - √6.
        let t = gap_closing_time(10.0, -8.0, 1.0).unwrap();
        assert!((t - (4.0 - 6f64.sqrt())).abs() < 1e-14);
    }

    #[test]
    fn pair_head_on_and_miss() {
        let r = Vector2::new(1.0, 0.0);
        let t = pair_contact_time(&r, &Vector2::new(-2.0, 0.0), 0.5);
        assert!((t - 0.25).abs() < 1e-16);
        assert_eq!(
            pair_contact_time(&r, &Vector2::new(2.0, 0.0), 0.5),
            f64::INFINITY
        );
        // Passing with an impact parameter larger than sigma.
        let r = Vector2::new(1.0, 0.6);
        assert_eq!(
            pair_contact_time(&r, &Vector2::new(-1.0, 0.0), 0.5),
            f64::INFINITY
        );
        // Overlapping by rounding and approaching: at once; receding: never.
        let r = Vector2::new(0.5 - 1e-17, 0.0);
        assert_eq!(pair_contact_time(&r, &Vector2::new(-1.0, 0.0), 0.5), 0.0);
        assert_eq!(
            pair_contact_time(&r, &Vector2::new(1.0, 0.0), 0.5),
            f64::INFINITY
        );
        // A ball with itself, and a pair at rest.
        let zero = Vector2::zeros();
        assert_eq!(pair_contact_time(&zero, &zero, 0.5), f64::INFINITY);
        assert_eq!(pair_contact_time(&r, &zero, 0.5), f64::INFINITY);
    }
}
