"""Planar motion against MuJoCo: a box sliding on a driven plate, run in MuJoCo and measured against the exact
planar solver, with selfalign's Moreau beside it.

Run from the repository top:  .venv/bin/python benchmarks/mujoco_planar.py [--tiny]

MuJoCo is a benchmark-only dependency (the ``bench`` extra of pyproject.toml); nothing of ``selfalign``
imports it.  The scene maps to MuJoCo as (docs/explanation/mujoco-planar.md):

* the table is a plate (a box 20 x 20 wide, mass 1e6) on two slide joints, x and y; before every step its
  joint positions and velocities are set to Y(t) and Y'(t) of the planar profile, so its motion is the
  table's exactly at each step's start;
* the part is a free box (half size 0.01) resting on it, friction coefficient 1 (MuJoCo takes the larger of
  the two geoms' coefficients; both are 1), gravity (0, 0, -1): mu g = 1, the paper's dimensionless units
  (Sect. 3.2), so the positions and times are the dimensionless ones;
* the part's position relative to the table is the box's x, y minus the plate's joint positions.

Scenes (PERIODS periods):

* ``drift``: the Fig. 18 profile ``ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)`` along x and y, the y motion a
  quarter period behind: the part walks;
* ``stick``: ``ThreePhaseProfile(1.05, 0.05, 0.9, 0.8)`` along x, rotated by 0.6 rad: |Y''| <= 0.9 < mu
  everywhere, the exact part sticks for good (displacement 0); MuJoCo's soft contact lets it creep.

Measured: the error of the drift velocity (the mean velocity over the last period) and of the end position
against the exact solver, the creep per period of the stick scene, and the CPU time (``time.process_time``)
of each run, at MuJoCo's default settings (timestep 0.002, pyramidal cone, impratio 1, no noslip) and at
tightened settings (timestep 2e-4, elliptic cone, impratio 10, solref time constant 2 timesteps, solimp
0.99 ... 0.999, 10 noslip iterations), next to selfalign's Moreau at the same step and the exact solver.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import selfalign as sa
from selfalign.model.planar import PlanarProfile

REPO = Path(__file__).resolve().parent.parent
PERIODS = 10
FIG18 = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
#: name -> planar profile of the scene (module docstring); the part starts at rest at the origin.
PROFILES = {"drift": PlanarProfile(FIG18, FIG18, offset=0.25),
            "stick": PlanarProfile(sa.ThreePhaseProfile(1.05, 0.05, 0.9, 0.8), angle=0.6)}
#: MuJoCo's settings: name -> (timestep, <option> attributes, solref time constant in timesteps or None).
SETTINGS = {"default": (0.002, {}, None),
            "tightened": (2e-4, {"cone": "elliptic", "impratio": "10", "noslip_iterations": "10"}, 2.0)}
HALF = 0.01

XML = """<mujoco>
  <option timestep="{timestep}" gravity="0 0 -1" {options}/>
  <worldbody>
    <body name="plate">
      <joint name="px" type="slide" axis="1 0 0"/>
      <joint name="py" type="slide" axis="0 1 0"/>
      <geom type="box" size="10 10 0.1" pos="0 0 -0.1" mass="1e6" friction="1 0.005 0.0001" {contact}/>
    </body>
    <body name="part" pos="0 0 {half}">
      <freejoint/>
      <geom type="box" size="{half} {half} {half}" mass="1" friction="1 0.005 0.0001" {contact}/>
    </body>
  </worldbody>
