"""A minimal compiled event loop: the measuring stick of the engine's speed.

It restates, on purpose, the closed-form arcs of :mod:`selfalign.model.arcs` (quadratic
on a uniform surface; harmonic for forward and hyperbolic for backward slip in the
transition zone) and the stick/slip rule of :mod:`selfalign.model.friction`, in the
fewest lines that integrate one piecewise-constant profile period after period: no zone
crossings (a zone run must stay inside the zone), no outcome decisions, no recording,
no fast-forward.  It is not part of the package and nothing imports it but the
benchmarks, which run it on the same scenes as the engine, in the same process, and
check that the end states agree bit for bit.  Events are counted as the engine counts
them: every profile break passed, and every change of mode (slip start, stick, reversal).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(error_model="numpy")
def run(breaks, accels, w, c_mu, xi, v, periods):
    """(xi, v, events) after ``periods`` periods from (xi, v) at t = 0; c_mu > 1: in the zone."""
    zone = c_mu > 1.0
    om = math.sqrt((c_mu - 1.0) / w) if zone else 0.0
    mu = 1.0 + (c_mu - 1.0) * (xi / w) if zone else 1.0
    a = accels[0]
    mode = (1 if v > 0.0 else -1) if v != 0.0 else (-1 if a > mu else (1 if a < -mu else 0))
    events = 0
    for n in range(periods):
        for p in range(accels.shape[0]):
            a = accels[p]
            if n > 0 or p > 0:                          # a profile break
                events += 1
                if v * mode < 0.0:
                    v = 0.0
                if mode == 0 or v == 0.0:
                    mu = 1.0 + (c_mu - 1.0) * (xi / w) if zone else 1.0
                    new = -1 if a > mu else (1 if a < -mu else 0)
                    events += new != mode
                    mode = new
                    v = 0.0
            seg = breaks[p + 1] - breaks[p]
            s0 = 0.0
            while mode != 0:
                if v * mode < 0.0:
                    v = 0.0
                mu = 1.0 + (c_mu - 1.0) * (xi / w) if zone else 1.0
                acc0 = -a - mode * mu
                rem = seg - s0
                if not zone:                            # quadratic arc
                    s_v = -v / acc0 if acc0 * mode < 0.0 else math.inf
                    s = min(s_v, rem)
                    c, s1, s2 = 1.0, s, 0.5 * s * s
                elif mode > 0:                          # harmonic arc
                    s_v = math.atan2(v * om + 0.0, -acc0) / om
                    s = min(s_v, rem)
                    h = math.sin(0.5 * om * s)
                    c, s1, s2 = 1.0 - 2.0 * h * h, 2.0 * h * math.cos(0.5 * om * s) / om, 2.0 * (h / om) * (h / om)
                else:                                   # hyperbolic arc
                    den = acc0 + v * om
                    s_v = math.log1p(-2.0 * v * om / den) / (2.0 * om) if acc0 > 0.0 and den > 0.0 else math.inf
                    s = min(s_v, rem)
                    h = math.sinh(0.5 * om * s)
                    c, s1, s2 = 1.0 + 2.0 * h * h, 2.0 * h * math.cosh(0.5 * om * s) / om, 2.0 * (h / om) * (h / om)
                xi += v * s1 + acc0 * s2
                if s_v > rem:                           # the piece ends first
                    v = v * c + acc0 * s1
                    break
                s0 += s                                 # v = 0: stick or reverse
                events += 1
                v = 0.0
                mu = 1.0 + (c_mu - 1.0) * (xi / w) if zone else 1.0
                mode = -1 if a > mu else (1 if a < -mu else 0)
    return xi, v, events


def run_batch(breaks, accels, w, c_mu, xi, v, periods):
    """:func:`run` for every row of ``breaks``, ``accels`` (one member each); arrays of (xi, v, events)."""
    return _batch(np.ascontiguousarray(breaks), np.ascontiguousarray(accels), w, c_mu, np.asarray(xi, float),
                  np.asarray(v, float), periods)


@njit(error_model="numpy")
def _batch(breaks, accels, w, c_mu, xi, v, periods):
    n = breaks.shape[0]
    out_xi, out_v, out_events = np.empty(n), np.empty(n), np.empty(n, dtype=np.int64)
    for i in range(n):
        out_xi[i], out_v[i], out_events[i] = run(breaks[i], accels[i], w, c_mu, xi[i], v[i], periods)
    return out_xi, out_v, out_events
