"""The BLAS-free SQP of selfalign.analysis.sqp: right answers on problems with a
known solution, feasible iterates, and the same bits of the Fig. 6 optimiser under every
BLAS kernel and thread count."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from selfalign.analysis.sqp import cholesky_solve, dot, householder_qr, matmul, minimise, solve_qp


def test_linear_algebra_matches_numpy():
    """The written-out products and factorisations agree with numpy's (BLAS/LAPACK) to rounding."""
    rng = np.random.default_rng(3)
    a, b, x = rng.normal(size=(7, 5)), rng.normal(size=(5, 4)), rng.normal(size=5)
    np.testing.assert_allclose(dot(a, x), a @ x, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(matmul(a, b), a @ b, rtol=1e-13, atol=1e-14)
    q, r = householder_qr(a)
    np.testing.assert_allclose(matmul(q, r), a, atol=1e-13)
    np.testing.assert_allclose(matmul(q.T, q), np.eye(7), atol=1e-13)
    np.testing.assert_allclose(np.tril(r, -1), 0.0, atol=1e-13)
    spd = matmul(a.T, a) + np.eye(5)
    np.testing.assert_allclose(cholesky_solve(spd, x), np.linalg.solve(spd, x), rtol=1e-12)
    with pytest.raises(ValueError, match="not positive definite"):
        cholesky_solve(-spd, x)


def test_qp_active_constraint():
    """min (x - 2)^2 + (y - 1)^2 with x + y <= 1 and -x <= 0: the projection (1, 0) of (2, 1)."""
    A = np.array([[1.0, 1.0], [-1.0, 0.0]]) / np.array([[math.sqrt(2.0)], [1.0]])
    r = np.array([1.0 / math.sqrt(2.0), 0.0])
    d, work = solve_qp(2.0 * np.eye(2), np.array([-4.0, -2.0]), A, r)
    np.testing.assert_allclose(d, [1.0, 0.0], atol=1e-14)
    assert work.tolist() == [0]


def test_qp_interior_minimum():
    """An inactive constraint leaves the unconstrained minimum -B^-1 g."""
    d, work = solve_qp(np.diag([2.0, 4.0]), np.array([-2.0, 4.0]), np.array([[1.0, 0.0]]), np.array([5.0]))
    np.testing.assert_allclose(d, [1.0, -1.0], atol=1e-14)
    assert work.size == 0


def test_minimise_reaches_the_constrained_optimum():
    """Rosenbrock's function under x + y <= 1.5 (optimum on the boundary, found by dense
    search to 1e-6) from the feasible (-1, 1): within 1e-4, every accepted point feasible."""
    points = []

    def fun(z):
        points.append(z.copy())
        return (1 - z[0]) ** 2 + 100 * (z[1] - z[0] ** 2) ** 2

    def grad(z):
        return np.array([-2 * (1 - z[0]) - 400 * z[0] * (z[1] - z[0] ** 2), 200 * (z[1] - z[0] ** 2)])

    res = minimise(fun, grad, np.array([-1.0, 1.0]), np.array([[1.0, 1.0]]), np.array([1.5]),
                   first_step=0.1, min_step=1e-12, max_iter=400)
    xs = np.linspace(0.8, 1.0, 200_001)
    best = xs[np.argmin((1 - xs) ** 2 + 100 * (1.5 - xs - xs**2) ** 2)]
    assert res.converged, res.message
    np.testing.assert_allclose(res.x, [best, 1.5 - best], atol=1e-4)
    assert max(p[0] + p[1] for p in points) <= 1.5 + 1e-12
    assert np.all(np.diff(res.history) <= 0.0)


def test_minimise_refuses_infeasible_start_and_bad_options():
    """An infeasible x0 or a non-positive trust is a clear error before any evaluation."""
    with pytest.raises(ValueError, match="violates the constraints"):
        minimise(lambda z: 0.0, lambda z: z, np.array([2.0]), np.array([[1.0]]), np.array([1.0]),
                 first_step=1.0, min_step=1e-6, max_iter=3)
    with pytest.raises(ValueError, match="first_step must be finite and > 0"):
        minimise(lambda z: 0.0, lambda z: z, np.array([0.0]), np.array([[1.0]]), np.array([1.0]),
                 first_step=0.0, min_step=1e-6, max_iter=3)


RUN = """
import json, sys
from selfalign.analysis.fourier_design import optimise_fourier
opt = optimise_fourier(0.072, 0.021, 3.2, 1275.0, order=12, max_iter=8)
print(json.dumps([float(v).hex() for v in [opt.f, *opt.profile.cos_coeffs, *opt.profile.sin_coeffs]]))
"""


@pytest.mark.blas
def test_fourier_optimum_is_the_same_bits_under_every_blas_kernel():
    """The Fig. 6 optimiser (its first 8 iterations) ends at the same bits with the
    machine's own OpenBLAS kernel and with Prescott, single- and double-threaded.  The SciPy
    SLSQP version it replaces did not: f = 0x1.213b1029bd06dp-11 (AVX-512 kernel) against
    0x1.213b2a09c45a1p-11 (Prescott) after the same 8 iterations."""
    outputs = {}
    for core, threads in ((None, "1"), (None, "2"), ("Prescott", "1"), ("Prescott", "2")):
        env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
        env["OPENBLAS_NUM_THREADS"] = threads
        if core:
            env["OPENBLAS_CORETYPE"] = core
        out = subprocess.run([sys.executable, "-c", RUN], env=env, capture_output=True, text=True, check=True)
        outputs[(core, threads)] = json.loads(out.stdout.strip().splitlines()[-1])
    first = next(iter(outputs.values()))
    assert all(v == first for v in outputs.values()), outputs


def test_a_model_that_loses_positive_definiteness_restarts():
    """Hypothesis (module docstring of selfalign.analysis.sqp): the damped BFGS matrix can lose positive
    definiteness to rounding on the working constraints' null space (the Fourier optimisation of Fig. 6's
    period and stroke at |y''| <= 100, order 4, reached a Cholesky pivot of -2.6e-11 and raised); the
    SQP then restarts its model from the scaled identity instead of failing, every iterate stays
    feasible, and the optimum improves on its start."""
    from selfalign.analysis.fourier_design import optimise_fourier

    opt = optimise_fourier(0.072, 0.021, 3.2, 100.0, order=4, max_iter=130, progress="quiet")
    assert opt.restarts >= 1
    assert opt.vbar > 0.0 and opt.history_f[-1] < opt.history_f[0]
    s = opt.settings
    assert s["stroke"] <= 0.021 * (1 + 1e-9) and s["peak_velocity"] <= 3.2 * (1 + 1e-3)
    assert s["peak_acceleration"] <= 100.0 * (1 + 1e-3)
