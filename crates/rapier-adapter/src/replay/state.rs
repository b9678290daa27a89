//! The replay's scratch, kept between steps so that a steady state
//! allocates nothing.

use super::node::{BallOnPath, Node, Pair, Slot, Sweeper};
use super::queue::PairQueue;
use crate::handle_map::HandleMap;
use crate::leaves::LeafGrid;
use crate::rapier::prelude::*;
use crate::sweep_grid::SweepGrid;

/// Scratch space of the replay, kept between steps so that a steady state
/// allocates nothing. Its methods live in the modules of their jobs:
/// `nodes` (the nodes and pairs of a run), `predict` (when a pair meets),
/// `sweep` (the partners a moving body can reach), `impact` (one impact:
/// the law, friction included) and `resolve` (the run).
#[derive(Default)]
pub(crate) struct Replay {
    pub(super) nodes: Vec<Node>,
    /// The dynamic nodes whose path the law bent this run, in the order of
    /// their first impact (the write-back walks these, not every node).
    pub(super) hit: Vec<usize>,
    /// Node of a body (valid when stamped this run): dense per-handle
    /// storage rather than hash maps (hashing was a fifth of a step).
    pub(super) body_slots: HandleMap<RigidBodyHandle, Slot>,
    /// Node of a collider (its body's, or its own for a collider without a
    /// body): which pairs are in the replay already is known without
    /// reading the collider (see `Replay::has_pair`).
    pub(super) collider_slots: HandleMap<ColliderHandle, Slot>,
    /// This run's stamp.
    pub(super) stamp: u32,
    pub(super) pairs: Vec<Pair>,
    /// For each node, the first and the last pair it is in (`NO_PAIR`
    /// when none): the node's pairs are a list threaded through the pairs
    /// themselves ([`Pair::next`]), in the order they were added. One list
    /// per node in a vector of its own would reallocate in steady state
    /// (which node a body gets changes from step to step, and a ball's list
    /// could land in a slot too small for it); these need no allocation
    /// beyond `pairs`' and `nodes`' own.
    pub(super) ends: Vec<[u32; 2]>,
    /// For each node, how many pairs it is in.
    pub(super) degrees: Vec<u32>,
    /// The pairs of crowded nodes (see `nodes::CROWD`), by
    /// `nodes::pair_key`: a crowded node's list is too long to walk for
    /// every pair a sweep or its neighbours bring (kept between runs, so a
    /// steady state allocates nothing).
    pub(super) crowd_pairs: std::collections::HashSet<u64>,
    /// Each pair's next meeting.
    pub(super) queue: PairQueue,
    /// Scratch of the bulk sweep: the colliders to sweep.
    pub(super) sweepers: Vec<Sweeper>,
    /// After the step, pairs of sweepers (numbers into `sweepers`, the
    /// lower first) whose boxes meet but whose balls do not, on the paths
    /// they have before any impact: left out of the replay until an impact
    /// changes the path of either (see `Replay::bring_deferred`).
    pub(super) deferred: Vec<(u32, u32)>,
    /// For each node made before the bulk sweep, its range of
    /// `deferred_by` (emptied once brought in).
    pub(super) deferred_range: Vec<(u32, u32)>,
    /// Indices into `deferred`, grouped by node.
    pub(super) deferred_by: Vec<u32>,
    /// Scratch of the bulk sweep: a uniform grid over the swept boxes.
    pub(super) grid: SweepGrid,
    /// Scratch of the bulk sweep: (sweeper, collider index) pairs found.
    pub(super) found: Vec<(u32, u32)>,
    /// Scratch of the bulk sweep, per collider: the stamp of the run in
    /// which the collider is a sweeper (its pairs with other sweepers come
    /// from the grid alone).
    pub(super) sweeping: HandleMap<ColliderHandle, u32>,
    /// The colliders (with their nodes) whose path an impact bent at the
    /// instant being resolved: swept once the instant is over, along their
    /// last path (see `Replay::resolve`).
    /// With each, the collider's radius and centre offset when a pair of
    /// balls gave them (see `Replay::swept_aabb`).
    pub(super) bent: Vec<(usize, ColliderHandle, Option<BallOnPath>)>,
    /// The pairs of balls apart at the instant being resolved whose bodies
    /// an impact there bent: predicted once the instant is over (see
    /// `Replay::defer_if_apart`).
    pub(super) apart: Vec<u32>,
    /// Scratch of a single sweep: the collider indices it met.
    pub(super) met: Vec<u32>,
    /// rapier's broad-phase boxes in a grid, for the single sweeps of a run
    /// that makes many (see [`LeafGrid`]).
    pub(super) leaves: LeafGrid,
    /// Never sweep in bulk, nor through `leaves` (the unit tests compare
    /// both ways).
    pub(crate) per_body_sweep: bool,
    /// Runs that swept in bulk (for the unit tests).
    #[cfg(test)]
    pub(crate) bulk_sweeps: u64,
    /// Overlaps of swept boxes the bulk sweeps found, with each other and
    /// with rapier's leaves (for the unit tests: what the join paid).
    #[cfg(test)]
    pub(crate) swept_overlaps: u64,
    #[cfg(feature = "parallel")]
    pub(super) par: ParScratch,
}

/// Scratch of the bulk sweep's passes on rayon's pool (`parallel`).
#[cfg(feature = "parallel")]
#[derive(Default)]
pub(super) struct ParScratch {
    /// The grid's pairs of sweepers, each with whether it may meet on the
    /// present paths, in the serial join's order.
    pub joined: Vec<(u32, u32, bool)>,
    /// rapier's leaves that are not sweepers: (collider index, box).
    pub leaves: Vec<(u32, Aabb)>,
}
