"""What a self-aligning station must do, in SI units: the input of :func:`selfalign.analysis.design.design`.

A spec names the machine (friction coefficient mu of the base surface and its relative
uncertainty, the friction ratio c_mu of the high-friction strip, gravity), the part (its
width, the transition width w of eqs. 7-9), the actuator's limits (stroke, |acceleration|,
period range) and the task (distance to the strip, positioning tolerance, objective).
Every check raises before any work, with one line naming the key.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .errors import check_finite, check_integer, check_positive
from .friction import FrictionLaw
from .profiles import MIN_RAMP_FRACTION

OBJECTIVES = ("process_time", "robustness")
#: Profile families the design tool searches: the paper's three-phase profile (Sect. 4.4.3) and the
#: fastest table motion (docs/explanation/optimal-motion.md).
FAMILIES = ("three_phase", "optimal")
#: Most designs a search grid may hold (periods x strokes x accelerations^2 x c_mu values): the
#: closed-form screening needs about :data:`BYTES_PER_DESIGN` bytes and 4 us per design (921,600
#: designs, the default grid of a c_mu range: 0.23 GB, 3.6 s).
MAX_DESIGNS = 4_000_000
#: Peak memory of the search per design (tracemalloc over the grid and its screening: 245 bytes), rounded up.
BYTES_PER_DESIGN = 250
#: Candidates of the time-error front that the design tool simulates besides those it verifies.
FRONT_SIMULATED = 12
#: Values of mu at which the design tool checks the closed-form conditions.
DENSE_MU = 65
#: Most steady-state entry runs a design may simulate (entries x mu_samples x (max_verified +
#: FRONT_SIMULATED); the default is 256 x 5 x 60 = 76,800): each runs until the part stops or
#: the period budget ends, up to about a millisecond under static friction.
MAX_ENTRY_RUNS = 500_000
#: Longest distance [m] from the part to the strip: the process run simulates every period of
#: the approach (a run of 2 D / (vbar dt) periods; a table is metres long, not more).
MAX_DISTANCE = 10.0


@dataclass(frozen=True)
class DesignGrid:
    """Resolution of the search: ``periods`` (geometric over the period range), ``strokes``
    (linear up to the maximum stroke), ``accelerations`` (linear up to the maximum |y''|, for
    y2'' and y3'' each), ``c_mu`` (values over a c_mu range), ``entries`` (steady-state entries
    simulated per mu sample, >= 256), ``mu_samples`` (odd, >= 3: both extremes and the middle)
    and ``max_verified`` (most candidates the engine checks before giving up)."""

    periods: int = 12
    strokes: int = 12
    accelerations: int = 40
    c_mu: int = 4
    entries: int = 256
    mu_samples: int = 5
    max_verified: int = 48

    def __post_init__(self):
        for name, low in (("periods", 1), ("strokes", 1), ("accelerations", 2), ("c_mu", 1), ("entries", 256),
                          ("mu_samples", 3), ("max_verified", 1)):
            check_integer(f"search.{name}", getattr(self, name), low, 10_000)
        if self.mu_samples % 2 == 0:
            raise ValueError(f"search.mu_samples must be odd (the middle of the mu range is a sample), "
                             f"got {self.mu_samples}")
        runs = self.entries * self.mu_samples * (self.max_verified + FRONT_SIMULATED)
        if runs > MAX_ENTRY_RUNS:
            raise ValueError(f"search.entries x search.mu_samples x (search.max_verified + {FRONT_SIMULATED} "
                             f"designs of the front) = {self.entries:,} x {self.mu_samples:,} x "
                             f"{self.max_verified + FRONT_SIMULATED:,} = {runs:,} entry runs to simulate, more than "
                             f"the {MAX_ENTRY_RUNS:,} allowed")

    def designs(self, fixed_period: bool, fixed_c_mu: bool) -> int:
        """Designs on the grid: periods x strokes x accelerations^2 x c_mu values (one period for a
        fixed period, one c_mu for a fixed strip; strokes count at most ``strokes``)."""
        return ((1 if fixed_period else self.periods) * self.strokes * self.accelerations**2
                * (1 if fixed_c_mu else self.c_mu))


@dataclass(frozen=True)
class DesignSpec:
    """A design problem in SI units (m, s, m/s^2): what a self-aligning station must do.

    The input of :func:`~selfalign.design` (module docstring of
    ``selfalign.model.design_spec``).  A spec names the machine (friction coefficient mu
    of the base surface and its relative uncertainty, the friction ratio c_mu of the
    high-friction strip, gravity), the part (its width, the transition width w of
    eqs. 7-9), the actuator's limits (stroke, ``|acceleration|``, period range) and the task
    (distance to the strip, positioning tolerance, objective).  Every check raises before
    any work, with one line naming the key.  Design spec files are read by
    :func:`~selfalign.load_design_spec`.

    Parameters
    ----------
    mu : float
        Friction coefficient of the base surface (the kinetic one under static/kinetic or
        Stribeck friction); > 0.
    mu_uncertainty : float
        Relative uncertainty delta of mu, in [0, 1): the design must hold for every mu in
        [mu (1 - delta), mu (1 + delta)].
    c_mu : tuple of float
        (low, high) of the strip's friction ratio, 1 < low <= high; equal for a fixed strip.
    width : float
        Width of the part [m], the transition width w of eqs. 7-9 and the length scale L.
    max_stroke : float
        Largest stroke of the actuator [m].
    max_acceleration : float
        Largest ``|y''|`` of the actuator [m/s^2].
    period : tuple of float
        (low, high) of the period in s, low <= high.
    distance : float
        Distance [m] from the part to the strip's edge at the start; at most 10 m (the
        process run simulates every period of the approach).
    tolerance : float
        Positioning tolerance [m]; smaller than ``distance`` (the part starts outside the
        band it is to end in).
    g : float, optional
        Gravitational acceleration [m/s^2].  Default 9.81.
    accumulation : bool, optional
        Require Delta_x_d = 0 (every entry accumulates at x_stick_min).  Default False.
    objective : str, optional
        "process_time" (the default): the least worst-case process time; "robustness": the
        largest mu margin with a worst-case process time <= ``max_process_time``.
    max_process_time : float, optional
        The process time [s] to keep; required with ``objective="robustness"``.
    name : str, optional
        The name of the design (a spec file's stem).  Default "design".
    min_stroke : float, optional
        The smallest stroke the actuator can make, in (0, max_stroke] (None: any stroke up to
        ``max_stroke``; equal to it for a fixed-stroke drive such as a cam).
    grid : DesignGrid, optional
        Resolution of the search (``selfalign.model.design_spec.DesignGrid``); at most
        4,000,000 designs.  Default ``DesignGrid()``.
    friction : FrictionLaw, optional
        The friction law (``selfalign.model.friction.FrictionLaw``) on base and strip alike
        (the paper's Coulomb friction by default, static/kinetic with mu_s = r mu_k, or
        Stribeck with its ``v_s`` in m/s, made dimensionless at each mu).
    ramp : float, optional
        The time [s] over which y'' ramps linearly at each switch of the three-phase profile
        (finite jerk; None: the paper's jumps); shorter than a third of the longest period and
        at least 2^-48 times it.
    families : tuple of str, optional
        The profile families searched, among "three_phase" (the paper's, Sect. 4.4.3) and
        "optimal" (the fastest table motion, docs/explanation/optimal-motion.md); the faster
        guaranteed design wins.  Default ("three_phase",).

    Attributes
    ----------
    mu_range : tuple of float
        [mu (1 - delta), mu (1 + delta)].
    c_mu_fixed : bool
        True when the strip's c_mu is fixed (low == high).

    Raises
    ------
    TypeError
        If a number of the spec is not a real number.
    ValueError
        If a value is outside its range above (the message names the key), ``friction`` is
        not a FrictionLaw, ``grid`` is not a DesignGrid, the grid holds more than
        4,000,000 designs, or ``families`` is empty, repeats a name or names another family.

    See Also
    --------
    load_design_spec : Reads a spec from a YAML file.
    design : Searches and certifies the design of a spec.

    Examples
    --------
    >>> import selfalign as sa
    >>> spec = sa.DesignSpec(mu=0.2, mu_uncertainty=0.05, c_mu=(2.0, 3.0), width=2e-3, max_stroke=1e-3,
    ...                      max_acceleration=8.0, period=(0.01, 0.1), distance=10e-3, tolerance=250e-6)
    >>> print(spec.describe())
    mu = 0.2 +- 5 % (0.19..0.21), c_mu = 2..3, w = 2 mm, stroke <= 1 mm, |y''| <= 8 m/s^2,
    f = 10..100 Hz, distance 10 mm, tolerance 250 um
    >>> spec.c_mu_fixed, spec.frequency_range()
    (False, (10.0, 100.0))
    """

    mu: float
    mu_uncertainty: float
    c_mu: tuple[float, float]
    width: float
    max_stroke: float
    max_acceleration: float
    period: tuple[float, float]
    distance: float
    tolerance: float
    g: float = 9.81
    accumulation: bool = False
    objective: str = "process_time"
    max_process_time: float | None = None
    name: str = "design"
    min_stroke: float | None = None
    grid: DesignGrid = field(default_factory=DesignGrid)
    friction: FrictionLaw = field(default_factory=FrictionLaw)
    ramp: float | None = None
    families: tuple[str, ...] = ("three_phase",)

    def __post_init__(self):
        families = self.families
        if isinstance(families, str) or not isinstance(families, (tuple, list)) or not families \
                or any(f not in FAMILIES for f in families) or len(set(families)) != len(families):
            raise ValueError(f"profile.families must be a non-empty list of distinct names among "
                             f"{', '.join(FAMILIES)}, got {families!r}")
        object.__setattr__(self, "families", tuple(families))
        if not isinstance(self.friction, FrictionLaw):
            raise ValueError(f"friction must be a FrictionLaw, got {type(self.friction).__name__}")
        if self.ramp is not None:
            check_positive("actuator.ramp", self.ramp)
        for key in ("mu", "width", "max_stroke", "max_acceleration", "distance", "tolerance", "g"):
            check_positive(key, getattr(self, key))
        if self.distance > MAX_DISTANCE:
            raise ValueError(f"task.distance must be <= {MAX_DISTANCE:g} m (the process run simulates every period of "
                             f"the approach), got {self.distance!r}")
        if self.tolerance >= self.distance:
            raise ValueError(f"task.tolerance must be smaller than task.distance = {self.distance!r} m (the part "
                             f"starts outside the band it is to end in), got {self.tolerance!r}")
        if self.min_stroke is not None and not 0.0 < check_finite("min_stroke", self.min_stroke) <= self.max_stroke:
            raise ValueError(f"min_stroke must lie in (0, max_stroke = {self.max_stroke!r}], got {self.min_stroke!r}")
        delta = check_finite("mu_uncertainty", self.mu_uncertainty)
        if not 0.0 <= delta < 1.0:
            raise ValueError(f"mu_uncertainty must lie in [0, 1) (a relative uncertainty), got {delta!r}")
        low, high = (check_finite("c_mu", c) for c in self.c_mu)
        if not 1.0 < low <= high:
            raise ValueError(f"c_mu must satisfy 1 < low <= high (a high-friction strip), got {self.c_mu!r}")
        p_low, p_high = (check_positive("period", p) for p in self.period)
        if p_low > p_high:
            raise ValueError(f"period must satisfy low <= high, got {self.period!r}")
        if self.ramp is not None and 3.0 * self.ramp >= p_high:
            raise ValueError(f"actuator.ramp must be shorter than a third of the longest period ({p_high:g} s: three "
                             f"ramps per period), got {self.ramp!r}")
        if self.ramp is not None and self.ramp < MIN_RAMP_FRACTION * p_high:
            raise ValueError(f"actuator.ramp must be at least 2^-48 times the longest period, "
                             f"{MIN_RAMP_FRACTION * p_high!r} s (a shorter ramp is lost in the rounding of the "
                             f"profile's switch times; leave ramp out for the paper's jumps), got {self.ramp!r}")
        if self.objective not in OBJECTIVES:
            raise ValueError(f"objective must be one of {', '.join(OBJECTIVES)}, got {self.objective!r}")
        if self.objective == "robustness" and self.max_process_time is None:
            raise ValueError("objective 'robustness' needs task.max_process_time (the process time to keep)")
        if self.max_process_time is not None:
            check_positive("max_process_time", self.max_process_time)
        if not isinstance(self.grid, DesignGrid):
            raise ValueError(f"grid must be a DesignGrid, got {type(self.grid).__name__}")
        designs = self.grid.designs(p_low == p_high, low == high)
        if designs > MAX_DESIGNS:
            raise ValueError(f"search grid of {designs:,} designs (search.periods x strokes x accelerations^2 x c_mu) "
                             f"needs about {designs * BYTES_PER_DESIGN / 1e9:.3g} GB, more than the {MAX_DESIGNS:,} "
                             f"designs allowed ({MAX_DESIGNS * BYTES_PER_DESIGN / 1e9:g} GB)")

    @property
    def mu_range(self) -> tuple[float, float]:
        """[mu (1 - delta), mu (1 + delta)]."""
        return self.mu * (1.0 - self.mu_uncertainty), self.mu * (1.0 + self.mu_uncertainty)

    @property
    def c_mu_fixed(self) -> bool:
        return self.c_mu[0] == self.c_mu[1]

    def frequency_range(self) -> tuple[float, float]:
        """[1 / period_high, 1 / period_low] in Hz."""
        return 1.0 / self.period[1], 1.0 / self.period[0]

    def describe(self) -> str:
        """One line of the spec's numbers, for reports."""
        lo, hi = self.mu_range
        c = f"{self.c_mu[0]:g}" if self.c_mu_fixed else f"{self.c_mu[0]:g}..{self.c_mu[1]:g}"
        f_lo, f_hi = self.frequency_range()
        stroke = (f"<= {1e3 * self.max_stroke:g}" if self.min_stroke is None
                  else f"{1e3 * self.min_stroke:g}..{1e3 * self.max_stroke:g}")
        return (f"mu = {self.mu:g} +- {100 * self.mu_uncertainty:g} % ({lo:.4g}..{hi:.4g}), c_mu = {c}, "
                f"w = {1e3 * self.width:g} mm, stroke {stroke} mm, |y''| <= "
                f"{self.max_acceleration:g} m/s^2, f = {f_lo:.4g}..{f_hi:.4g} Hz, distance {1e3 * self.distance:g} mm, "
                f"tolerance {1e6 * self.tolerance:g} um{', accumulation' if self.accumulation else ''}"
                + (f", {self.effects()}" if self.effects() != "none" else ""))

    def effects(self) -> str:
        """The effects beyond the paper's model this spec declares, in words ("none" for the paper's model)."""
        parts = []
        if self.friction.kind == "static_kinetic":
            parts.append(f"static/kinetic friction mu_s/mu_k = {self.friction.ratio:g}")
        elif self.friction.stribeck:
            parts.append(f"Stribeck friction mu_s/mu_k = {self.friction.ratio:g}, v_s = {1e3 * self.friction.v_s:g} "
                         f"mm/s, delta = {self.friction.delta:g}")
        if self.ramp is not None:
            parts.append(f"finite jerk: y'' ramps over {1e3 * self.ramp:g} ms at each switch")
        return "; ".join(parts) or "none"


def period_from_frequency(low_hz: float, high_hz: float) -> tuple[float, float]:
    """The period range (s) of a frequency range (Hz)."""
    for value in (low_hz, high_hz):
        check_positive("actuator.frequency", value)
    if low_hz > high_hz:
        raise ValueError(f"actuator.frequency must satisfy min <= max, got {low_hz!r} > {high_hz!r}")
    return 1.0 / high_hz, 1.0 / low_hz

