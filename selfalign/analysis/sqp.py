"""A small SQP method for linear inequality constraints whose arithmetic does not go through BLAS.

Why not SciPy's SLSQP: it forms its products and factorisations with BLAS and LAPACK,
whose kernels (``OPENBLAS_CORETYPE``, the thread count) add in different orders, so its
iterates differ in the last bits from one kernel to another.  An optimiser path is
sensitive to that (the Fig. 6 objective is not smooth where a slip grazes x' = 0): on
one machine SLSQP ended at f = 2.33e-4 with its own kernel and 2.82e-4 with another.
Here every product is an elementwise numpy multiplication followed by a reduction along
one axis (numpy's summation, in an order fixed by numpy, not by the CPU), and the only
factorisations (Householder QR, Cholesky) are written out below, so the iterates are the
same bits whatever the BLAS kernel and thread count.

:func:`solve_qp` minimises g.d + d.B d / 2 subject to A d <= r with r >= 0 (d = 0 is
feasible) by the primal active-set method (Nocedal & Wright, Numerical Optimization,
Alg. 16.3).  :func:`minimise` is a line-search SQP on top of it, as SLSQP is: at each
iterate the quadratic model with a damped BFGS matrix (Powell's update) is minimised under
the constraints, which are linear and hence exact, and the step along its solution is
halved until the objective decreases enough (Armijo).  Every iterate is feasible, so the
objective itself serves as merit function.  Should the BFGS matrix lose positive definiteness
to rounding on the null space of the working constraints (a Cholesky pivot at or below zero), the
model restarts from the scaled identity of the first iteration (``SQPResult.restarts``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: A step alpha d is taken when the objective falls by at least ARMIJO alpha grad.d.
ARMIJO = 1e-4
#: Halvings of the step before the line search gives up.
LINE_SEARCH = 20


def dot(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """a @ x without BLAS: rows of ``a`` times ``x``, summed along the last axis."""
    return np.add.reduce(a * x, axis=-1)


def matmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a @ b for 2-D arrays without BLAS."""
    return np.add.reduce(a[:, :, None] * b[None, :, :], axis=1)


