//! A uniform grid of boxes, for joins of many boxes at once (the replay's
//! bulk sweep, the calm-neighbourhood test).

use crate::math::{DIM, Real, Vector};
use crate::rapier::prelude::*;

/// A uniform grid of boxes (the swept boxes of the bulk sweep), in
/// compressed rows: each box is stored once, in the cell of its low corner,
/// and the boxes of cell `c` are `items[start[c]..start[c + 1]]`. Cells are
/// a quarter larger than the largest box, so a box meeting a query has its
/// low corner less than one cell (by a fifth of a cell, far more than any
/// rounding of the cell coordinates) below the query's. Kept between steps:
/// no allocation in a steady state.
pub(crate) struct SweepGrid {
    origin: Vector,
    inv_cell: Real,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<GridItem>,
    /// Scratch of `build`: each box's cell, from the counting pass to the
    /// placing pass.
    box_cells: Vec<u32>,
}

/// A box in a [`SweepGrid`] cell.
#[derive(Copy, Clone, Debug)]
struct GridItem {
    /// The box's number in the order it was given to [`SweepGrid::build`].
    index: u32,
    aabb: Aabb,
}

impl Default for SweepGrid {
    fn default() -> Self {
        Self {
            origin: Vector::ZERO,
            inv_cell: 1.0,
            dims: [1; 3],
            start: Vec::new(),
            items: Vec::new(),
            box_cells: Vec::new(),
        }
    }
}

impl SweepGrid {
    /// Cells per box at most (the grid coarsens beyond).
    const CELLS_PER_BOX: usize = 8;

    /// Grid the boxes: cells a quarter larger than the largest box, coarser
    /// if that would make more than `CELLS_PER_BOX` cells per box.
    /// `false` (nothing built) if the boxes span more than the scalar type
    /// can hold.
    pub(crate) fn build(&mut self, boxes: impl Iterator<Item = Aabb> + Clone) -> bool {
        let mut lo = Vector::splat(Real::MAX);
        let mut hi = Vector::splat(Real::MIN);
        let mut largest: Real = 0.0;
        let mut n = 0;
        for b in boxes.clone() {
            lo = lo.min(b.mins);
            hi = hi.max(b.maxs);
            largest = largest.max((b.maxs - b.mins).max_element());
            n += 1;
        }
        let extent = hi - lo;
        if !(extent.is_finite() && largest.is_finite()) {
            return false;
        }
        let mut cell = (1.25 * largest)
            .max(Real::EPSILON * extent.max_element())
            .max(Real::MIN_POSITIVE);
        // Counted in floating point: no overflow whatever the extents.
        let count = |cell: Real| -> f64 {
            (0..DIM)
                .map(|k| (f64::from(extent[k]) / f64::from(cell)).floor() + 1.0)
                .product()
        };
        while count(cell) > (Self::CELLS_PER_BOX * n.max(1)) as f64 {
            cell *= 2.0;
        }
        if !cell.is_finite() {
            return false;
        }
        self.origin = lo;
        self.inv_cell = 1.0 / cell;
        self.dims = [1; 3];
        for (k, d) in self.dims.iter_mut().enumerate().take(DIM) {
            *d = (extent[k] * self.inv_cell) as usize + 1;
        }
        let cells: usize = self.dims.iter().product();
        // Counting sort of the boxes by the cell of their low corner:
        // `start[c + 1]` counts cell c, then (prefix sums, shifted by one)
        // is cell c's next free slot, which ends as the start of cell c + 1.
        self.start.clear();
        self.start.resize(cells + 1, 0);
        let mut box_cells = std::mem::take(&mut self.box_cells);
        box_cells.clear();
        for b in boxes.clone() {
            let c = self.cell_of(b.mins);
            self.start[c + 1] += 1;
            box_cells.push(c as u32);
        }
        // The sum runs in a register: `start[c + 1] += start[c]` would
        // wait on the store of the previous cell at every cell.
        let mut sum = 0;
        for s in &mut self.start {
            sum += *s;
            *s = sum;
        }
        self.start.rotate_right(1);
        self.start[0] = 0;
        let placeholder = GridItem {
            index: 0,
            aabb: Aabb::new_invalid(),
        };
        self.items.clear();
        self.items.resize(n, placeholder);
        for (i, (b, &c)) in boxes.zip(&box_cells).enumerate() {
            let c = c as usize;
            self.items[self.start[c + 1] as usize] = GridItem {
                index: i as u32,
                aabb: b,
            };
            self.start[c + 1] += 1;
        }
        self.box_cells = box_cells;
        true
    }

