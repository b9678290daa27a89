//! Sweeps: the governed colliders a moving body could reach this step,
//! found along its path through rapier's broad phase (one query at a time,
//! or in bulk through a grid of the swept boxes).

use super::context::Run;
use super::node::{BallOnPath, Sweeper};
use super::nodes::rest_pose;
use super::predict::cast_balls;
use super::state::Replay;
use crate::cast::Rewind;
use crate::handle_map::HandleMap;
use crate::leaves::for_each_leaf;
use crate::math::Real;
use crate::rapier::parry::partitioning::Bvh;
use crate::rapier::parry::query::DefaultQueryDispatcher;
use crate::rapier::prelude::*;
use crate::sweep_grid::SweepGrid;

/// The bulk sweep replaces one broad-phase query per swept collider when at
/// least this many colliders sweep, and at least one in `BULK_SHARE` of all
/// colliders does (a gas: every ball moves more than rapier's prediction
/// distance per step).
const BULK_MIN: usize = 64;
const BULK_SHARE: usize = 8;

impl Replay {
    /// Bodies that move more than their own half-size this step can cross a
    /// partner without a contact ever being seen (rapier's CCD does not
    /// sweep dynamic against dynamic): query the broad phase along their
    /// path over the step and bring every governed collider it meets into
    /// the replay.
    pub(super) fn sweep_fast_bodies(&mut self, run: &Run) {
        let input = run.input;
        let mut sweepers = std::mem::take(&mut self.sweepers);
        sweepers.clear();
        for j in 0..input.flagged.len() {
            let ch = input.flagged[j];
            let Some(handle) = run.colliders.get(ch).and_then(|co| co.parent()) else {
                continue;
            };
            if input.starts.of(handle).is_none() {
                continue;
            }
            let n = self.node(run, ch, Some(handle));
            if let Some((aabb, ball)) = self.swept_aabb(run, ch, n, 0.0, None) {
                sweepers.push(Sweeper {
                    collider: ch,
                    node: n,
                    aabb,
                    ball,
                });
                self.nodes[n].swept = Some((ch, aabb));
            }
        }
        let bulk = !self.per_body_sweep
            && sweepers.len() >= BULK_MIN
            && sweepers.len() * BULK_SHARE >= run.colliders.len();
        let in_bulk = bulk && self.sweep_in_bulk(run, &sweepers);
        #[cfg(test)]
        {
            self.bulk_sweeps += u64::from(in_bulk);
        }
        if !in_bulk {
            for &Sweeper {
                collider: ch, aabb, ..
            } in &sweepers
            {
                self.sweep_query(run, ch, aabb, 0.0);
            }
        }
        self.sweepers = sweepers;
    }

    /// The box collider `ch` of node `n` sweeps from `from` to the end of the
    /// step (in the frame the world shares, if it does, where the frame is
    /// at the step's end: [`StepFrame::lag`](crate::frame::StepFrame::lag)),
    /// if it moves far enough over that time to be swept (more than
    /// half its size, or more than `sweep_reach`, `fall_reach` if it moves
    /// along gravity); with it, the collider's
    /// radius and centre offset if it is a ball (as [`Replay::ball`]).
    /// `known` is that radius and offset when the caller has them (a pair
    /// of balls keeps them): then neither the collider nor its body is read.
    pub(super) fn swept_aabb(
        &self,
        run: &Run,
        ch: ColliderHandle,
        n: usize,
        from: Real,
        known: Option<BallOnPath>,
    ) -> Option<(Aabb, Option<BallOnPath>)> {
        let dt = run.dt;
        let node = &self.nodes[n];
        // Against the frame a world falling as a whole shares, where gravity
        // is every body's alike: nothing falls onto a partner at rest.
        let frame = &run.input.frame;
        let moved = frame.relative(node.v) * (dt - from);
        let reach = if frame.shared.is_none() && node.v.dot(run.gravity_dt) > 0.0 {
            run.reach.fall
        } else {
            run.reach.sweep
        };
        let far_enough = |half: Real| moved.length() > half.min(reach);
        // The box in the frame where it is at the step's end (`lag`).
        let lag = frame.lag(dt - from);
        let (swept, ball) = match known {
            Some(ball) => {
                if !far_enough(ball.0) {
                    return None;
                }
                (node.swept_ball(ball, (from, dt), lag), known)
            }
            None => {
                let co = run.colliders.get(ch)?;
                let shape = co.shape();
                let ball = shape.as_ball();
                let half = crate::body_view::half_size(co);
                if !far_enough(half) {
                    return None;
                }
                let rest = rest_pose(run.bodies, co);
                match ball {
                    Some(ball) => {
                        let ball = (ball.radius, rest.translation - node.x1);
                        (node.swept_ball(ball, (from, dt), lag), Some(ball))
                    }
                    None => {
                        let mut start = node.moved(rest, from);
                        start.translation += lag;
                        let end = node.moved(rest, dt);
                        let swept = shape.compute_aabb(&start).merged(&shape.compute_aabb(&end));
                        (swept, None)
                    }
                }
            }
        };
        // A box that is not finite (a body the runtime guard cuts off)
        // meets nothing.
        (swept.mins.is_finite() && swept.maxs.is_finite()).then_some((swept, ball))
    }