def householder_qr(m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Q (n, n) orthogonal and R (n, k) upper triangular with m = Q R, by Householder
    reflections (no LAPACK)."""
    n, k = m.shape
    q, r = np.eye(n), np.array(m, dtype=float)
    for j in range(min(k, n - 1)):
        x = r[j:, j]
        norm = math.sqrt(float(dot(x, x)))
        if norm == 0.0:
            continue
        v = x.copy()
        v[0] += math.copysign(norm, x[0])
        v /= math.sqrt(float(dot(v, v)))
        r[j:, j:] -= 2.0 * np.multiply.outer(v, dot(r[j:, j:].T, v))
        q[:, j:] -= 2.0 * np.multiply.outer(dot(q[:, j:], v), v)
    return q, r


def cholesky_solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x with matrix x = rhs for a symmetric positive definite matrix (Cholesky, no LAPACK).
    ValueError if it is not positive definite to working precision."""
    n = matrix.shape[0]
    low = np.zeros((n, n))
    for j in range(n):
        diag = float(matrix[j, j]) - float(dot(low[j, :j], low[j, :j]))
        if not diag > 1e-14 * abs(float(matrix[j, j])):
            raise ValueError(f"matrix not positive definite (pivot {diag!r} in column {j})")
        low[j, j] = math.sqrt(diag)
        low[j + 1:, j] = (matrix[j + 1:, j] - dot(low[j + 1:, :j], low[j, :j])) / low[j, j]
    y = np.zeros(n)
    for j in range(n):
        y[j] = (rhs[j] - float(dot(low[j, :j], y[:j]))) / low[j, j]
    x = np.zeros(n)
    for j in range(n - 1, -1, -1):
        x[j] = (y[j] - float(dot(low[j + 1:, j], x[j + 1:]))) / low[j, j]
    return x


def back_substitute(r: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x with r x = rhs, r upper triangular (k, k)."""
    k = r.shape[0]
    x = np.zeros(k)
    for j in range(k - 1, -1, -1):
        x[j] = (rhs[j] - float(dot(r[j, j + 1:], x[j + 1:]))) / r[j, j]
    return x


def solve_qp(B: np.ndarray, g: np.ndarray, A: np.ndarray, r: np.ndarray, *, max_iter: int | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """(d, working set) minimising g.d + d.B d / 2 subject to A d <= r, B symmetric positive
    definite, rows of A of unit length, r >= 0, by the primal active-set method from d = 0
    with the null-space step (Householder QR of the working rows).

    A blocking row that is linearly dependent on the working rows to 1e-10 is skipped (it
    can only block through rounding).  Ties are broken by the lowest row index, so the
    result is deterministic.  After ``max_iter`` (default 10 (n + 1)) iterations the
    current d is returned: feasible and with a model value no larger than at 0.
    """
    n = g.size
    max_iter = 10 * (n + 1) if max_iter is None else max_iter
    r = np.maximum(r, 0.0)
    d = np.zeros(n)
    work: list[int] = []
    skip = np.zeros(A.shape[0], dtype=bool)
    for _ in range(max_iter):
        q = g + dot(B, d)
        k = len(work)
        basis, tri = householder_qr(A[work].T) if k else (np.eye(n), np.zeros((n, 0)))
        null = basis[:, k:]
        if null.shape[1]:
            w = cholesky_solve(matmul(null.T, matmul(B, null)), -dot(null.T, q))
            p = dot(null, w)
        else:
            p = np.zeros(n)
        size = float(np.max(np.abs(p)))
        if size <= 1e-14 * (1.0 + float(np.max(np.abs(d)))):
            if k == 0:
                break
            lam = back_substitute(tri[:k], -dot(basis[:, :k].T, q))
            if float(lam.min()) >= 0.0:
                break
            work.pop(int(np.argmin(lam)))
            skip[:] = False
            continue
        ap = dot(A, p)
        slack = np.maximum(r - dot(A, d), 0.0)
        candidates = (ap > 1e-12 * size) & ~skip
        candidates[work] = False
        alpha, j = 1.0, -1
        while candidates.any():
            ratios = np.where(candidates, slack / np.where(candidates, ap, 1.0), np.inf)
            j = int(np.argmin(ratios))
            if ratios[j] >= 1.0:
                j = -1
                break
            if math.sqrt(float(dot(dot(null.T, A[j]), dot(null.T, A[j])))) > 1e-10:
                alpha = float(ratios[j])
                break
            skip[j] = candidates[j] = False
            j = -1
        d = d + alpha * p
        if j >= 0:
            work.append(j)
    return d, np.array(work, dtype=np.int64)


def bfgs_update(B: np.ndarray, s: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Powell's damped BFGS update of B with step s and gradient change y (stays positive definite)."""
    bs = dot(B, s)
    sbs = float(dot(s, bs))
    sy = float(dot(s, y))
    if sbs <= 0.0:
        return B
    if sy < 0.2 * sbs:
        theta = 0.8 * sbs / (sbs - sy)
        y = theta * y + (1.0 - theta) * bs
        sy = float(dot(s, y))
    return B - np.multiply.outer(bs, bs) / sbs + np.multiply.outer(y, y) / sy


@dataclass
class SQPResult:
    """Result of :func:`minimise`: the final point, its value and gradient, the value after
    every iteration (``history``, the start first), counts (``restarts``: of the quasi-Newton
    model), and why it stopped."""

    x: np.ndarray
    fun: float
    grad: np.ndarray
    history: np.ndarray
    iterations: int
    evaluations: int
    gradients: int
    converged: bool
    message: str
    restarts: int = 0


def minimise(fun, grad, x0: np.ndarray, A: np.ndarray, b: np.ndarray, *, first_step: float, min_step: float,
             max_iter: int, callback=None) -> SQPResult:
    """Minimise ``fun`` subject to A x <= b from the feasible ``x0`` (module docstring).

    ``grad(x)`` is the gradient of ``fun``.  The initial model Hessian is |grad| /
    first_step times the identity, so the first unconstrained step has length
    ``first_step``.  Each iteration halves the step along the QP direction d until
    fun(x + alpha d) <= fun(x) + ARMIJO alpha grad.d (at most LINE_SEARCH times).  Stops,
    converged, when the model has no descent direction (a first-order point), when no step
    along d decreases fun (at a kink of a nonsmooth fun), or when the step is shorter than
    ``min_step`` (max norm); otherwise after ``max_iter`` iterations.  ``callback(x, f)``, if
    given, is called after every iteration with the new iterate (progress reports).  ValueError
    if x0 is not feasible or an option is out of range.
    """
    for name, value in (("first_step", first_step), ("min_step", min_step)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    norms = np.sqrt(dot(A, A))
    if not np.all(norms > 0):
        raise ValueError("minimise: a constraint row of A is zero")
    a, limit = A / norms[:, None], b / norms
    x = np.array(x0, dtype=float)
    violation = float(np.max(dot(a, x) - limit))
    if violation > 1e-12:
        raise ValueError(f"minimise: x0 violates the constraints A x <= b by {violation:.3g}")
    f, g = float(fun(x)), np.asarray(grad(x), dtype=float)
    B = np.eye(x.size) * (max(math.sqrt(float(dot(g, g))), 1e-300) / first_step)
    history, evaluations, gradients, restarts = [f], 1, 1, 0
    message, converged, iterations = f"iteration limit {max_iter} reached", False, 0
    for iterations in range(1, max_iter + 1):
        try:
            d, _ = solve_qp(B, g, a, np.maximum(limit - dot(a, x), 0.0))
        except ValueError:
            # The damped BFGS model lost positive definiteness to rounding on the working set's null
            # space: restart it as at x0 (scaled identity) from here.
            B = np.eye(x.size) * (max(math.sqrt(float(dot(g, g))), 1e-300) / first_step)
            restarts += 1
            try:
                d, _ = solve_qp(B, g, a, np.maximum(limit - dot(a, x), 0.0))
            except ValueError as exc:
                message = f"the quadratic model is not positive definite after a restart ({exc})"
                break
        slope = float(dot(g, d))
        if not slope < 0.0:
            message, converged = "no descent direction: a first-order point", True
            break
        alpha = 1.0
        for _ in range(LINE_SEARCH):
            f_new = float(fun(x + alpha * d))
            evaluations += 1
            if f_new <= f + ARMIJO * alpha * slope:
                break
            alpha *= 0.5
        else:
            message, converged = f"no decrease along the QP direction after {LINE_SEARCH} halvings", True
            break
        step = alpha * d
        g_new = np.asarray(grad(x + step), dtype=float)
        gradients += 1
        B = bfgs_update(B, step, g_new - g)
        x, f, g = x + step, f_new, g_new
        history.append(f)
        if callback is not None:
            callback(x, f)
        if float(np.max(np.abs(step))) < min_step:
            message, converged = f"step shorter than {min_step:.3g}", True
            break
    return SQPResult(x=x, fun=f, grad=g, history=np.array(history), iterations=iterations,
                     evaluations=evaluations, gradients=gradients, converged=converged, message=message,
                     restarts=restarts)