    /// The cell of a point inside the grid's extent.
    fn cell_of(&self, p: Vector) -> usize {
        let mut c = 0;
        for k in (0..DIM).rev() {
            let x = ((p[k] - self.origin[k]) * self.inv_cell) as usize;
            c = c * self.dims[k] + x.min(self.dims[k] - 1);
        }
        c
    }

    /// The cells whose boxes may meet `b` (their low corners lie between
    /// one cell below `b`'s and `b`'s high corner), clamped to the grid;
    /// `None` if there are none (or `b` is not finite).
    fn range(&self, b: &Aabb) -> Option<[[usize; 2]; 3]> {
        let mut r = [[0, 0]; 3];
        for (k, rk) in r.iter_mut().enumerate().take(DIM) {
            let lo = (b.mins[k] - self.origin[k]) * self.inv_cell - 1.0;
            let hi = (b.maxs[k] - self.origin[k]) * self.inv_cell;
            let last = (self.dims[k] - 1) as Real;
            if !(hi >= 0.0 && lo < last + 1.0) {
                return None;
            }
            *rk = [
                lo.max(0.0).min(last) as usize,
                hi.max(0.0).min(last) as usize,
            ];
        }
        Some(r)
    }

    /// Call `f(a, b)` once for every two boxes `a < b` that meet, in no
    /// particular order. Boxes that meet have low corners less than a box
    /// (so less than a cell) apart on every axis: their cells are the same
    /// or neighbours. Each cell is joined with itself and with the
    /// neighbours after it in memory order (along x, then the three cells
    /// of each later row it touches), so each pair of cells once.
    #[cfg(any(test, not(feature = "parallel")))]
    pub(crate) fn self_join(&self, f: impl FnMut(u32, u32)) {
        let [_, ny, nz] = self.dims;
        self.join_rows(0..ny * nz, f);
    }

    /// `SweepGrid::self_join` with `f` run on rayon's pool (the current
    /// one: rapier's, inside its step): `f`'s results (those it gives) for
    /// every two boxes that meet, appended to `out` in the order
    /// `self_join` calls `f`, whatever the number of threads. Rows of cells are shared out in
    /// runs, each run's results collected apart and joined in row order.
    #[cfg(feature = "parallel")]
    pub(crate) fn par_self_join<T: Send>(
        &self,
        f: impl Fn(u32, u32) -> Option<T> + Sync,
        out: &mut Vec<T>,
    ) {
        use rayon::prelude::*;
        let [_, ny, nz] = self.dims;
        let rows = ny * nz;
        // Several runs per thread, so that a crowded run does not leave
        // the other threads idle.
        let run = rows.div_ceil(8 * rayon::current_num_threads()).max(1);
        let parts: Vec<Vec<T>> = (0..rows.div_ceil(run))
            .into_par_iter()
            .map(|r| {
                let mut part = Vec::new();
                self.join_rows(r * run..((r + 1) * run).min(rows), |a, b| {
                    part.extend(f(a, b));
                });
                part
            })
            .collect();
        out.reserve(parts.iter().map(Vec::len).sum());
        for part in parts {
            out.extend(part);
        }
    }

