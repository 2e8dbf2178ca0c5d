"""Several parts on one table: the parts, their contacts and impacts (the paper's Sect. 8, recommendation 5).

N rigid parts lie on one line on the same table.  Part i (i = 0 the rear-most, N - 1 the front-most; the
parts walk forward, +x, toward the stop zone) has its front at x_i (the paper's x), width w_i, mass m_i and
friction factor k_i (its friction coefficient relative to the table's mu).  It covers [x_i - w_i, x_i]; the
gap to the part in front is g_i = (x_{i+1} - w_{i+1}) - x_i >= 0.  In the paper's scaling (Sect. 3.2,
forces per m mu g) part i moves by

    m_i x_i'' = -m_i y'' + f_i + lam_{i-1} - lam_i,      f_i in -m_i k_i mu_bar_i(x_i) Sign(x_i'),

with mu_bar_i of eqs. 7-9 over the part's own width and lam_i >= 0 the compressive force between parts i
and i + 1, zero unless g_i = 0 (unilateral contact).

Which parts stick, which slide and which contacts open is decided by one convex problem on the chain,
:func:`chain_minimiser` (docs/explanation/several-parts.md): at a common velocity the accelerations of
touching parts minimise sum m_i ((a_i - b_i)^2 / 2 + s_i |a_i|) subject to a_{i+1} >= a_i on closed
contacts, whose optimality conditions are exactly the equations of motion above with their set-valued
friction and complementary contact forces.  The same problem at the velocity level gives Moreau's
time-step and the impact law (:func:`impact_velocities`).  It is solved exactly, by pooling adjacent
violators (each pooled block's exact one-dimensional minimiser), not iterated to a tolerance.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from dataclasses import KW_ONLY, dataclass

from .errors import check_finite, check_positive, check_real
from .registry import formula, kernel_helper

#: Touching parts may overlap by this many ulp of their positions and widths (rounding of computed positions).
OVERLAP_ULPS = 4
#: Rows of the scratch array :func:`chain_minimiser` needs (shape (CHAIN_WORK_ROWS, N)).
CHAIN_WORK_ROWS = 6
#: Rows of the scratch array :func:`impact_velocities` needs (shape (IMPACT_WORK_ROWS, N)).
IMPACT_WORK_ROWS = CHAIN_WORK_ROWS + 2


@dataclass(frozen=True)
class Part:
    """One rigid part on the table, among several.

    A :class:`~selfalign.Scene` with ``parts=[Part(...), ...]`` simulates several parts on one line of the
    table, the rear-most first, with unilateral contacts between neighbours and Newton's impact law
    (docs/explanation/several-parts.md).  Each part carries its own start, extent, mass and friction.

    Parameters
    ----------
    x0 : float
        Start position of the part's front (the paper's x), dimensionless; finite.
    v0 : float, optional
        Start velocity relative to the table; finite.  Default 0.
    width : float
        The part's width w > 0 (dimensionless, Sect. 3.3): it covers [x - w, x], and on a stop zone its
        friction rises over this width (eqs. 7-9).  Keyword only.
    mass : float, optional
        Its mass relative to the others, > 0 (only ratios of masses matter).  Default 1.
    friction_factor : float, optional
        Its friction coefficient relative to the table's mu, > 0 (mu_bar is multiplied by it).  Default 1.

    Attributes
    ----------
    x0 : float
        Start position of the front.
    v0 : float
        Start velocity relative to the table.
    width : float
        Width w.
    mass : float
        Mass (relative).
    friction_factor : float
        Friction coefficient relative to the table's mu.

    Raises
    ------
    TypeError
        If a value is not a real number.
    ValueError
        If a value is not finite, or width, mass or friction_factor is not > 0.

    See Also
    --------
    Scene : Takes several parts (``parts=[Part(...), ...]``) and their restitution.

    Examples
    --------
    >>> import selfalign as sa
    >>> sa.Part(0.0, width=0.05)
    Part(x0=0.0, v0=0.0, width=0.05, mass=1.0, friction_factor=1.0)
    >>> sa.Part(0.0, width=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: width must be > 0, got -1.0
    """

    x0: float
    v0: float = 0.0
    _: KW_ONLY
    width: float
    mass: float = 1.0
    friction_factor: float = 1.0

    def __post_init__(self):
        for name in ("x0", "v0"):
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        for name in ("width", "mass", "friction_factor"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))


def check_parts(parts) -> tuple[Part, ...]:
    """Return ``parts`` as a tuple, or raise unless it is a non-empty sequence of :class:`Part` listed rear to
    front without overlaps.

    Parameters
    ----------
    parts : sequence of Part
        The parts, the rear-most first: part i + 1's rear x0 - width must not lie behind part i's front x0
        by more than rounding (:data:`OVERLAP_ULPS`): touching parts are allowed, also where their positions
        were computed (``Part(13 * 0.05, width=0.05)`` behind ``Part(12 * 0.05, width=0.05)``: 0.6 against
        0.6000000000000001).  The solvers treat such an overlap as touching.

    Returns
    -------
    tuple of Part

    Raises
    ------
    TypeError
        If ``parts`` is not a sequence, or an entry is not a Part (naming its index).
    ValueError
        If ``parts`` is empty, or two neighbours overlap (naming both and their positions).

    Examples
    --------
    >>> from selfalign.model.parts import Part, check_parts
    >>> len(check_parts([Part(0.0, width=0.1), Part(0.1, width=0.1)]))
    2
    >>> check_parts([Part(0.0, width=0.1), Part(0.05, width=0.1)])
    Traceback (most recent call last):
    ...
    ValueError: parts[1] overlaps parts[0]: its rear x0 - width = -0.05 lies behind the front x0 = 0 ...
    """
    if isinstance(parts, (str, bytes)) or not isinstance(parts, Sequence):
        raise TypeError(f"parts must be a sequence of Part, got {type(parts).__name__}")
    if not parts:
        raise ValueError("parts must hold at least one Part, got none")
    for i, part in enumerate(parts):
        if not isinstance(part, Part):
            raise TypeError(f"parts[{i}] must be a Part, got {type(part).__name__}")
    for i in range(len(parts) - 1):
        rear = parts[i + 1].x0 - parts[i + 1].width
        rounding = OVERLAP_ULPS * sys.float_info.epsilon * max(abs(parts[i].x0), abs(parts[i + 1].x0),
                                                               parts[i + 1].width)
        if rear < parts[i].x0 - rounding:
            raise ValueError(f"parts[{i + 1}] overlaps parts[{i}]: its rear x0 - width = {rear:g} lies behind the "
                             f"front x0 = {parts[i].x0:g} of parts[{i}] (parts are listed rear to front and may "
                             f"touch, not overlap)")
    return tuple(parts)


def check_restitution(e) -> float:
    """Return the restitution coefficient ``e`` as a float, or raise unless it is a real number in [0, 1].

    Parameters
    ----------
    e : float
        Newton's coefficient of restitution of the contacts between parts (:func:`impact_velocities`):
        0 plastic, 1 elastic.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``e`` is not a real number.
    ValueError
        If ``e`` lies outside [0, 1] or is NaN.

    Examples
    --------
    >>> from selfalign.model.parts import check_restitution
    >>> check_restitution(0.5)
    0.5
    >>> check_restitution(1.5)
    Traceback (most recent call last):
    ...
    ValueError: restitution must be a number in [0, 1] (0 plastic, 1 elastic), got 1.5
    """
    value = check_real("restitution", e)
    if not 0.0 <= value <= 1.0:
        raise ValueError(f"restitution must be a number in [0, 1] (0 plastic, 1 elastic), got {e!r}")
    return value


@kernel_helper
def _block_minimiser(first, last, m, beta, s, offset) -> float:
    """The minimiser w of sum_j m_j ((w - beta_j)^2 / 2 + s_j |w - offset_j|) over j in [first, last]: zero
    of the increasing g(w) = M w - sum m beta + sum m s Sign(w - offset), exact up to the rounding of its
    sums (a soft threshold where the offsets are equal, else the breakpoint or interval where g changes
    sign)."""
    mass, pull, stick, low, high = 0.0, 0.0, 0.0, offset[first], offset[first]
    for j in range(first, last + 1):
        mass += m[j]
        pull += m[j] * beta[j]
        stick += m[j] * s[j]
        low, high = min(low, offset[j]), max(high, offset[j])
    if stick == 0.0:
        return pull / mass
    if low == high:
        excess = pull - mass * low
        return low + math.copysign(max(abs(excess) - stick, 0.0), excess) / mass
    below = -math.inf                        # the largest breakpoint after which g is still < 0
    for j in range(first, last + 1):
        o = offset[j]
        side, tie = 0.0, 0.0
        for i in range(first, last + 1):
            weight = m[i] * s[i]
            if offset[i] < o:
                side += weight
            elif offset[i] > o:
                side -= weight
            else:
                tie += weight
        g = mass * o - pull + side
        if g - tie <= 0.0 <= g + tie:
            return o
        if g + tie < 0.0:
            below = max(below, o)
    side = 0.0
    for i in range(first, last + 1):
        side += m[i] * s[i] if offset[i] <= below else -m[i] * s[i]
    return (pull - side) / mass


@formula(unnumbered="the equations of motion of several parts in contact (eq. 6 per part, Coulomb friction of "
                    "eq. 2, unilateral contact) as the optimality conditions of a convex problem on the chain; "
                    "beyond the paper (Sect. 8, recommendation 5)")
def chain_minimiser(b, m, s, lower, joined, out, work) -> None:
    """Write into ``out`` the unique minimiser a of sum_i m_i ((a_i - b_i)^2 / 2 + s_i |a_i|) subject to
    a_{i+1} - a_i >= lower_i wherever ``joined[i]``.

    The mode selection of several parts (docs/explanation/several-parts.md).  Its optimality conditions
    are m_i a_i = m_i b_i - m_i s_i xi_i + lam_{i-1} - lam_i with xi_i in Sign(a_i) and lam_i >= 0
    complementary to a_{i+1} - a_i - lower_i >= 0: with b_i = -y'' and s_i = k_i mu_bar_i they are the
    accelerations of touching parts at rest (a_i = 0: part i sticks; touching parts with different a_i
    separate), with s = 0 and b_i = -y'' - sign(v) k_i mu_bar_i those of parts sliding together, and at the
    velocity level Moreau's step and the impact law (:func:`impact_velocities`).

    Solved exactly by pooling adjacent violators: with a_i = w_i + D_i (D the running sum of ``lower`` along
    each joined run) the constraints are w_{i+1} >= w_i, the loss stays separable and convex, and merging
    neighbouring blocks while the rear one's minimiser exceeds the front one's ends at the minimiser (Best,
    Chakravarti and Ubhaya 2000).  Blocks with equal minimisers are not merged (a closed contact without
    force).  Loops only, no allocation: the compiled steppers call it as it is.

    Parameters
    ----------
    b, m, s : numpy.ndarray
        Float arrays of length N: targets, weights (> 0) and friction bounds (>= 0).
    lower : numpy.ndarray
        Float array of length N - 1: the least a_{i+1} - a_i on each joined contact.
    joined : numpy.ndarray
        Bool array of length N - 1: whether the constraint between i and i + 1 holds (a closed contact).
    out : numpy.ndarray
        Float array of length N, written with the minimiser.
    work : numpy.ndarray
        Float scratch array of shape (CHAIN_WORK_ROWS, N).

    Examples
    --------
    Two parts at rest pushed together by y'' = -1.5: alone the front one (k = 2) would stick and the rear
    one (k = 1) slide forward at 0.5; together they share the mass-weighted factor 1.5 and stick.

    >>> import numpy as np
    >>> from selfalign.model.parts import CHAIN_WORK_ROWS, chain_minimiser
    >>> out = np.empty(2)
    >>> chain_minimiser(np.array([1.5, 1.5]), np.ones(2), np.array([1.0, 2.0]), np.zeros(1), np.array([True]),
    ...                 out, np.empty((CHAIN_WORK_ROWS, 2)))
    >>> out.tolist()
    [0.0, 0.0]
    """
    n = b.size
    shift, beta, offset, value, start = work[0], work[1], work[2], work[3], work[4]
    for i in range(n):
        shift[i] = shift[i - 1] + lower[i - 1] if i > 0 and joined[i - 1] else 0.0
        beta[i] = b[i] - shift[i]
        offset[i] = -shift[i]
    top = -1
    for i in range(n):
        top += 1
        start[top] = i
        value[top] = _block_minimiser(i, i, m, beta, s, offset)
        # A block that opens a run (flag 1) never pools with the blocks behind it.
        work[5, top] = 1.0 if i == 0 or not joined[i - 1] else 0.0
        while top > 0 and work[5, top] == 0.0 and value[top - 1] > value[top]:
            value[top - 1] = _block_minimiser(int(start[top - 1]), i, m, beta, s, offset)
            top -= 1
    for k in range(top, -1, -1):
        end = n if k == top else int(start[k + 1])
        for i in range(int(start[k]), end):
            out[i] = value[k] + shift[i]


@formula(unnumbered="Newton's impact law applied simultaneously to every closed contact of a chain of parts "
                    "(Moreau's generalised Newton law); beyond the paper (Sect. 8, recommendation 5)")
def impact_velocities(v, m, e, joined, out, work) -> None:
    """Write into ``out`` the velocities u just after an impact among parts with velocities ``v`` before it.

    The generalised Newton law (Moreau), simultaneous over every closed contact (``joined[i]``: parts i and
    i + 1 touch): u minimises the kinetic energy of the velocity jump, sum m_i (u_i - v_i)^2 / 2, subject
    to u_{i+1} - u_i >= e max(v_i - v_{i+1}, 0) on each closed contact, with impulses complementary to
    those constraints (:func:`chain_minimiser` with s = 0).  So momentum is conserved; e = 0 merges the
    approaching parts (plastic); two parts collide as in the textbook; and Newton's cradle (three equal
    parts, v = (1, 0, 0), both contacts closed, e = 1) gives u = (-1/3, 2/3, 2/3), which conserves energy
    but is not the cradle's (0, 0, 1): a simultaneous law sends no wave through the chain.  It is the law
    chosen because it is the one Moreau's time-stepping converges to, it is exact in one solve and has no
    order of collisions to choose (docs/explanation/several-parts.md).  Friction gives no impulse (it is
    bounded by the weight).

    Parameters
    ----------
    v, m : numpy.ndarray
        Float arrays of length N: velocities before the impact and masses (> 0).
    e : float
        Coefficient of restitution in [0, 1].
    joined : numpy.ndarray
        Bool array of length N - 1: which neighbours touch.
    out : numpy.ndarray
        Float array of length N, written with the velocities after the impact.
    work : numpy.ndarray
        Float scratch array of shape (IMPACT_WORK_ROWS, N).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.model.parts import IMPACT_WORK_ROWS, impact_velocities
    >>> out = np.empty(3)
    >>> impact_velocities(np.array([1.0, 0.0, 0.0]), np.ones(3), 1.0, np.array([True, True]), out,
    ...                   np.empty((IMPACT_WORK_ROWS, 3)))
    >>> np.round(out, 12).tolist()
    [-0.333333333333, 0.666666666667, 0.666666666667]
    """
    n = v.size
    s, lower = work[CHAIN_WORK_ROWS], work[CHAIN_WORK_ROWS + 1]
    for i in range(n):
        s[i] = 0.0
        lower[i] = e * max(v[i] - v[i + 1], 0.0) if i < n - 1 and joined[i] else 0.0
    chain_minimiser(v, m, s, lower[:max(n - 1, 0)], joined, out, work[:CHAIN_WORK_ROWS])
