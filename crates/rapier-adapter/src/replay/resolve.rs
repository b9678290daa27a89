//! A replay run: the candidates and the sweeps bring pairs in, the impacts
//! are taken from the queue in time order, each bending its two bodies'
//! paths and bringing their neighbours in, and the bodies the law bent are
//! written back.

use std::cmp::Ordering;

use super::context::{ReplayInput, ReplayOutput, ReplaySets, Run};
use super::impact::{Applied, write_spin};
use super::node::{BallOnPath, Key, NO_PAIR, Pair};
use super::state::Replay;
use crate::cast::Rewind;
use crate::events::AppliedBy;
use crate::math::{Real, from_law};
use crate::rapier::prelude::*;

impl Replay {
    /// After rapier's step: resolve this step's impacts in time order and
    /// write the results back into `sets.bodies`. The pairs are the
    /// candidates the replay resolves and those the sweeps of
    /// `input.flagged` find.
    pub(crate) fn run(
        &mut self,
        input: &ReplayInput,
        sets: ReplaySets<'_>,
        out: &mut ReplayOutput,
    ) {
        self.clear();
        let dt = input.frame.dt;
        if dt.partial_cmp(&0.0) != Some(Ordering::Greater) {
            return; // a step of no time (or NaN) has nothing to replay
        }
        {
            let run = Run::new(input, &sets);
            for c in input.candidates {
                if c.applied_by != AppliedBy::Replay {
                    continue; // bounced by rapier's solver (restitution mode)
                }
                if let Some(i) = self.add_pair(&run, c.collider1, c.collider2) {
                    self.predict(&run, i, 0.0, Rewind::Allowed);
                }
            }
            self.sweep_fast_bodies(&run);
            self.resolve(&run, out);
        }
        self.write_back(sets.bodies, dt, out.woken);
    }

    /// Write back the bodies whose path the law bent, in node order: where
    /// they are at the step's end, their velocities, their rotation; each
    /// listed in `woken`.
    fn write_back(
        &mut self,
        bodies: &mut RigidBodySet,
        dt: Real,
        woken: &mut Vec<RigidBodyHandle>,
    ) {
        self.hit.sort_unstable();
        for &n in &self.hit {
            let node = &self.nodes[n];
            let Key::Body(h) = node.key else { continue };
            let Some(rb) = bodies.get_mut(h) else {
                continue;
            };
            let x = node.at(dt);
            let v = node.body.linvel;
            if x.is_finite() && v.is_finite() {
                rb.set_translation(x, true);
                rb.set_linvel(v, true);
                write_spin(node, rb);
                woken.push(h);
            }
        }
    }

    /// The impacts on the queue, in time order, each bending the paths of
    /// its two bodies and bringing their neighbours in.
    fn resolve(&mut self, run: &Run, out: &mut ReplayOutput) {
        let max_events = run.input.config.max_events_per_step;
        let mut events = 0usize;
        // The instant of the impacts whose bodies are in `bent`.
        let mut instant = Real::NEG_INFINITY;
        loop {
            // A pile resolves most of its impacts at one instant, pair by
            // pair through the overlapping cluster, each body hit several
            // times: its path is swept only once the instant is over, along
            // the last velocity it got then (the paths of the impacts in
            // between last no time), and its pairs with balls apart at
            // that instant are predicted then (`defer_if_apart`). The
            // sweep and those predictions may bring in pairs meeting at
            // that instant still: the loop takes them before any later.
            if !(self.bent.is_empty() && self.apart.is_empty())
                && self.queue.peek().is_none_or(|t| t.max(0.0) > instant)
            {
                self.finish_instant(run, instant);
                continue;
            }
            let Some((t, i)) = self.queue.pop() else {
                break;
            };
            let pair = self.pairs[i];
            if pair.apart_at == t {
                // Queued before an impact at this instant bent either body:
                // predicted again once the instant is over.
                continue;
            }
            if events >= max_events {
                out.log.cap_hit();
                log::warn!(
                    "kimpact: more than {max_events} impacts in one step; the rest is left to rapier"
                );
                break;
            }
            // A pair struck already in this step and closing slower than
            // the rebound cut-off waits for the next step.
            let floor = if pair.struck { run.rebound_cutoff } else { 0.0 };
            let Some(applied) = self.impact(run, &pair, floor, out.log) else {
                continue;
            };
            self.pairs[i].struck = true;
            events += 1;
            self.bend(&pair, t, &applied);
            let at = pair.hit;
            out.log.push(
                pair.colliders(),
                t,
                at.point,
                applied.outcome,
                AppliedBy::Replay,
            );
            let from = t.max(0.0);
            instant = from;
            self.chain(run, &pair, from);
            self.predict_after(run, (i, &pair), t, from);
        }
    }

    /// The instant `instant` is over: the pairs of balls apart then are
    /// predicted, and the colliders whose paths its impacts bent swept.
    fn finish_instant(&mut self, run: &Run, instant: Real) {
        let apart = std::mem::take(&mut self.apart);
        for &j in &apart {
            self.pairs[j as usize].apart_at = Real::NEG_INFINITY;
            self.predict(run, j as usize, instant, Rewind::Never);
        }
        self.apart = apart;
        self.apart.clear();
        let bent = std::mem::take(&mut self.bent);
        for &(n, collider, ball) in &bent {
            self.nodes[n].sweep_due = None;
            self.sweep(run, (n, collider, ball), instant);
        }
        self.bent = bent;
        self.bent.clear();
    }

