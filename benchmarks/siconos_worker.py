"""The model of several parts on one table (docs/explanation/several-parts.md) in Siconos, run by
benchmarks/siconos_parts.py in a process of its own.

Run:  /usr/bin/python3 benchmarks/siconos_worker.py < job.json > answer.json

It runs under the interpreter that has Siconos (Debian's ``python3-siconos`` installs it for
/usr/bin/python3, built against that interpreter's numpy 1.x), not in the project's environment: it
imports only the standard library, numpy and ``siconos``, never ``selfalign``.  The job (JSON on stdin)
is ``{"runs": [run, ...]}`` with, per run,

    profile          {"breaks": [...], "accels": [...], "dt": ...}: piecewise-constant y'' over one period
    parts            [{"x0", "v0", "width", "mass", "friction_factor"}, ...], rear-most first
                     (a friction factor of 0: no friction interaction, a free part)
    surface          null (uniform) or {"x_mu", "c_mu"}: the stop zone of eqs. 7-9 over each part's width
    restitution      Newton's e of the contacts between neighbours
    periods, steps_per_period, theta
    activation_threshold   optional, default 0: MoreauJeanOSI's threshold of the contact test y + h/2 y' <= threshold

and the answer (JSON on stdout) is ``{"version": ..., "runs": [{"x_end", "v_end", "cpu", "steps",
"gs_iterations", "residual"}, ...]}``; ``cpu`` is the process time of the model's construction and of the
time loop (the interpreter's start and the imports excluded).

The Siconos model, part by part:

* part i is a ``LagrangianLinearTIDS`` with q = (x_i), mass matrix (m_i), and the table's inertial force
  -m_i y'' as its external force, set before every step to -m_i (y'(t_k + h) - y'(t_k)) / h, the mean of
  y'' over the step (exact for the piecewise-constant y'': the same table impulse as
  ``selfalign.solvers.parts_moreau``);
* its friction with the table is a ``RelayNSL`` on the interaction y = x_i (a ``LagrangianLinearTIR``,
  C = (1)): at the velocity level the step's friction impulse lies in [-h m_i k_i mu_bar_i, h m_i k_i
  mu_bar_i] and opposes the end-of-step velocity, the paper's eq. 2 in the table frame; on a stop zone
  the bounds are set before every step from mu_bar at the midpoint x_i + h/2 v_i (and the one-step
  problem is built again: Siconos reads the bounds of a relay only when it builds the problem);
* the contact of parts i and i + 1 is a ``NewtonImpactNSL(e)`` on the gap y = x_{i+1} - x_i - w_{i+1}
  (C = (-1, 1), constant term -w_{i+1});
* Moreau-Jean time-stepping (``MoreauJeanOSI(theta)``, ``TimeStepping``), the one-step problem a
  ``GenericMechanical`` problem (Siconos' problem for interactions of mixed laws: here relay blocks
  and complementarity blocks), solved by Gauss-Seidel over the blocks, each block by Lemke's method.

The friction relation carries the constant term -1e6: Siconos 4.4.0 adds a relay interaction to the
active set without a test, but removes it again by the position test of a unilateral contact
(y + h/2 y' > 0), so that with y = x_i > 0 the friction would act only every other step.  The constant
keeps y negative for any position the runs reach; it changes nothing else (the velocity y' = x_i' is
what the relay constrains).
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np
import siconos
import siconos.kernel as sk
import siconos.numerics as sn

#: Gauss-Seidel tolerance and iteration limit of the one-step problem.
TOLERANCE = 1e-14
MAX_ITERATIONS = 10_000
#: Constant term of the friction relation: y = x_i - OFFSET stays negative (module docstring).
OFFSET = 1e6


def table_impulses(breaks, accels, dt, n):
    """y'(t_k + h) - y'(t_k) for the n steps of one period (h = dt / n), exact for piecewise-constant y''."""
    breaks = np.asarray(breaks, dtype=float)
    accels = np.asarray(accels, dtype=float)
    t = np.arange(n + 1) * (dt / n)
    start = np.concatenate([[0.0], np.cumsum(np.diff(breaks) * accels)])   # y' - y'(0) at each break
    piece = np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, accels.size - 1)
    return np.diff(start[piece] + accels[piece] * (t - breaks[piece]))


def mu_bar(xi, w, c_mu):
    """Eqs. 7-9: 1 before the zone, c_mu on it, linear over the part's width w in between."""
    return 1.0 if xi <= 0.0 else c_mu if xi >= w else 1.0 + (c_mu - 1.0) * (xi / w)


