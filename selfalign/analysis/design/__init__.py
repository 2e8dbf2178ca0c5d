"""From a machine's limits to a guaranteed self-aligning design (Sects. 2, 4.4.3, 5, 7).

The two objectives of Sect. 2: bring the part to x_d in the least process time T_p and stop
it there with the smallest positioning error Delta_x_d.  :func:`design` searches the
three-phase profiles (Sect. 4.4.3) and, where the spec's ``families`` ask for it, the fastest
table motions (:mod:`.optimal`, docs/explanation/optimal-motion.md) inside an actuator's limits,
in SI units (:class:`~selfalign.model.design_spec.DesignSpec`), and certifies the one it returns;
with both families the faster guaranteed design wins and ``Design.gain`` compares them.  What
follows describes the three-phase search; the optimal family is verified in the same way
(:func:`~.optimal.verify_motions`), without the closed forms of the paper's profile.

Scaling (Sect. 3.2).  The length scale is the part's width, L = w~ (so w = 1), and
T = sqrt(L / (mu g)).  A fixed SI profile (period P, stroke S, accelerations A2, A3) is,
at friction coefficient mu', the dimensionless profile dt = P / T(mu'), dy = S / L,
y2 = A2 / (mu' g), y3 = A3 / (mu' g): a change of mu changes the profile the model sees.

Search.  A grid over (P, S, A2, A3, c_mu) inside the limits (:class:`DesignGrid`), screened
with closed forms at every mu of a dense sample of [mu (1 - delta), mu (1 + delta)]
(:data:`~selfalign.model.design_spec.DENSE_MU`): a physical profile (q <= 1, Sect. 5.1), forward motion (case > 0 and
vbar > 0, :func:`~selfalign.analysis.steady_state.steady_state_grid`), a strip that can hold
the part (max(A2, A3) <= c_mu mu' g, eq. 41) and, where accumulation is asked for, y2'' > y3''
(docs/explanation/paper.md: no setting with y3'' > y2''
accumulates) and an end position x_stick_min (eq. 41) that moves with mu by at most the
tolerance.  Survivors are ranked by a closed-form process time (distance to travel over the
slowest vbar, :class:`Screen`) and verified
with the engine, best first.

Effects.  The spec may declare static/kinetic or Stribeck friction and y'' ramps
(finite jerk; candidates whose ramps do not fit are dropped and counted).  The closed forms
above are the paper's model, so they then only rank the candidates (a heuristic); the
guarantee and the process time are simulated with the effect (:func:`friction_at`,
:func:`ramp_at`), by the most exact method that can
(:func:`~selfalign.solvers.methods.most_exact_method`; ``Verification.method``).

Guarantee (per candidate, :func:`verify`).  At ``mu_samples`` values of mu (both extremes
and the middle included), every one of ``entries`` steady-state entries into the strip
(Sect. 7.1, :func:`~selfalign.analysis.positioning.positioning_grid`) must end at rest or
accumulate, and with ``accumulation`` every one must accumulate; the sufficient condition
of Sect. 7.3 (x_{n+1}(x_mu) < x_stick_min, eq. 59) is reported where eq. 59 applies.  The
end positions are bounded over the whole mu interval and every entry phase, not only at the
samples (:func:`end_bounds`): no part rests below x_stick_min at mu_max (eq. 41, a proof; for
a design whose entries all accumulate the bound is the range of eq. 41 over the interval), and
the largest end is the largest sample plus the allowance the sampling gives for what lies
between samples (:func:`phase_sup`, :func:`mu_sup`).  The middle of the bound is x_d, its
half-width the robust error Delta_x_d,mu, which must not exceed the tolerance.  The process time
is simulated: the part at rest on the table (x' = 0) a distance D before the strip at the
start of the dwell (t = 0), until its first arrival within the tolerance of x_d
(``t_arrive``; an accumulation reaches x_d only as t -> infinity, so the band is needed)
and until the solver decides rest or accumulation (``t_rest``), at every mu sample; its bound
over the interval (:func:`worst_process_time`) must not exceed ``max_process_time``.

The guarantee is as strong as the model (:data:`ASSUMPTIONS`, with the spec's effects:
``Design.assumptions``).

Modules: :mod:`.candidates` (the grid and the scaling), :mod:`.screening` (closed forms),
:mod:`.optimal` (the optimal family: its candidates and their simulated guarantee),
:mod:`.verification` (the simulated guarantee and its bounds), :mod:`.search` (:func:`design`),
:mod:`.explanation` (why no design meets a spec), :mod:`.design_map`.  The design as text is
presentation: :func:`selfalign.io.design_report.design_report`.
"""

from __future__ import annotations

from .candidates import Candidates, dimensionless, friction_at, mu_values, ramp_at, scale, search_grid
from .design_map import DesignMap, design_map
from .optimal import Motion, motions, verify_motions
from .screening import Screen, end_spread, robustness_margin, screen
from .search import ASSUMPTIONS, Design, design
from .verification import Verification, end_bounds, mu_sup, phase_sup, sufficient_condition, verify, worst_process_time

__all__ = ["ASSUMPTIONS", "Candidates", "Design", "DesignMap", "Motion", "Screen", "Verification", "design",
           "design_map", "dimensionless", "end_bounds", "end_spread", "friction_at", "motions", "mu_sup", "mu_values",
           "phase_sup", "ramp_at", "robustness_margin", "scale", "screen", "search_grid", "sufficient_condition",
           "verify", "verify_motions", "worst_process_time"]