    /// `self_join` over the rows (`z * ny + y`) in `rows`, in order: each
    /// cell of those rows joined with itself and the neighbours after it.
    fn join_rows(&self, rows: std::ops::Range<usize>, mut f: impl FnMut(u32, u32)) {
        let [nx, ny, nz] = self.dims;
        let mut test = |a: &GridItem, b: &GridItem| {
            if a.aabb.intersects(&b.aabb) {
                f(a.index.min(b.index), a.index.max(b.index));
            }
        };
        // The items of cells x0..=x1 (clamped) of row (y, z).
        let run = |x0: usize, x1: usize, y: usize, z: usize| -> &[GridItem] {
            let row = (z * ny + y) * nx;
            let (from, to) = (row + x0, row + x1.min(nx - 1));
            &self.items[self.start[from] as usize..self.start[to + 1] as usize]
        };
        // The later rows a row touches: (dy, dz) after (0, 0).
        let later: &[(isize, isize)] = if DIM == 2 {
            &[(1, 0)]
        } else {
            &[(1, 0), (-1, 1), (0, 1), (1, 1)]
        };
        for row in rows {
            let (y, z) = (row % ny, row / ny);
            for x in 0..nx {
                let here = run(x, x, y, z);
                if here.is_empty() {
                    continue;
                }
                for (i, a) in here.iter().enumerate() {
                    for b in &here[i + 1..] {
                        test(a, b);
                    }
                }
                let mut others: [&[GridItem]; 5] = [&[]; 5];
                if x + 1 < nx {
                    others[0] = run(x + 1, x + 1, y, z);
                }
                for (slot, &(dy, dz)) in others[1..].iter_mut().zip(later) {
                    let (Some(y2), Some(z2)) = (y.checked_add_signed(dy), z.checked_add_signed(dz))
                    else {
                        continue;
                    };
                    if y2 < ny && z2 < nz {
                        *slot = run(x.saturating_sub(1), x + 1, y2, z2);
                    }
                }
                for a in here {
                    for other in others {
                        for b in other {
                            test(a, b);
                        }
                    }
                }
            }
        }
    }

