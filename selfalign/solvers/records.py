"""Named records the compiled kernel reads and writes, and the profile table it runs on.

Every array that crosses between Python and the kernel is a numpy structured array
with named fields (never a positional tuple): one :data:`MEMBER_DTYPE` record per
trajectory holds its inputs, its working state and its outcome; arcs, events,
samples and zone/level crossings have records of their own.  Nothing here imports
numba.

Profile table.  The kernel reads every table motion from one float64 row per profile
(:func:`pack_profiles`), the header at fixed columns (:data:`DT`, :data:`AMAX`,
:data:`SWING`, :data:`REST_ACC`) and the method's data after it:

* ``exact`` on a piecewise-constant profile: m, breaks[0..m], accels[0..m-1]
  (zero-length pieces dropped);
* ``exact`` on a Fourier profile: K, a_1..a_K, b_1..b_K, omega_1..omega_K;
* ``exact`` on a piecewise-linear-y'' profile (finite jerk, the same smooth stepper):
  -m (negative: not a Fourier row), breaks[0..m], then per piece y'', the jerk (slope
  of y''), y' and y at its start and y'' at its end (m values each);
* ``moreau``: N, h, the largest |increment|, then the N table-velocity increments
  y'(t_k + h) - y'(t_k) of one period of steps from the start phase t_0 (the exact
  impulse of each step).
"""

from __future__ import annotations

import numpy as np

#: Methods the kernel runs (the ``method`` code passed to it).
EXACT_PIECEWISE, EXACT_SMOOTH, MOREAU = 0, 1, 2
#: Horizons (``until`` codes): the requested periods; a final outcome; the first stick
#: event; the first bit-exact repeat of the period-boundary state (the periodic motion
#: Floquet analysis linearises about).
UNTIL_PERIODS, UNTIL_REST, UNTIL_STICK, UNTIL_CYCLE = 0, 1, 2, 3
UNTIL_CODES = {"periods": UNTIL_PERIODS, "rest": UNTIL_REST, "stick": UNTIL_STICK, "cycle": UNTIL_CYCLE}

#: Profile-table header columns.
DT, AMAX, SWING, REST_ACC, DATA = 0, 1, 2, 3, 4

#: The settings of one run of the driver, the same for every member (one record): the horizon
#: (``until`` code, ``total`` periods), the event budget, the longest cycle recognised, the
#: accumulation tolerance, whether repeating periods may be skipped, and Moreau's iteration.
RUN_DTYPE = np.dtype([("until", "i8"), ("total", "i8"), ("max_events", "i8"), ("max_cycle", "i8"),
                      ("acc_tol", "f8"), ("fp_tol", "f8"), ("fp_max_iter", "i8"), ("fast_forward", "?"),
                      ("fixed_point", "?")], align=True)


def run_settings(until: int, total: int, max_events: int, max_cycle: int, acc_tol: float, fast_forward: bool,
                 fixed_point: bool = False, fp_tol: float = 0.0, fp_max_iter: int = 1) -> np.ndarray:
    """The :data:`RUN_DTYPE` record (an array of one) of a run."""
    run = np.zeros(1, dtype=RUN_DTYPE)
    run[0] = (until, total, max_events, max_cycle, acc_tol, fp_tol, fp_max_iter, fast_forward, fixed_point)
    return run