</mujoco>"""


def mujoco_missing() -> str | None:
    """Why MuJoCo cannot be run here (a sentence), or None."""
    try:
        import mujoco  # noqa: F401
    except ImportError as exc:
        return f"mujoco cannot be imported ({exc}); install the bench extra"
    return None


def model(setting: str):
    """The MuJoCo model of the plate and the part at ``setting`` (:data:`SETTINGS`)."""
    import mujoco

    timestep, options, tc = SETTINGS[setting]
    contact = "" if tc is None else f'solref="{tc * timestep} 1" solimp="0.99 0.999 0.001 0.5 2"'
    xml = XML.format(timestep=timestep, options=" ".join(f'{k}="{v}"' for k, v in options.items()),
                     contact=contact, half=HALF)
    return mujoco.MjModel.from_xml_string(xml)


def run_mujoco(profile, setting: str, periods: int) -> dict:
    """The part on the plate driven by ``profile`` for ``periods`` periods: its relative position at each
    period end and the CPU time of the run."""
    import mujoco

    m = model(setting)
    d = mujoco.MjData(m)
    per_period = round(profile.dt / m.opt.timestep)
    h = profile.dt / per_period
    m.opt.timestep = h
    d.qpos[:2], d.qvel[:2] = profile.position(0.0), profile.velocity(0.0)
    d.qpos[2:4], d.qvel[2:4] = d.qpos[:2], d.qvel[:2]
    mujoco.mj_forward(m, d)
    ends = [np.zeros(2)]
    start = time.process_time()
    for period in range(periods):
        for k in range(per_period):
            t = (period * per_period + k) * h
            d.qpos[:2], d.qvel[:2] = profile.position(t), profile.velocity(t)
            mujoco.mj_step(m, d)
        t = (period + 1) * per_period * h
        ends.append(d.qpos[2:4] - profile.position(t))
    return {"ends": np.array(ends), "cpu": time.process_time() - start, "h": h, "steps_per_period": per_period}


def ours(profile, periods: int, steps_per_period: int) -> dict:
    """selfalign's exact solver and Moreau at ``steps_per_period`` on the same scene: relative positions at
    the period ends and CPU times."""
    out = {}
    for method, options in (("exact", {}), ("moreau", {"steps_per_period": steps_per_period})):
        scene = sa.Scene(profile, periods=periods, record=sa.Record(series=("x",), samples_per_period=2))
        start = time.process_time()
        traj = sa.simulate(scene, method=method, **options)
        out[method] = {"ends": np.asarray(traj.x)[::2], "cpu": time.process_time() - start}
    return out


def work_precision(tiny: bool = False) -> dict:
    """The table of the module docstring: per scene and MuJoCo setting, the drift-velocity error, the
    end-position error, the creep per period (the stick scene) and the CPU times of MuJoCo, Moreau at the
    same step and the exact solver, with their ratios; ``{"skipped": reason}`` without MuJoCo."""
    missing = mujoco_missing()
    if missing:
        return {"skipped": missing}
    import mujoco

    periods = 2 if tiny else PERIODS
    sa.simulate(sa.Scene(PROFILES["drift"], periods=1), method="moreau")          # compiles
    rows = []
    for name, profile in PROFILES.items():
        for setting in SETTINGS:
            got = run_mujoco(profile, setting, periods)
            ref = ours(profile, periods, got["steps_per_period"])
            exact, moreau = ref["exact"]["ends"], ref["moreau"]["ends"]
            row = {"scene": name, "setting": setting, "h": got["h"], "periods": periods}
            for label, ends, cpu in (("mujoco", got["ends"], got["cpu"]), ("moreau", moreau, ref["moreau"]["cpu"])):
                drift = (ends[-1] - ends[-2]) / profile.dt
                drift_exact = (exact[-1] - exact[-2]) / profile.dt
                row[label] = {"end_error": float(np.linalg.norm(ends[-1] - exact[-1])),
                              "drift_error": float(np.linalg.norm(drift - drift_exact)),
                              "creep_per_period": float(np.linalg.norm(ends[-1] - ends[0])) / periods,
                              "cpu": cpu}
            row["exact"] = {"cpu": ref["exact"]["cpu"], "end": exact[-1].tolist()}
            row["cpu_ratio_mujoco_to_moreau"] = row["mujoco"]["cpu"] / max(row["moreau"]["cpu"], 1e-9)
            row["cpu_ratio_mujoco_to_exact"] = row["mujoco"]["cpu"] / max(row["exact"]["cpu"], 1e-9)
            rows.append(row)
    return {"mujoco_version": mujoco.__version__, "periods": periods, "rows": rows}


def format_table(report: dict) -> str:
    """The report as one Markdown table."""
    if "skipped" in report:
        return f"skipped: {report['skipped']}"
    lines = [f"MuJoCo {report['mujoco_version']}, {report['periods']} periods", "",
             "| scene | setting | h | MuJoCo end error | drift error | creep/period | CPU s | Moreau end error "
             "| Moreau CPU s | exact CPU s |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in report["rows"]:
        mj, mo = r["mujoco"], r["moreau"]
        lines.append(f"| {r['scene']} | {r['setting']} | {r['h']:.2e} | {mj['end_error']:.2e} "
                     f"| {mj['drift_error']:.2e} | {mj['creep_per_period']:.2e} | {mj['cpu']:.3f} "
                     f"| {mo['end_error']:.2e} | {mo['cpu']:.4f} "
                     f"| {r['exact']['cpu']:.4f} |")
    return "\n".join(lines)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tiny", action="store_true", help="2 periods")
    parser.add_argument("--json", type=Path, default=REPO / "results" / "benchmarks" / "mujoco_planar.json")
    args = parser.parse_args(argv)
    report = work_precision(args.tiny)
    print(format_table(report))
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(report, indent=2))
    return report


if __name__ == "__main__":
    main()