    /// Call `f` once with the index of every box that meets `aabb`, in
    /// no particular order.
    pub(crate) fn overlaps(&self, aabb: &Aabb, mut f: impl FnMut(u32)) {
        let Some(r) = self.range(aabb) else { return };
        for z in r[2][0]..=r[2][1] {
            for y in r[1][0]..=r[1][1] {
                // A row of cells along x is one run of items.
                let row = (z * self.dims[1] + y) * self.dims[0];
                let (from, to) = (row + r[0][0], row + r[0][1]);
                for item in &self.items[self.start[from] as usize..self.start[to + 1] as usize] {
                    if aabb.intersects(&item.aabb) {
                        f(item.index);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
#[allow(clippy::unnecessary_cast)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// Every two boxes `s < t` that meet, by brute force, in order.
    fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for (s, a) in boxes.iter().enumerate() {
            for (t, b) in boxes.iter().enumerate().skip(s + 1) {
                if a.intersects(b) {
                    pairs.push((s as u32, t as u32));
                }
            }
        }
        pairs
    }

    /// The grid's lookups, deduplicated as the bulk sweep does, give every
    /// overlapping (box, query) pair exactly once: against brute force, for
    /// boxes of mixed sizes, queries partly or wholly outside the grid, and
    /// one query larger than the whole grid (a wall).
    #[test]
    fn the_sweep_grid_finds_every_overlap_once() {
        let mut rng = TestRng::new(7);
        for size in [0.05, 0.5, 3.0] {
            let boxes: Vec<Aabb> = (0..300).map(|_| rng.aabb(10.0, size)).collect();
            let mut queries: Vec<Aabb> = (0..300).map(|_| rng.aabb(14.0, 1.0)).collect();
            queries.push(Aabb::new(Vector::splat(-100.0), Vector::splat(100.0)));
            let mut grid = SweepGrid::default();
            assert!(grid.build(boxes.iter().copied()));
            let mut found = Vec::new();
            for (q, aabb) in queries.iter().enumerate() {
                grid.overlaps(aabb, |s| found.push((s, q)));
            }
            found.sort_unstable();
            let mut brute = Vec::new();
            for (s, b) in boxes.iter().enumerate() {
                for (q, aabb) in queries.iter().enumerate() {
                    if aabb.intersects(b) {
                        brute.push((s as u32, q));
                    }
                }
            }
            brute.sort_unstable();
            assert!(brute.len() > 300, "size {size}: {} overlaps", brute.len());
            assert_eq!(found, brute, "size {size}");
            // The boxes against each other, as the bulk sweep joins the
            // sweepers: each overlapping pair once, from its first box.
            let mut joined = Vec::new();
            grid.self_join(|s, t| joined.push((s, t)));
            joined.sort_unstable();
            let brute = overlapping_pairs(&boxes);
            assert!(
                size < 3.0 || brute.len() > 100,
                "size {size}: {} pairs",
                brute.len()
            );
            assert_eq!(joined, brute, "size {size}: the join");
        }
    }

    /// Boxes that only touch a query (a shared face or corner: `intersects`
    /// counts them) are found too, far from the grid's origin and at the
    /// largest box size, where a box's low corner lies a whole box below
    /// the query's.
    #[test]
    fn the_sweep_grid_finds_boxes_that_only_touch() {
        let size = 0.5;
        let base = Vector::splat(1000.0);
        let at = |i: usize| -> Vector {
            let mut p = base;
            for k in 0..DIM {
                p[k] += size * ((i >> (4 * k)) % 16) as Real;
            }
            p
        };
        // A lattice of boxes, each touching its neighbours.
        let boxes: Vec<Aabb> = (0..1 << (4 * DIM))
            .map(|i| Aabb::new(at(i), at(i) + Vector::splat(size)))
            .collect();
        let mut grid = SweepGrid::default();
        assert!(grid.build(boxes.iter().copied()));
        for (q, query) in boxes.iter().enumerate().step_by(7) {
            let mut found = Vec::new();
            grid.overlaps(query, |s| found.push(s));
            found.sort_unstable();
            let brute: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&s| query.intersects(&boxes[s as usize]))
                .collect();
            assert!(brute.len() > 1, "box {q} touches its neighbours");
            assert_eq!(found, brute, "box {q}");
        }
        // And against each other, as the bulk sweep joins the sweepers.
        let mut joined = Vec::new();
        grid.self_join(|s, t| joined.push((s, t)));
        joined.sort_unstable();
        assert_eq!(joined, overlapping_pairs(&boxes), "the join");
    }

    /// On rayon's pool, the join gives every pair in the very order of the
    /// serial join, at 1, 2, 3 and 4 threads, for sparse and crowded
    /// boxes (many pairs per row of cells).
    #[cfg(feature = "parallel")]
    #[test]
    fn the_parallel_join_keeps_the_serial_order() {
        let mut rng = TestRng::new(11);
        for size in [0.5, 1.5, 3.0] {
            let boxes: Vec<Aabb> = (0..2000).map(|_| rng.aabb(10.0, size)).collect();
            let mut grid = SweepGrid::default();
            assert!(grid.build(boxes.iter().copied()));
            let mut serial = Vec::new();
            grid.self_join(|s, t| serial.push((s, t)));
            assert!(serial.len() > 100, "size {size}: {} pairs", serial.len());
            for threads in 1..=4 {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("a pool");
                let mut joined = vec![(u32::MAX, u32::MAX)];
                pool.install(|| grid.par_self_join(|s, t| Some((s, t)), &mut joined));
                assert_eq!(joined[0], (u32::MAX, u32::MAX), "appended, not replaced");
                assert_eq!(joined[1..], serial[..], "size {size}, {threads} threads");
            }
        }
    }

    /// Boxes further apart than the scalar type can measure are not
    /// gridded (the caller falls back to one query per box) rather than
    /// looping or indexing out of range.
    #[test]
    fn the_sweep_grid_refuses_boxes_it_cannot_measure() {
        let far = Real::MAX * 0.75;
        let boxes = [
            Aabb::new(Vector::splat(-far), Vector::splat(-far + 1.0)),
            Aabb::new(Vector::splat(far - 1.0), Vector::splat(far)),
        ];
        let mut grid = SweepGrid::default();
        assert!(!grid.build(boxes.iter().copied()));
        let near = [Aabb::new(Vector::ZERO, Vector::splat(1.0)); 2];
        assert!(grid.build(near.iter().copied()));
    }
}