    /// Sweep collider `ch` of node `n` along the node's path from `from` to
    /// the end of the step, if it moves far enough over that time (more
    /// than half its size, or more than `sweep_reach`), and bring every
    /// governed collider the sweep meets into the replay, predicted from
    /// `from`.
    pub(super) fn sweep(
        &mut self,
        run: &Run,
        (n, ch, ball): (usize, ColliderHandle, Option<BallOnPath>),
        from: Real,
    ) {
        let Some((aabb, _)) = self.swept_aabb(run, ch, n, from, ball) else {
            return;
        };
        if let Some((c, covered)) = self.nodes[n].swept
            && c == ch
            && covered.mins.cmple(aabb.mins).all()
            && aabb.maxs.cmple(covered.maxs).all()
        {
            // Every collider this box meets was met by the earlier sweep and
            // is in the replay already, predicted again after each impact.
            return;
        }
        self.nodes[n].swept = Some((ch, aabb));
        self.sweep_query(run, ch, aabb, from);
    }

    /// The colliders of rapier's broad phase whose box meets `swept`, as
    /// rapier's tree query finds them (it can miss one under an inner node
    /// not yet refitted: see [`Replay::sweep_in_bulk`]), met by collider
    /// `ch` from time `from`.
    fn sweep_query(&mut self, run: &Run, ch: ColliderHandle, swept: Aabb, from: Real) {
        let query = run.broad_phase.as_query_pipeline(
            &DefaultQueryDispatcher,
            run.bodies,
            run.colliders,
            QueryFilter::default(),
        );
        // In collider order (as the bulk sweep takes them), not the tree's.
        let mut met = std::mem::take(&mut self.met);
        met.clear();
        // Room for every collider once, so that a sweep meeting more than
        // any before does not allocate in a steady state.
        met.reserve(run.colliders.len());
        if !self.per_body_sweep && self.leaves.wanted(query.bvh) {
            self.leaves.overlaps(&swept, &mut met);
        } else {
            met.extend(
                query
                    .intersect_aabb_conservative(swept)
                    .map(|(other, _)| other.into_raw_parts().0),
            );
        }
        met.sort_unstable();
        for &index in &met {
            if let Some((_, other)) = run.colliders.get_unknown_gen(index) {
                self.meet(run, ch, other, from);
            }
        }
        self.met = met;
    }

