"""End states of a few thousand random scenes, saved before a kernel change and compared after it.

Run:  python benchmarks/bit_identity.py save FILE.npz     (before changing the kernel)
      python benchmarks/bit_identity.py check FILE.npz    (after each change: bit for bit)

A performance change of the kernel must not move a single bit of a result.  The scenes
cover every path of the compiled driver: three-phase profiles on uniform surfaces and
stop zones (random zone, start state and phase), general piecewise-constant and
polynomial profiles, Fourier profiles (exact, uniform surface) and Moreau runs; every
``until`` mode of the batch (periods with and without fast-forward, rest, stick, cycle)
with level crossings and a small event budget; scalar runs with and without recording (event log, arcs, dense
series); and the Fig. 17 entry runs of a small positioning grid.  Every field of every
result record is compared by its bytes (NaN payloads included); a field that exists on
one side only (a working field added or removed) is reported and skipped.
"""

from __future__ import annotations

import sys

import numpy as np

import selfalign as sa
from selfalign.analysis.positioning import positioning_grid
from selfalign.solvers.driver import simulate_batch

UNTILS = ({"until": "periods", "periods": 25}, {"until": "periods", "periods": 25, "fast_forward": False},
          {"until": "rest", "max_periods": 300}, {"until": "stick", "max_periods": 300},
          {"until": "cycle", "max_periods": 300}, {"until": "rest", "max_periods": 300, "max_events": 57})


def _zone(rng):
    return sa.StopZone(rng.uniform(-0.2, 0.3), np.exp(rng.uniform(np.log(0.005), np.log(0.5))),
                       rng.uniform(1.05, 6.0)) if rng.random() < 0.7 else sa.Uniform()


def _three_phase(rng):
    dt = rng.uniform(0.3, 2.0)
    y2, y3 = np.exp(rng.uniform(np.log(0.3), np.log(8.0), 2))
    dy = dt * dt / (8 * (1 / y2 + 1 / y3)) * rng.uniform(0.05, 0.999)
    return sa.ThreePhaseProfile(dt, dy, y2, y3)


def _piecewise(rng):
    """A random zero-mean piecewise-constant profile of 2-6 pieces."""
    m = int(rng.integers(2, 7))
    lengths = rng.uniform(0.05, 1.0, m)
    accels = rng.uniform(-4.0, 4.0, m)
    accels[-1] = -np.sum(accels[:-1] * lengths[:-1]) / lengths[-1]
    if not abs(accels[-1]) < 8.0:
        accels[-1] = 0.0
        accels[:-1] -= np.sum(accels[:-1] * lengths[:-1]) / np.sum(lengths[:-1])
    breaks = np.concatenate([[0.0], np.cumsum(lengths)])
    return sa.PiecewiseConstantProfile(breaks, accels, 0.0, 0.0)


def _start(rng):
    return (rng.uniform(-0.3, 0.1), rng.uniform(-0.5, 0.5) if rng.random() < 0.5 else 0.0,
            rng.uniform(0.0, 1.0) if rng.random() < 0.5 else 0.0)


def _scenes(rng, count, make_profile, zones=True):
    out = []
    while len(out) < count:
        try:
            profile = make_profile(rng)
        except ValueError:
            continue
        out.append((profile, _zone(rng) if zones else sa.Uniform(), *_start(rng)))
    return out


def _batch(scenes, **kw):
    profiles, zones, x0, v0, phase = zip(*scenes)
    uniform = [isinstance(z, sa.Uniform) for z in zones]
    rng = np.random.default_rng(len(scenes))
    return simulate_batch(list(profiles), np.array(x0), np.array(v0), np.array(phase),
                          x_mu=[x if u else z.x_mu for x, z, u in zip(x0, zones, uniform)],
                          w=[1.0 if u else z.w for z, u in zip(zones, uniform)],
                          c_mu=[1.0 if u else z.c_mu for z, u in zip(zones, uniform)],
                          levels=rng.uniform(-0.2, 0.6, (len(scenes), 2)), **kw)


def _put(out, name, arr):
    """Store a structured array field by field (``name/field``), a plain one as it is."""
    arr = np.asarray(arr)
    if arr.dtype.names:
        for field in arr.dtype.names:
            out[f"{name}/{field}"] = np.ascontiguousarray(arr[field])
    else:
        out[name] = arr


def _trajectory(out, name, traj):
    _put(out, f"{name}/end", np.array([traj.x_end, traj.v_end, traj.tau_end]))
    _put(out, f"{name}/ints", np.array([traj.period_end, int(traj.reason), traj.stats["events"],
                                        traj.stats["steps"]]))
    for key in ("events", "arcs"):
        if getattr(traj, key) is not None:
            _put(out, f"{name}/{key}", getattr(traj, key))
    for key, series in traj.series.items():
        _put(out, f"{name}/series/{key}", series)


