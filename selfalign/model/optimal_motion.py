"""The fastest table motion under an acceleration limit (beyond the paper; derivation in
docs/explanation/optimal-motion.md).

On a uniform surface (mu_bar = 1, Sect. 3.2) with static/kinetic friction of ratio r = mu_s / mu_k >= 1
(r = 1: the paper's Coulomb law) and table accelerations |y''| <= a, a > r, no periodic table motion of
period dt moves the part faster on average than

    v* = (a^2 - 1) r^2 dt / (4 a (1 + r)^2),

and the three-piece motion y'' = -a, +a, +r with the durations of :func:`optimal_phase_times` attains it:
the part slides forward for D = r dt / (1 + r) (a triangle of x' up to (a^2 - 1) D / (2 a)) and sticks for
D / r while the table regains its speed at the largest acceleration that keeps it stuck.
"""

from __future__ import annotations

import numpy as np

from .registry import formula

_WHY = ("beyond the paper: the largest steady mean velocity under |y''| <= a and its table motion, proven in "
        "docs/explanation/optimal-motion.md (the paper optimises within the three-phase family of Sect. 4.4.3)")


@formula(unnumbered=_WHY, kernel=False)
def optimal_mean_velocity(dt, accel_max, ratio):
    """v* = (a^2 - 1) r^2 dt / (4 a (1 + r)^2): the largest steady mean velocity x' of the part over all
    periodic table motions of period ``dt`` with |y''| <= ``accel_max`` = a, under static/kinetic friction
    of ratio ``ratio`` = r (r = 1: Coulomb, (a^2 - 1) dt / (16 a)).

    Valid for a > r (for a <= r the part never leaves the table's motion and the mean velocity is 0).
    Inputs broadcast.
    """
    dt, a, r = (np.asarray(v, dtype=float) for v in (dt, accel_max, ratio))
    return (a * a - 1.0) * r * r * dt / (4.0 * a * (1.0 + r) ** 2)


@formula(unnumbered=_WHY, kernel=False)
def optimal_phase_times(dt, accel_max, ratio):
    """(t_back, t_catch, t_stick): the durations of y'' = -a, +a and +r of the fastest motion.

    With the forward-slip time D = r dt / (1 + r): t_back = D (a + 1) / (2 a) (the table pulls back, the
    part slides forward and gains speed at a - 1), t_catch = D (a - 1) / (2 a) (the table catches up, the
    part loses speed at a + 1 and reaches rest exactly at its end) and t_stick = D / r (the part sticks
    while the table regains the speed D at the static limit r).  They sum to dt and y'' has zero mean.
    Inputs broadcast.
    """
    dt, a, r = (np.asarray(v, dtype=float) for v in (dt, accel_max, ratio))
    slide = r * dt / (1.0 + r)
    return slide * (a + 1.0) / (2.0 * a), slide * (a - 1.0) / (2.0 * a), slide / r