    /// The sweep of many colliders at once: the swept boxes go in a uniform
    /// grid, every box of rapier's broad phase (the leaves its queries test)
    /// looks up the cells whose boxes may meet it, and every overlap of a
    /// swept box with a broad-phase box is taken, sweeper by sweeper, each
    /// in collider order (the order of [`Replay::sweep_query`] too). It finds every pair one
    /// [`Replay::sweep_query`] each would, and the few such a query misses.
    /// `false`, having done nothing, if the boxes cannot be gridded (the
    /// caller then sweeps them one query each). One pass over the
    /// colliders replaces a tree descent per swept collider (in a gas every
    /// ball is swept, and a descent each costs more than the grid).
    fn sweep_in_bulk(&mut self, run: &Run, sweepers: &[Sweeper]) -> bool {
        let tree = run
            .broad_phase
            .as_query_pipeline(
                &DefaultQueryDispatcher,
                run.bodies,
                run.colliders,
                QueryFilter::default(),
            )
            .bvh;
        let mut grid = std::mem::take(&mut self.grid);
        if !grid.build(sweepers.iter().map(|x| x.aabb)) {
            self.grid = grid;
            return false;
        }
        let mut found = std::mem::take(&mut self.found);
        found.clear();
        // Two sweepers can meet only where their swept boxes do: each such
        // pair is taken once, from the grid alone, by the sweeper numbered
        // first (the one that would reach it first in the order below).
        let mut sweeping = std::mem::take(&mut self.sweeping);
        for sweeper in sweepers {
            sweeping.insert(sweeper.collider, self.stamp);
        }
        let mut deferred = std::mem::take(&mut self.deferred);
        deferred.clear();
        self.join_sweepers(run, &grid, sweepers, &mut found, &mut deferred);
        if !deferred.is_empty() {
            self.group_deferred(&deferred, sweepers);
        }
        self.deferred = deferred;
        self.join_leaves(tree, &grid, &sweeping, &mut found);
        #[cfg(test)]
        {
            self.swept_overlaps += (found.len() + self.deferred.len()) as u64;
        }
        self.grid = grid;
        self.sweeping = sweeping;
        // Sweeper by sweeper, each in collider order, as one query each
        // would take them.
        found.sort_unstable();
        for &(s, index) in &found {
            let Some((_, other)) = run.colliders.get_unknown_gen(index) else {
                continue;
            };
            let ch = sweepers[s as usize].collider;
            self.meet(run, ch, other, 0.0);
        }
        self.found = found;
        true
    }

    /// The pairs of sweepers whose boxes meet in `grid`: into `found` as
    /// (sweeper, collider index) when they may meet on their present paths,
    /// into `deferred` otherwise. A pair of balls that does not meet on the
    /// paths the bodies have now is deferred: its prediction would be
    /// "never", and it matters only once an impact bends either path (most
    /// pairs of a gas: their boxes meet, their balls do not).
    fn join_sweepers(
        &mut self,
        run: &Run,
        grid: &SweepGrid,
        sweepers: &[Sweeper],
        found: &mut Vec<(u32, u32)>,
        deferred: &mut Vec<(u32, u32)>,
    ) {
        let nodes = &self.nodes;
        let dt = run.dt;
        // Whether sweepers `s` and `t` may meet on their present paths.
        let may_meet = |s: u32, t: u32| {
            let (a, b) = (&sweepers[s as usize], &sweepers[t as usize]);
            match (a.ball, b.ball) {
                // The first cast `Replay::predict` would make of the pair.
                (Some(b1), Some(b2)) => {
                    cast_balls([(&nodes[a.node], b1), (&nodes[b.node], b2)], 0.0, dt).is_some()
                }
                _ => true,
            }
        };
        let mut take = |s: u32, t: u32, meets: bool| {
            if meets {
                found.push((s, sweepers[t as usize].collider.into_raw_parts().0));
            } else {
                deferred.push((s, t));
            }
        };
        #[cfg(not(feature = "parallel"))]
        grid.self_join(|s, t| take(s, t, may_meet(s, t)));
        #[cfg(feature = "parallel")]
        {
            // The casts on rayon's pool, taken here in the serial order.
            let mut joined = std::mem::take(&mut self.par.joined);
            joined.clear();
            grid.par_self_join(|s, t| Some((s, t, may_meet(s, t))), &mut joined);
            for &(s, t, meets) in &joined {
                take(s, t, meets);
            }
            self.par.joined = joined;
        }
    }