def run(job):
    """One run of the job (module docstring); returns its answer."""
    start = time.process_time()
    profile, parts = job["profile"], job["parts"]
    dt, n, periods = float(profile["dt"]), int(job["steps_per_period"]), int(job["periods"])
    h = dt / n
    surface = job.get("surface")
    nsds = sk.NonSmoothDynamicalSystem(0.0, periods * dt)
    systems, relays = [], []
    for p in parts:
        ds = sk.LagrangianLinearTIDS([float(p["x0"])], [float(p["v0"])], np.array([[float(p["mass"])]]))
        nsds.insertDynamicalSystem(ds)
        systems.append(ds)
        bound = h * p["mass"] * p["friction_factor"]
        if bound > 0.0:
            law = sk.RelayNSL(1, -bound, bound)
            relation = sk.LagrangianLinearTIR(np.array([[1.0]]), np.array([-OFFSET]))
            nsds.link(sk.Interaction(law, relation), ds)
            relays.append((law, ds, p))
    for i in range(len(parts) - 1):
        relation = sk.LagrangianLinearTIR(np.array([[-1.0, 1.0]]), np.array([-float(parts[i + 1]["width"])]))
        nsds.link(sk.Interaction(sk.NewtonImpactNSL(float(job["restitution"])), relation),
                  systems[i], systems[i + 1])
    problem = sk.GenericMechanical(sn.SICONOS_GENERIC_MECHANICAL_NSGS)
    options = problem.numericsSolverOptions()
    options.dparam[sn.SICONOS_DPARAM_TOL] = TOLERANCE
    options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = MAX_ITERATIONS
    integrator = sk.MoreauJeanOSI(float(job["theta"]))
    integrator.setConstraintActivationThreshold(float(job.get("activation_threshold", 0.0)))
    simulation = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), integrator, problem)
    force = -table_impulses(profile["breaks"], profile["accels"], dt, n) / h
    masses = [float(p["mass"]) for p in parts]
    iterations, residual = 0, 0.0
    for k in range(periods * n):
        a = force[k % n]
        for ds, m in zip(systems, masses):
            ds.setFExtPtr(np.array([m * a]))
        if surface is not None:
            for law, ds, p in relays:
                x_mid = ds.q()[0] + 0.5 * h * ds.velocity()[0]
                bound = h * p["mass"] * p["friction_factor"] * mu_bar(x_mid - surface["x_mu"], p["width"],
                                                                      surface["c_mu"])
                law.setLb(-bound)
                law.setUb(bound)
            problem.setHasBeenUpdated(False)      # the relay bounds are read when the problem is built
        simulation.computeOneStep()
        iterations = max(iterations, int(options.iparam[sn.SICONOS_IPARAM_ITER_DONE]))
        residual = max(residual, float(options.dparam[sn.SICONOS_DPARAM_RESIDU]))
        simulation.nextStep()
    cpu = time.process_time() - start
    return {"x_end": [float(ds.q()[0]) for ds in systems], "v_end": [float(ds.velocity()[0]) for ds in systems],
            "cpu": cpu, "steps": periods * n, "gs_iterations": iterations, "residual": residual}


def main():
    jobs = json.load(sys.stdin)
    answer = {"version": str(getattr(siconos, "version", "")), "runs": [run(job) for job in jobs["runs"]]}
    json.dump(answer, sys.stdout)


if __name__ == "__main__":
    main()
