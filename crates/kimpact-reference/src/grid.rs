//! The uniform cell grid (cell list) over the box.

use nalgebra::SVector;

/// Relative margin by which cells are made larger than the largest diameter,
/// so that a ball whose centre lies a rounding error outside its cell still
/// meets every possible partner in the `3^D` cells around it.
const CELL_MARGIN: f64 = 1e-9;

/// A uniform grid of `n[k]` cells per axis, padded with one layer of empty
/// cells on every side so that neighbour offsets need no bounds checks.
/// Interior cell coordinates run from 1 to `n[k]`.
#[derive(Clone, Debug)]
pub(crate) struct Grid<const D: usize> {
    /// Interior cells per axis.
    pub n: [u32; D],
    /// Cell size per axis.
    pub size: [f64; D],
    /// Lower corner of the box.
    pub lo: [f64; D],
    /// Flat-index stride per axis (padded grid).
    pub stride: [usize; D],
    /// Total number of (padded) cells.
    pub total: usize,
    /// Flat offsets of the `3^D` cells around a cell (itself included).
    pub neighbours: Vec<isize>,
}

impl<const D: usize> Grid<D> {
    /// A grid over `[lo, hi]` with cells no smaller than `min_cell` (times
    /// `1 + 1e-9`) and at most about `max_cells` interior cells.
    pub fn new(
        lo: &SVector<f64, D>,
        hi: &SVector<f64, D>,
        min_cell: f64,
        max_cells: usize,
    ) -> Self {
        let lengths: [f64; D] = std::array::from_fn(|k| hi[k] - lo[k]);
        let volume: f64 = lengths.iter().product();
        let min_cell = min_cell * (1.0 + CELL_MARGIN);
        let cell = min_cell.max((volume / max_cells as f64).powf(1.0 / D as f64));
        let n: [u32; D] = std::array::from_fn(|k| {
            let count = (lengths[k] / cell).floor();
            if count.is_finite() && count >= 1.0 {
                count.min(f64::from(u32::MAX / 4)) as u32
            } else {
                1
            }
        });
        let size: [f64; D] = std::array::from_fn(|k| lengths[k] / f64::from(n[k]));
        let mut stride = [0usize; D];
        let mut total = 1usize;
        for k in 0..D {
            stride[k] = total;
            total *= n[k] as usize + 2;
        }
        let neighbours = (0..3usize.pow(D as u32))
            .map(|code| {
                let mut rest = code;
                stride
                    .iter()
                    .map(|&s| {
                        let o = (rest % 3) as isize - 1;
                        rest /= 3;
                        o * s as isize
                    })
                    .sum()
            })
            .collect();
        Self {
            n,
            size,
            lo: std::array::from_fn(|k| lo[k]),
            stride,
            total,
            neighbours,
        }
    }

    /// The interior cell coordinates of a point of the box.
    pub fn coords_of(&self, p: &SVector<f64, D>) -> [u32; D] {
        std::array::from_fn(|k| {
            let c = ((p[k] - self.lo[k]) / self.size[k]).floor();
            if c >= 0.0 {
                (c as u32).min(self.n[k] - 1) + 1
            } else {
                1
            }
        })
    }

    /// The flat index of interior coordinates.
    pub fn flat(&self, coords: &[u32; D]) -> usize {
        coords
            .iter()
            .zip(&self.stride)
            .map(|(&c, &s)| c as usize * s)
            .sum()
    }

    /// The lower boundary of cell coordinate `c` on axis `k`.
    #[inline]
    pub fn lower(&self, k: usize, c: u32) -> f64 {
        self.lo[k] + f64::from(c - 1) * self.size[k]
    }

    /// The upper boundary of cell coordinate `c` on axis `k`.
    #[inline]
    pub fn upper(&self, k: usize, c: u32) -> f64 {
        self.lo[k] + f64::from(c) * self.size[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector2, Vector3};

    #[test]
    fn layout_2d() {
        let g = Grid::<2>::new(&Vector2::zeros(), &Vector2::new(1.0, 0.5), 0.1, 1000);
        assert_eq!(g.n, [9, 4]);
        assert_eq!(g.stride, [1, 11]);
        assert_eq!(g.total, 11 * 6);
        assert_eq!(g.neighbours, vec![-12, -11, -10, -1, 0, 1, 10, 11, 12]);
        assert_eq!(g.coords_of(&Vector2::new(0.0, 0.5)), [1, 4]);
        assert_eq!(g.coords_of(&Vector2::new(0.5, 0.2)), [5, 2]);
        assert!((g.upper(0, 9) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn cell_count_is_capped() {
        let g = Grid::<3>::new(&Vector3::zeros(), &Vector3::repeat(1000.0), 0.01, 64);
        let interior: u64 = g.n.iter().map(|&n| u64::from(n)).product();
        assert!(interior <= 64, "{:?}", g.n);
    }
}