    /// Every other leaf of rapier's tree (walls, slow bodies; not the
    /// colliders `sweeping` stamps this run) whose box meets a cell of
    /// `grid`: into `found` as (sweeper, collider index). A leaf's box
    /// looks up the cells whose boxes may meet it. Every leaf, not only
    /// those under inner nodes that meet a swept box: between steps some
    /// inner boxes do not enclose the leaves below them (rapier refits the
    /// ancestors of moved leaves lazily), so a query descending from the
    /// root can miss a collider whose own box meets the query's (it
    /// happens in a falling pile).
    fn join_leaves(
        &mut self,
        tree: &Bvh,
        grid: &SweepGrid,
        sweeping: &HandleMap<ColliderHandle, u32>,
        found: &mut Vec<(u32, u32)>,
    ) {
        let stamp = self.stamp;
        #[cfg(not(feature = "parallel"))]
        for_each_leaf(tree, |index, node| {
            if sweeping.get_by_index(index) != Some(&stamp) {
                grid.overlaps(&node.aabb(), |s| found.push((s, index)));
            }
        });
        #[cfg(feature = "parallel")]
        {
            // The leaves listed, then looked up on rayon's pool (`found`
            // is sorted by the caller: the order it is filled in does not
            // matter).
            use rayon::prelude::*;
            let mut leaves = std::mem::take(&mut self.par.leaves);
            leaves.clear();
            for_each_leaf(tree, |index, node| {
                if sweeping.get_by_index(index) != Some(&stamp) {
                    leaves.push((index, node.aabb()));
                }
            });
            let run = leaves
                .len()
                .div_ceil(8 * rayon::current_num_threads())
                .max(1);
            let parts: Vec<Vec<(u32, u32)>> = leaves
                .par_chunks(run)
                .map(|chunk| {
                    let mut part = Vec::new();
                    for (index, aabb) in chunk {
                        grid.overlaps(aabb, |s| part.push((s, *index)));
                    }
                    part
                })
                .collect();
            for part in parts {
                found.extend(part);
            }
            self.par.leaves = leaves;
        }
    }

    /// Group the deferred pairs by node (`deferred_range`, `deferred_by`).
    pub(super) fn group_deferred(&mut self, deferred: &[(u32, u32)], sweepers: &[Sweeper]) {
        let n = self.nodes.len();
        self.deferred_range.clear();
        self.deferred_range.resize(n, (0, 0));
        let ends = |&(s, t): &(u32, u32)| [sweepers[s as usize].node, sweepers[t as usize].node];
        for pair in deferred {
            for node in ends(pair) {
                self.deferred_range[node].1 += 1;
            }
        }
        let mut sum = 0;
        for range in &mut self.deferred_range {
            let count = range.1;
            *range = (sum, sum);
            sum += count;
        }
        self.deferred_by.clear();
        self.deferred_by.resize(sum as usize, 0);
        for (i, pair) in deferred.iter().enumerate() {
            for node in ends(pair) {
                let range = &mut self.deferred_range[node];
                self.deferred_by[range.1 as usize] = i as u32;
                range.1 += 1;
            }
        }
    }

    /// Node `n`'s path is about to bend: bring its deferred pairs into the
    /// replay (once), to be predicted with the rest of its pairs.
    pub(super) fn bring_deferred(&mut self, run: &Run, n: usize, from: Real) {
        let Some(&(start, end)) = self.deferred_range.get(n) else {
            return;
        };
        self.deferred_range[n] = (start, start);
        for j in start..end {
            let (s, t) = self.deferred[self.deferred_by[j as usize] as usize];
            let (c1, c2) = (
                self.sweepers[s as usize].collider,
                self.sweepers[t as usize].collider,
            );
            self.meet(run, c1, c2, from);
        }
    }

    /// Collider `ch`'s sweep reached collider `other`: if the law governs the
    /// pair, bring it into the replay and predict it from `from`.
    fn meet(&mut self, run: &Run, ch: ColliderHandle, other: ColliderHandle, from: Real) {
        if other == ch || self.has_pair(ch, other) || !run.governs(ch, other) {
            return;
        }
        if let Some(i) = self.add_pair(run, ch, other) {
            self.predict(run, i, from, Rewind::at(from));
        }
    }
}
