//! The law's modes' replay: the impacts of one step, resolved in time
//! order at their analytic times of impact, after rapier's step (impulse
//! and exact mode: every governed impact; restitution mode: those of the
//! bodies fast enough to tunnel).
//!
//! rapier integrates positions with the velocity it solved, so within a step
//! every body moves on a straight line from its start `x₀` to its end `x₁`,
//! at `v̄ = (x₁ − x₀)/dt` (which includes gravity and the contacts rapier kept,
//! such as the table under a billiard ball). The replay takes those lines as
//! the motion, finds when the pairs the hook handed over meet (a linear
//! cast: closed form for two balls and for a ball and a cuboid, parry's
//! shape cast otherwise), applies the law there,
//! bends the two lines, and repeats, in time order. A body whose velocity
//! changes brings its touching neighbours into the replay (chains: a row of
//! touching balls is a chain of impacts within one step). Pairs first seen
//! overlapping are rewound into the previous step, along the same lines.
//! The law itself acts on the velocities the bodies really have (rapier's
//! end-of-step velocity plus the changes so far), which differ from the path
//! velocity when rapier's solver pushed a body apart from an overlap.
//! At the end each body that took part gets `x = x(dt)` and
//! `v = v_rapier + Σ Δv`.
//!
//! The pairs are those rapier's contacts hold (the hook's candidates) and
//! those of bodies that move more than half their size per step (swept, as
//! they can cross a partner unseen). Exact mode also sweeps every body that
//! moves more than half rapier's prediction distance, which can meet a
//! partner rapier's contacts did not reach yet; impulse mode does so only
//! for a body that falls (moves along gravity: a landing on a pile at
//! rest), and leaves any other such pair to the next step, where rapier
//! first sees it overlapping and the replay rewinds it (a graze that
//! begins and ends within the step is missed).
//!
//! Restitution mode hands the replay only the bodies that move more than
//! a quarter of their size per step (and their pairs, which rapier's solver then
//! leaves alone): rapier's solver bounces every other pair with the law's
//! restitution. A body an impact bends chains on (brings its touching
//! neighbours in, and is swept again) only while it still moves that
//! fast. A line that crosses its box several times per step is bent at
//! every wall, and the body is written back inside.

//!
//! The run's modules, each with one job: `context` (what a run takes and
//! gives back, and what every call of it shares), `node` (nodes, pairs,
//! hits), `state` (the scratch kept between steps), `nodes` (making nodes
//! and pairs), `predict` (when a pair meets), `queue` (the meetings in
//! time order), `sweep` (the partners a moving body can reach), `impact`
//! (one impact under the law) and `resolve` (the run itself).

mod context;
mod impact;
mod node;
mod nodes;
mod predict;
mod queue;
mod resolve;
mod state;
mod sweep;

pub(crate) use context::{ReplayInput, ReplayOutput, ReplaySets};
pub(crate) use state::Replay;
