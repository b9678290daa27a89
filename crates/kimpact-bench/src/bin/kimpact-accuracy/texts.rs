//! The fixed prose of `accuracy.md`: what each comparison does and how.

pub const FINDINGS_BEGIN: &str = "<!-- findings: hand-written, kept by the generator -->";
pub const FINDINGS_END: &str = "<!-- end of findings -->";

pub const INTRO: &str = "\
All scenes use balls of diameter σ = 1 and mass 1 (except where a mass ratio is given), no \
friction, no gravity, rapier's default time step dt = 1/60 s and its default integration \
parameters. Each comparison builds the rapier world from the reference's own balls, so both \
start from the same state. The reference (`kimpact-reference`) is exact: every impact at its \
time of impact, up to rounding. Errors are absolute, with the incoming speed 1 and the radius \
as units. `native` is rapier unchanged with restitution 1 (or, for the cooling gas, the law's \
head-on restitution), the other rows are the adapter's modes.
";

pub const GAS_TEXT: &str = "\
200 balls at packing fraction 0.3 in a closed cubic box (the kind of gas of the CI test; 3D: 200 \
spheres), velocity components drawn uniform in [−3, 3] and scaled to kT = 3, run for \
T = {T} s (6,000 steps). The reference runs the same balls. `reference, other balls` is the \
reference from another draw of the initial balls at the same energy: it shows how far two exact \
runs of the same gas differ (hard-ball dynamics is chaotic, so beyond a few hundred impacts only \
statistics can agree), i.e. the noise floor of every column. Momentum: |P| in units of \
sqrt(2ME), averaged over the checkpoints (about 1/sqrt(N) = 0.07 for an equilibrium gas; the \
walls exchange momentum with the balls). Speeds are divided by the rms speed at their checkpoint \
and pooled over the second half of the run (100 checkpoints in all); KS is the \
Kolmogorov–Smirnov distance. ms/step is measured while another job of the program shares the \
two cores. The wall-impulse residual checks the impulse bookkeeping used for the pressure: per \
step and axis, the change of the balls' total momentum minus the net impulse counted on the \
walls, summed, over the summed wall impulses (0 is perfect; f32 rounds).
";

pub const Z_TEXT: &str = "\
Elastic hard disks (2D, bulk η = 0.3 and 0.5) and spheres (3D, bulk η = 0.3), Maxwell \
velocities at kT = 1, in boxes whose lengths accessible to the centres are ℓ = (60, 30) (2D) \
and (10, 10, 20) (3D) diameters (the box is ℓ + σ); the reference also runs a larger 3D box, \
ℓ = (14, 14, 28), too large for rapier in a few minutes. N is chosen by two short reference runs so \
that the bulk packing fraction comes out at the wanted η. The reference is equilibrated for 50 \
time units and measured over the time in the table (20 blocks); the rapier modes, each in the \
f32 and the f64 build of the adapter (`precision`; the reference always computes in f64), for 10 \
and then over the time in the table (10 blocks), one run each, from the same balls.

**The estimator.** Near a hard wall the density is not the bulk density, and near the edges \
and corners of the box the force on a wall is not the bulk pressure times its area. So:

- *Density* is counted away from the walls: the centres in the region at least w = max(ℓ_min/5, 3.5 σ) from every wall (6 σ in 2D, 3.5 \
and 5.6 σ in the two 3D boxes), sampled every 0.5 time units, divided by the region's volume; η_bulk = ρ v_ball, and \
the equation of state is evaluated at η_bulk.
- *Pressure* comes from the wall impulses, with each wall's excess near its ends eliminated by \
comparing walls of different lengths. A wall of accessible length ℓ_j feels F = P ℓ_j − 2γ in \
2D (γ the excess per end, the same at every 90° corner by symmetry), so \
P = (F_y − F_x)/(ℓ_x − ℓ_y): the force on the extra length of the long walls, which lies away \
from the corners. In 3D, with a square cross-section ℓ = (a, a, c), F_k = P A_k − 2γ Per_k \
(A_k and Per_k the accessible area and perimeter of face k; the edges' line tension adds a \
constant, of relative size ~1e-3 here, which is neglected), so \
P = (2 F_x − (a + c) F_z / a) / (a (c − a)). F_k is the mean of the two walls of axis k.
- *Temperature* kT = 2 E_kin/(D N), averaged over the samples (constant in the exact \
simulators; `kT drift` shows how much a rapier mode lost or gained during the measurement).
- Z = P/(ρ_bulk kT); the error is the standard error over the blocks. rapier's wall impulses \
are those its solver applied plus, in the `impulse` and `exact` modes, the law's impulses \
(`Kimpact::events`); the wall-impulse residual checks them against the balls' momentum.

The difference of two wall forces is noisy (about 4x the relative noise of one force), so the \
rapier runs, much shorter than the reference's, also get a low-noise comparison: \
`single-wall Z vs reference's` is the force on the walls of axis 0 over their accessible \
length or area, with the bulk density (an estimator with a bias of its own, the same in every \
simulator), relative to the reference's value of the same estimator.
";

pub const Z_CHECKS_TEXT: &str = "\
Checks of the estimator, on the reference: `naive Z` (total wall impulse over the whole box \
surface, mean density N/V, compared with the equation of state at the nominal η = N v/V), \
`no end correction` (force on one pair of walls over its accessible length or area, bulk \
density), and the result with the density counted beyond other distances w from the walls \
(cells: w, bulk η there, Z against the equation of state at that η).
";

pub const COOLING_TEXT: &str = "\
The gas above (another draw of the balls) with d̃ = 0.01 (walls too, own-mass policy), for \
T = {T} s: kinetic energy over time in the reference and in each mode (the curves are in \
`accuracy.svg` and `accuracy.csv`). The law's effective restitution depends on the masses and \
on the impact angle (grazing impacts are clamped), so the curves are compared with the \
reference, not with a constant-restitution formula. `native` has the law's head-on restitution \
sqrt(1 − 8 d̃) between balls and sqrt(1 − 2 d̃) against walls (rapier averages the two \
colliders' coefficients, which the walls' coefficient accounts for). `worst deviation` is the \
largest |E/E_ref − 1| over the 60 checkpoints; `reference, other balls` (another draw at the \
same energy) is the noise floor: beyond a few collision times every run is an independent \
sample of the same cooling.
";

pub const COST_TEXT: &str = "\
Each mode at dt, dt/2, dt/4 and dt/8 (rapier's own way to buy accuracy), in each of the four \
builds (2D and 3D, f32 and f64; one row of the plot each): the CPU time of the 200-ball gas \
per simulated second (one thread, no other job of this program running), against the relative \
energy error of that gas after T = {T} s (elastic: every loss is error), the velocity error \
after one oblique impact (masses 1:10) and in Newton's cradle. Errors are clamped at 1e-16 in \
the plot.
";