def collect() -> dict:
    """Every result of the scene set, as named arrays."""
    rng = np.random.default_rng(20261121)
    out = {}
    families = {"three_phase": _scenes(rng, 2000, _three_phase), "piecewise": _scenes(rng, 300, _piecewise),
                "polynomial": _scenes(rng, 200, lambda r: sa.PolynomialProfile(
                    r.uniform(0.5, 2.0), r.uniform(0.01, 0.1), r.uniform(0.55, 0.95)))}
    for fam, scenes in families.items():
        for j, kw in enumerate(UNTILS):
            res = _batch(scenes, **kw)
            _put(out, f"{fam}/batch{j}/records", res.records)
            _put(out, f"{fam}/batch{j}/crossings", res.crossings)
        for i, (p, zone, x0, v0, phase) in enumerate(scenes[:300]):
            horizon = {"periods": 25} if i % 2 else {"until": "rest", "max_periods": 300}
            record = (sa.Record(events=True, arcs=True) if i % 3 == 0 else
                      sa.Record(series=("x", "v", "mode"), samples_per_period=16) if i % 3 == 1 else sa.Record())
            scene = sa.Scene(p, zone, x0=x0, v0=v0, phase=phase, record=record, **horizon)
            _trajectory(out, f"{fam}/scalar{i}", sa.simulate(scene))
    fourier = []
    while len(fourier) < 60:
        k = int(rng.integers(1, 4))
        fourier.append((sa.FourierProfile(rng.uniform(0.5, 2.0), rng.uniform(-0.05, 0.05, k),
                                          rng.uniform(-0.05, 0.05, k)), sa.Uniform(), *_start(rng)))
    for j, kw in enumerate(UNTILS[:3]):
        res = _batch(fourier, **{**kw, **({"max_periods": 40} if "max_periods" in kw else {"periods": 10})})
        _put(out, f"fourier/batch{j}/records", res.records)
    for i, (p, zone, x0, v0, phase) in enumerate(fourier[:20]):
        scene = sa.Scene(p, zone, x0=x0, v0=v0, phase=phase, periods=5,
                         record=sa.Record(events=True, arcs=True) if i % 2 else sa.Record())
        _trajectory(out, f"fourier/scalar{i}", sa.simulate(scene))
    moreau = families["three_phase"][:40]
    for j, kw in enumerate((UNTILS[0], UNTILS[2])):
        res = _batch([(p, z, x0, v0, 0.0) for p, z, x0, v0, _ in moreau], method="moreau", h=0.01,
                     **{**kw, **({"max_periods": 60} if "max_periods" in kw else {})})
        _put(out, f"moreau/batch{j}/records", res.records)
    for i, (p, zone, x0, v0, phase) in enumerate(moreau[:10]):
        scene = sa.Scene(p, zone, x0=x0, v0=v0, phase=phase, periods=5, method="moreau",
                         solver_options={"h": 0.005, "iteration": "fixed_point" if i % 2 else "exact"},
                         record=sa.Record(series=("x", "v")) if i % 3 == 0 else sa.Record())
        _trajectory(out, f"moreau/scalar{i}", sa.simulate(scene))
    y = np.linspace(0.5, 2.5, 9)
    y2, y3 = np.meshgrid(y, y, indexing="ij")
    grid = positioning_grid(1.0, 0.084, y2, y3, w=0.05, c_mu=2.5, n_entries=16, levels=(0.99, 0.999))
    for key, value in vars(grid).items():
        if isinstance(value, np.ndarray):
            _put(out, f"fig17/{key}", value)
    return out


def _bytes(a: np.ndarray) -> bytes:
    return np.ascontiguousarray(a).view(np.uint8).tobytes()


def compare(saved: dict, now: dict) -> list[str]:
    """The names whose values differ (or exist on one side only, reported apart)."""
    bad = [name for name in saved if name in now and (saved[name].shape != now[name].shape
                                                      or _bytes(saved[name]) != _bytes(now[name]))]
    only = sorted(set(saved) ^ set(now))
    if only:
        print(f"{len(only)} fields exist on one side only (not compared), e.g. {only[:5]}")
    return bad


def main(argv) -> int:
    if len(argv) != 2 or argv[0] not in ("save", "check"):
        print(__doc__)
        return 2
    now = collect()
    if argv[0] == "save":
        np.savez_compressed(argv[1], **now)
        print(f"saved {len(now)} arrays to {argv[1]}")
        return 0
    with np.load(argv[1]) as f:
        saved = {name: f[name] for name in f.files}
    bad = compare(saved, now)
    print(f"compared {len(set(saved) & set(now))} arrays: {len(bad)} differ" + (f", e.g. {bad[:10]}" if bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
