"""Dense output: the recorded arcs of the exact solver evaluated on the sample grid, and the
model's mode at given states.
"""

from __future__ import annotations

import math

import numpy as np

from ...model import arcs as A
from ...model import friction as F
from .. import records as R
from .codes import ARC_SMOOTH, ARC_STICK
from .compiled import jit
from .piecewise import piece_at
from .recording import normalised_time
from .smooth import table_motion


@jit
def sample_arcs(arcs, row, tau0, spp):
    """Samples on the grid t = tau0 + j dt / spp plus every arc start (the state after each
    event): each arc with a positive duration contributes its start and the grid points
    strictly inside it; the last arc (the end state) contributes its start only.
    Returns (period, tau, x, v, mode) with tau measured from the arc's period start."""
    dt = row[R.DT]
    h = dt / spp
    na = arcs.shape[0]
    total = 0
    for pass_ in range(2):
        if pass_ == 1:
            period = np.empty(total, dtype=np.int64)
            tau = np.empty(total)
            x = np.empty(total)
            v = np.empty(total)
            mode = np.empty(total, dtype=np.int8)
        k = 0
        for i in range(na):
            arc = arcs[i]
            last = i == na - 1
            if arc.duration <= 0.0 and not last:
                continue
            off = arc.tau - tau0
            base = arc.period
            if off < 0.0:
                off += dt
                base -= 1
            j_lo = int(math.floor(off / h)) + 1
            j_hi = min(int(math.ceil((off + arc.duration) / h)) - 1, spp - 1)
            count = 1 if last else 1 + max(0, j_hi - j_lo + 1)
            if pass_ == 0:
                total += count
                continue
            for r in range(count):
                if r == 0:
                    sr = 0.0
                    pn, pt = arc.period, arc.tau
                else:
                    j = j_lo + r - 1
                    sr = min(max(j * h - off, 0.0), arc.duration)
                    pn, pt = normalised_time(base, tau0 + j * h, dt)
                if arc.kind == ARC_SMOOTH:
                    sig = float(arc.mode)
                    y0, yd0, _ = table_motion(row, arc.tau)
                    y1, yd1, _ = table_motion(row, arc.tau + sr)
                    dx, vv = A.smooth_step(sig, arc.v, sr, y0, yd0, y1, yd1)
                elif arc.kind != ARC_STICK and R.data_size(row) < 0:      # a slip of period_jerk_zone
                    m = -R.data_size(row)
                    jerk = row[R.col_jerk(m, piece_at(row, arc.tau))]
                    dx, vv, _ = A.jerk_step(arc.kind, arc.omega, arc.v, arc.acc, -jerk, sr)
                else:
                    dx, vv = A.step(arc.kind, arc.omega, arc.v, arc.acc, sr)
                period[k] = pn
                tau[k] = pt
                x[k] = arc.x + dx
                v[k] = vv
                mode[k] = arc.mode
                k += 1
    return period, tau, x, v, mode


@jit
def modes(v, ydd, mu):
    """The model's mode at states (v, y'', mu_bar): the sign of v, at v = 0 :func:`decide_mode`."""
    out = np.empty(v.shape[0], dtype=np.int8)
    for i in range(v.shape[0]):
        out[i] = 1 if v[i] > 0.0 else (-1 if v[i] < 0.0 else F.decide_mode(ydd[i], mu[i]))
    return out