#: One trajectory: inputs (set before the run), working state, outcome.  The working records
#: (this and HIST_DTYPE) are aligned, so that no field straddles a cache line; the records that
#: leave the kernel as results (arcs, events, samples, crossings) are packed, with no padding
#: bytes that could differ between two runs or files.  Positions are
#: relative to the member's origin (x_mu on a stop zone, else x0); see the kernel.
MEMBER_DTYPE = np.dtype([
    # inputs
    ("profile", "i8"), ("xi", "f8"), ("v", "f8"), ("tau0", "f8"),
    ("zone", "?"), ("w", "f8"), ("c_mu", "f8"),
    ("static_ratio", "f8"), ("v_s", "f8"), ("delta", "f8"),     # friction law: r = mu_s/mu_k; Stribeck if v_s > 0
    # derived at the start of the run
    ("b1", "f8"), ("omega", "f8"), ("xs", "f8"), ("acc_tol", "f8"), ("rest_acc", "f8"),
    # working state
    ("mode", "i1"), ("n", "i8"), ("piece0", "i8"), ("fresh", "?"), ("events", "i8"), ("steps", "i8"),
    ("dxp", "f8"), ("lo", "f8"), ("hi", "f8"), ("regions", "i1"), ("stop_n", "i8"), ("stop_tau", "f8"),
    ("sticks", "i8"), ("zone_sticks", "i8"), ("h1", "f8"), ("h2", "f8"), ("nh", "i1"),
    ("first_stick_xi", "f8"), ("first_stick_n", "i8"), ("first_stick_tau", "f8"),
    ("at_rest", "?"), ("xi_max", "f8"), ("path", "f8"), ("fast_forward", "i8"),
    ("n_arcs", "i8"), ("n_events", "i8"), ("n_samples", "i8"),
    ("fp_iterations", "i8"), ("fp_unconverged", "i8"), ("fp_max_change", "f8"),
    # outcome
    ("reason", "i1"), ("n_end", "i8"), ("tau_end", "f8"), ("contraction", "f8"), ("advance", "f8"),
    ("cycle", "i8"), ("cycle_region", "i1"), ("last_stick", "f8"),
], align=True)

#: One closed-form arc of the exact solver (kinds: :mod:`selfalign.model.arcs`).  ``x``
#: is the start position, ``acc`` x'' at the start, ``table_acc`` the table acceleration
#: y'' (NaN on a smooth profile), ``omega`` sqrt(b1) inside the zone (else 0), ``region``
#: LOW, ZONE or HIGH (:mod:`selfalign.solvers.outcomes`).
ARC_DTYPE = np.dtype([("kind", "i1"), ("period", "i8"), ("tau", "f8"), ("duration", "f8"), ("x", "f8"),
                      ("v", "f8"), ("acc", "f8"), ("table_acc", "f8"), ("omega", "f8"), ("mode", "i1"),
                      ("region", "i1")])

#: One event (:class:`selfalign.solvers.outcomes.EventKind`): time, state, the mode before
#: and after, and x'' just before and after (saltation matrices, Sect. 6.1).
EVENT_DTYPE = np.dtype([("kind", "i1"), ("period", "i8"), ("tau", "f8"), ("x", "f8"), ("v", "f8"),
                        ("mode_before", "i1"), ("mode", "i1"), ("acc_before", "f8"), ("acc_after", "f8")])

#: One dense-output sample.
SAMPLE_DTYPE = np.dtype([("period", "i8"), ("tau", "f8"), ("x", "f8"), ("v", "f8"), ("mode", "i1")])

#: First crossing of a boundary (x_mu, x_mu + w, then the requested levels): the time, the
#: velocity there and the stick events at x >= x_mu before it (period -1: never).
CROSS_DTYPE = np.dtype([("period", "i8"), ("tau", "f8"), ("v", "f8"), ("sticks", "i8")])

#: The state at one period boundary and the period that followed (cycle detection).
HIST_DTYPE = np.dtype([("v", "f8"), ("xi", "f8"), ("dxp", "f8"), ("lo", "f8"), ("hi", "f8"), ("path", "f8"),
                       ("mode", "i1"), ("regions", "i1")], align=True)


def records(dtype, size: int | tuple = 0) -> np.recarray:
    """A zeroed record array of ``dtype`` for the kernel (a recarray, so that the kernel's
    attribute access to fields also works uncompiled, NUMBA_DISABLE_JIT=1)."""
    return np.zeros(size, dtype=dtype).view(np.recarray)


def pack_profiles(rows: list[np.ndarray]) -> np.ndarray:
    """The profile table: the rows (header + method data) padded with NaN to one width."""
    width = max(row.size for row in rows)
    table = np.full((len(rows), width), np.nan)
    for i, row in enumerate(rows):
        table[i, :row.size] = row
    return table


