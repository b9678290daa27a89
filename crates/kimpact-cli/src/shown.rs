//! The steps a long run shows (the page, the animation): every
//! stride-th step and the last.

/// The steps shown: 0, `stride`, 2 `stride`, … and the last step.
pub fn shown_steps(steps: u64, stride: u64) -> Vec<u64> {
    let mut out: Vec<u64> = (0..=steps).step_by(stride.max(1) as usize).collect();
    if out.last() != Some(&steps) {
        out.push(steps);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_and_last_steps_are_always_shown() {
        assert_eq!(shown_steps(3, 1), [0, 1, 2, 3]);
        assert_eq!(shown_steps(10, 4), [0, 4, 8, 10]);
        assert_eq!(shown_steps(8, 4), [0, 4, 8]);
        assert_eq!(shown_steps(5, 0), [0, 1, 2, 3, 4, 5]);
    }
}
