//! rapier's broad-phase tree leaves: a walk over them, and a grid of
//! their boxes for runs that look many of them up.

use crate::math::Real;
use crate::rapier::parry::partitioning::{Bvh, BvhNode, TraversalAction};
use crate::rapier::prelude::*;
use crate::sweep_grid::SweepGrid;

/// The boxes of rapier's broad phase (its tree's leaves) in a [`SweepGrid`],
/// for the single sweeps of a run that makes many: the re-sweeps after
/// impacts in a settling pile (one per impact that sets a ball moving
/// further than rapier's contacts reach; a tree descent from the root for
/// each adds up over a pile's many impacts) and the
/// sweepers of a run too few for the bulk sweep. Built once a run has made
/// [`LeafGrid::QUERY_SHARE`]-th as many tree queries as the tree has
/// leaves (a build costs a pass over the leaves, about as much as that many
/// queries). It finds every leaf box a query meets, as the bulk sweep's
/// grid does, including those a tree descent misses under an inner node
/// not yet refitted. Boxes much larger than the typical one (walls, a
/// floor) stay out of the grid, whose cells would grow to their size, and
/// are tested one by one.
#[derive(Default)]
pub(crate) struct LeafGrid {
    /// Tree queries made this run.
    queries: usize,
    /// Built this run (`Some(false)`: tried and not possible).
    built: Option<bool>,
    grid: SweepGrid,
    /// The boxes in `grid`, with their collider index (a box's number in
    /// the grid is its place here).
    small: Vec<(u32, Aabb)>,
    /// The boxes left out of the grid, with their collider index.
    big: Vec<(u32, Aabb)>,
}

impl LeafGrid {
    /// A run builds the grid after `leaves / QUERY_SHARE` tree queries.
    const QUERY_SHARE: usize = 16;
    /// and never before this many.
    const MIN_QUERIES: usize = 64;
    /// A box is left out of the grid when its largest side exceeds this
    /// many times the mean of the leaves' largest sides.
    const BIG: Real = 4.0;
    /// The grid is not built when more boxes than this would be left out
    /// (each query would test them all).
    const MAX_BIG: usize = 64;

    /// Forget the last run.
    pub(crate) fn clear(&mut self) {
        self.queries = 0;
        self.built = None;
    }

    /// Count one tree query of this run; whether the grid is now to be
    /// used (built at this call if need be) for a tree of `tree` leaves.
    pub(crate) fn wanted(&mut self, tree: &Bvh) -> bool {
        match self.built {
            Some(built) => built,
            None => {
                self.queries += 1;
                let leaves = tree.leaf_count() as usize;
                if self.queries < Self::MIN_QUERIES.max(leaves / Self::QUERY_SHARE) {
                    return false;
                }
                let built = self.build(tree);
                self.built = Some(built);
                built
            }
        }
    }

    /// Grid the leaves of `tree`; `false` if they cannot be gridded.
    pub(crate) fn build(&mut self, tree: &Bvh) -> bool {
        let mut small = std::mem::take(&mut self.small);
        small.clear();
        self.big.clear();
        let mut sum: f64 = 0.0;
        for_each_leaf(tree, |key, node| {
            let b = node.aabb();
            sum += f64::from((b.maxs - b.mins).max_element());
            small.push((key, b));
        });
        let mean = sum / small.len().max(1) as f64;
        let cut = Self::BIG * mean as Real;
        // A box with a NaN side stays in, and the grid's build refuses it.
        if !cut.is_finite() {
            self.small = small;
            return false;
        }
        let mut i = 0;
        while i < small.len() {
            if (small[i].1.maxs - small[i].1.mins).max_element() > cut {
                self.big.push(small.swap_remove(i));
            } else {
                i += 1;
            }
        }
        let ok = self.big.len() <= Self::MAX_BIG && self.grid.build(small.iter().map(|&(_, b)| b));
        self.small = small;
        ok
    }

    /// Push the collider index of every box that meets `aabb` onto `met`,
    /// in no particular order.
    pub(crate) fn overlaps(&self, aabb: &Aabb, met: &mut Vec<u32>) {
        self.grid
            .overlaps(aabb, |i| met.push(self.small[i as usize].0));
        met.extend(
            self.big
                .iter()
                .filter(|(_, b)| aabb.intersects(b))
                .map(|&(key, _)| key),
        );
    }
}

/// Call `f` with the key (rapier: the collider's index) and the box of every
/// leaf of `tree`, once each, in no particular order. The keys are looked up
/// one by one from 0 (rapier's collider indices are dense: no tree descent,
/// and nothing read for a leaf `f` skips but its index) until every leaf
/// is seen; keys beyond twice the leaf count (a set that had many colliders
/// removed) are found by a walk down the tree.
pub(crate) fn for_each_leaf(tree: &Bvh, mut f: impl FnMut(u32, &BvhNode)) {
    let leaves = tree.leaf_count();
    let limit = leaves.saturating_mul(2).saturating_add(64);
    let mut seen = 0;
    let mut key = 0;
    while seen < leaves && key < limit {
        if let Some(node) = tree.leaf_node(key) {
            seen += 1;
            f(key, node);
        }
        key += 1;
    }
    if seen < leaves {
        tree.traverse(|node| {
            if !node.is_leaf() {
                return TraversalAction::Continue;
            }
            if let Some(key) = node.leaf_data()
                && key >= limit
            {
                f(key, node);
            }
            TraversalAction::Prune
        });
    }
}