def profile_header(dt: float, max_acceleration: float, swing: float, rest_acc: float) -> list[float]:
    """The header columns of one profile row (see the module docstring)."""
    return [float(dt), float(max_acceleration), float(swing), float(rest_acc)]


# The row layout (module docstring), the one place that knows where a datum sits.  Plain functions
# of the piece count m (harmonic count k) and an index; :func:`selfalign.solvers.jit.kernel`
# registers them with numba (:data:`LAYOUT`), so that the engine reads rows through these very
# functions and the builders below write them through the same ones.

def data_size(row) -> int:
    """The first data column: m pieces (piecewise constant), K harmonics (Fourier), -m pieces
    (piecewise-linear y''), N steps (Moreau)."""
    return int(row[DATA])


def col_break(i: int) -> int:
    """Column of break i (0..m) of a piecewise-constant or piecewise-linear row."""
    return DATA + 1 + i


def col_level(m: int, i: int) -> int:
    """Column of piece i's y'' (piecewise constant), or of y'' at its start (piecewise linear)."""
    return DATA + 2 + m + i


def col_jerk(m: int, i: int) -> int:
    """Column of piece i's jerk (the slope of y'') of a piecewise-linear row."""
    return DATA + 2 + 2 * m + i


def col_start_velocity(m: int, i: int) -> int:
    """Column of y' at the start of piece i of a piecewise-linear row."""
    return DATA + 2 + 3 * m + i


def col_start_position(m: int, i: int) -> int:
    """Column of y at the start of piece i of a piecewise-linear row."""
    return DATA + 2 + 4 * m + i


def col_end_level(m: int, i: int) -> int:
    """Column of y'' at the end of piece i of a piecewise-linear row."""
    return DATA + 2 + 5 * m + i


def col_fourier(k: int, j: int, i: int) -> int:
    """Column of harmonic i's cosine coefficient (j = 0), sine coefficient (1) or angular frequency
    (2) of a Fourier row with k harmonics."""
    return DATA + 1 + j * k + i


#: Columns of a Moreau row: the step h and the largest |impulse|; :func:`col_impulse` the impulses.
MOREAU_STEP, MOREAU_LARGEST = DATA + 1, DATA + 2


def col_impulse(k: int) -> int:
    """Column of the table impulse of Moreau step k."""
    return DATA + 3 + k


#: The layout functions the engine calls (registered with numba by :func:`selfalign.solvers.jit.kernel`).
LAYOUT = (data_size, col_break, col_level, col_jerk, col_start_velocity, col_start_position, col_end_level,
          col_fourier, col_impulse)


def piecewise_row(head: list, breaks, accels) -> np.ndarray:
    """The row of a piecewise-constant profile: m, breaks[0..m], accels[0..m-1]."""
    return np.array(head + [len(accels)] + list(breaks) + list(accels), dtype=float)


def linear_row(head: list, breaks, levels, jerks, velocities, positions, ends) -> np.ndarray:
    """The row of a piecewise-linear-y'' profile: -m, breaks[0..m], then per piece y'' at its start,
    the jerk, y' and y at its start, y'' at its end."""
    return np.array(head + [-len(levels)] + list(breaks) + list(levels) + list(jerks) + list(velocities)
                    + list(positions) + list(ends), dtype=float)


def fourier_row(head: list, cos_coeffs, sin_coeffs, omega) -> np.ndarray:
    """The row of a Fourier profile: K, the cosine and sine coefficients, the angular frequencies."""
    return np.array(head + [len(omega)] + list(cos_coeffs) + list(sin_coeffs) + list(omega), dtype=float)


def moreau_row(head: list, h: float, impulse: np.ndarray) -> np.ndarray:
    """The row of Moreau time-stepping: N, h, the largest |impulse|, the N table impulses."""
    return np.concatenate([head, [impulse.size, h, float(np.max(np.abs(impulse)))], impulse])