    /// The paths of `pair`'s bodies bend at `t` as `applied` says (a
    /// dominant or immovable body's path stays as it is).
    fn bend(&mut self, pair: &Pair, t: Real, applied: &Applied) {
        for (side, n) in [pair.a, pair.b].into_iter().enumerate() {
            let node = &mut self.nodes[n];
            if !node.dynamic() || applied.masses[side].is_infinite() {
                continue;
            }
            node.bend(t, from_law(&applied.delta_v[side]));
            if !node.hit {
                node.hit = true;
                self.hit.push(n);
            }
        }
    }

    /// Chains: after an impact of `pair` at `from`, each of its dynamic
    /// bodies that chains on brings its touching neighbours in and is swept
    /// along its new path once the instant is over.
    fn chain(&mut self, run: &Run, pair: &Pair, from: Real) {
        for n in [pair.a, pair.b] {
            if !self.nodes[n].dynamic() {
                continue;
            }
            let side = pair.side(n);
            let collider = pair.colliders()[side];
            let ball = pair.balls.map(|b| b[side]);
            if !self.chains(run, (n, collider, ball), from) {
                // Its touching neighbours are rapier's solver's next
                // step; its pairs with the sweepers are the replay's.
                self.bring_deferred(run, n, from);
                continue;
            }
            self.expand(run, n, from);
            self.bring_deferred(run, n, from);
            // The new path may reach what neither the narrow phase
            // nor the sweep along the old one saw: swept once this
            // instant is over.
            if self.nodes[n].sweep_due != Some(collider) {
                self.nodes[n].sweep_due = Some(collider);
                self.bent.push((n, collider, ball));
            }
        }
    }

    /// Fresh predictions, from `from`, for every pair of the two bodies of
    /// pair `i` (`pair`), whose impact at `t` bent them. The pairs listed
    /// now (a prediction adds none, but the list is walked up to its
    /// present end regardless); the impact's own pair once, in `a`'s list.
    /// A pair of balls apart at the instant waits for its end.
    fn predict_after(&mut self, run: &Run, (i, pair): (usize, &Pair), t: Real, from: Real) {
        let defer = t == from;
        for n in [pair.a, pair.b] {
            let [mut j, last] = self.ends[n];
            while j != NO_PAIR {
                let next = self.next_pair(j as usize, n);
                if (n == pair.a || j as usize != i)
                    && !(defer && self.defer_if_apart(j as usize, from))
                {
                    self.predict(run, j as usize, from, Rewind::Never);
                }
                if j == last {
                    break;
                }
                j = next;
            }
        }
    }

    /// Bring the governed contacts of node `n`'s marked colliders into the
    /// replay (once), and predict them from time `t`.
    fn expand(&mut self, run: &Run, n: usize, t: Real) {
        if self.nodes[n].expanded {
            return;
        }
        self.nodes[n].expanded = true;
        let Key::Body(handle) = self.nodes[n].key else {
            return;
        };
        let Some(rb) = run.bodies.get(handle) else {
            return;
        };
        for &ch in rb.colliders() {
            for cp in run.narrow_phase.contact_pairs_with(ch) {
                // Only the contacts rapier saw (touching neighbours).
                if !cp.has_any_active_contact()
                    || self.has_pair(cp.collider1, cp.collider2)
                    || !run.governs(cp.collider1, cp.collider2)
                {
                    continue;
                }
                if let Some(i) = self.add_pair(run, cp.collider1, cp.collider2) {
                    self.predict(run, i, t, Rewind::Never);
                }
            }
        }
    }

    /// Whether node `n`, whose path an impact on its collider `collider`
    /// (a ball of radius and offset `ball`, if it is one) bent at `from`,
    /// chains on: brings its touching neighbours into the replay and is
    /// swept along its new path. Always, but in restitution mode, where it
    /// does only while it moves more than a quarter of its size over the
    /// rest of the step (as `Prepare::is_swept` hands a body to the replay):
    /// slower, it cannot tunnel before rapier's contacts see it, and its
    /// pairs outside the replay are rapier's solver's next step, bounced
    /// with the law's restitution. (A row of touching balls struck hard
    /// chains on while the struck balls move that fast; a pile a falling
    /// ball lands on is not replayed through.)
    fn chains(
        &self,
        run: &Run,
        (n, collider, ball): (usize, ColliderHandle, Option<BallOnPath>),
        from: Real,
    ) -> bool {
        let share = run.reach.chain_share;
        if share == 0.0 {
            return true;
        }
        let half = match ball {
            Some((radius, _)) => radius,
            None => run
                .colliders
                .get(collider)
                .map_or(0.0, crate::body_view::half_size),
        };
        let v = run.input.frame.relative(self.nodes[n].v);
        (v * (run.dt - from)).length() > share * half
    }
}