#[cfg(test)]
#[allow(clippy::unnecessary_cast)]
mod tests {
    use super::*;
    use crate::math::{DIM, Vector};
    use crate::test_rng::TestRng;

    /// The leaf grid is built once a run has made its share of tree
    /// queries, and then finds for every query exactly the leaves whose box
    /// in the tree meets it (brute force over the tree's leaves), among
    /// them every leaf a descent of the tree finds; four walls far larger
    /// than the balls' boxes stay out of the grid and are still found.
    #[test]
    fn the_leaf_grid_finds_every_leaf_box_a_query_meets() {
        let mut rng = TestRng::new(5);
        // As dense in 3D as in 2D.
        let spread = if DIM == 2 { 40.0 } else { 12.0 };
        let mut tree = Bvh::new();
        let mut key = 0;
        for _ in 0..2000 {
            tree.insert(rng.aabb(spread, 0.6), key);
            key += 1;
        }
        for axis in 0..2 {
            for side in [-1.0, spread] {
                let (mut lo, mut hi) = (Vector::splat(-1.0), Vector::splat(spread + 1.0));
                lo[axis] = side;
                hi[axis] = side + 1.0;
                tree.insert(Aabb::new(lo, hi), key);
                key += 1;
            }
        }
        let mut leaves = LeafGrid::default();
        let needed = LeafGrid::MIN_QUERIES.max(key as usize / LeafGrid::QUERY_SHARE);
        for _ in 1..needed {
            assert!(!leaves.wanted(&tree));
        }
        assert!(leaves.wanted(&tree));
        assert_eq!(leaves.big.len(), 4, "the walls");
        let mut boxes = Vec::new();
        for_each_leaf(&tree, |key, node| boxes.push((key, node.aabb())));
        let mut found = 0;
        for q in 0..400 {
            // Some queries reach past the walls, one covers everything.
            let query = if q == 0 {
                Aabb::new(Vector::splat(-50.0), Vector::splat(90.0))
            } else {
                let b = rng.aabb(spread + 6.0, 2.5);
                Aabb::new(b.mins - Vector::splat(3.0), b.maxs - Vector::splat(3.0))
            };
            let mut met = Vec::new();
            leaves.overlaps(&query, &mut met);
            met.sort_unstable();
            let mut brute: Vec<u32> = boxes
                .iter()
                .filter(|(_, b)| query.intersects(b))
                .map(|&(key, _)| key)
                .collect();
            brute.sort_unstable();
            assert_eq!(met, brute, "query {q}");
            for key in tree.leaves(|node: &BvhNode| node.aabb().intersects(&query)) {
                assert!(brute.binary_search(&key).is_ok(), "query {q}: leaf {key}");
            }
            found += brute.len();
        }
        assert!(found > 2000 + 400, "{found} leaves found");
        // The next run counts its own queries.
        leaves.clear();
        assert!(!leaves.wanted(&tree));
    }

    /// Every leaf of a tree is visited once with its own box, whether its
    /// key is found by the look-up from 0 or, beyond twice the leaf count,
    /// by the walk down the tree: against the keys inserted, for a tree
    /// with removed leaves (holes), sparse keys far beyond the leaf count,
    /// and an empty tree.
    #[test]
    fn every_leaf_is_visited_once() {
        let mut rng = TestRng::new(3);
        let mut tree = Bvh::new();
        let mut visited = Vec::new();
        for_each_leaf(&tree, |key, _| visited.push(key));
        assert!(visited.is_empty());
        let mut keys: Vec<u32> = (0..200).collect();
        keys.extend([500, 1_000, 77_777]);
        let boxes: Vec<Aabb> = keys.iter().map(|_| rng.aabb(10.0, 1.0)).collect();
        for (&key, aabb) in keys.iter().zip(&boxes) {
            tree.insert(*aabb, key);
        }
        for key in (0..200).step_by(3) {
            tree.remove(key);
        }
        let expected: Vec<(u32, Aabb)> = keys
            .iter()
            .zip(&boxes)
            .filter(|(k, _)| **k >= 200 || **k % 3 != 0)
            .map(|(k, b)| (*k, *b))
            .collect();
        let mut visited = Vec::new();
        for_each_leaf(&tree, |key, node| visited.push((key, node.aabb())));
        visited.sort_unstable_by_key(|v| v.0);
        assert_eq!(visited.len(), expected.len());
        for (v, e) in visited.iter().zip(&expected) {
            assert_eq!(v.0, e.0);
            assert!(v.1.contains(&e.1), "leaf {}: its box", e.0);
        }
    }
}
