"""The model's formulas, each defined once and tagged with the equation(s) of the paper it implements.

A function marked with :func:`formula` is a plain scalar Python function of floats (written with
:mod:`math` only).  Python code calls it directly; when the event kernel
(:mod:`selfalign.solvers.engine`) is first loaded it registers every marked function with numba,
so that the compiled code calls this same function compiled, never a copy.  A vectorised formula
of the model (numpy arrays in and out, which the kernel does not call) is marked with
``formula(..., kernel=False)``: it is tagged and indexed the same way, but not given to numba.  A
function of the model that a kernel formula calls but that implements no formula of its own (a step of
an algorithm, such as the one-dimensional minimiser of :func:`selfalign.model.parts.chain_minimiser`) is
marked with :func:`kernel_helper`: registered with numba the same way, not indexed.
Marking imports nothing: ``import selfalign`` stays light.

Every mark says what the function implements, one of:

* ``eqs=("7", "8")``: the numbers of the paper's equations it implements
  (the paper's numbering, as the docstrings cite them).  Each equation has exactly one
  implementing function, its owner (:func:`equation_index`); every other function calls it;
* ``unnumbered="why"``: it has no number of its own (a building block of a numbered formula, a
  formula the paper states in words, or one beyond the paper such as the Stribeck law), and why.

The citation convention, which tests/test_formulas.py enforces over the whole package
(:func:`implementation_markers`): inside a function, a comment that *starts* with the equation
(``# eq. (41)``, ``# eqs. 7-9: ...``) or a docstring line that starts with ``Implements eq.``
marks the code as an implementation of that equation, and only its owner may carry it.  Any other
mention (``see eq. (41)``, ``d_{1,1} of eq. (49)``, ``(eq. 41, :func:`stick_limit`)``) is a
reference in prose and allowed anywhere.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from dataclasses import dataclass

#: Every function marked with :func:`formula` for the compiled kernel, in definition order.
FORMULAS: list = []
#: Every marked function (kernel and vectorised) of the modules imported so far, in definition order.
TAGGED: list = []
#: Every function marked with :func:`kernel_helper`: compiled with the kernel formulas, not indexed.
HELPERS: list = []


@dataclass(frozen=True)
class Tag:
    """What a formula implements: equation numbers, or why it has none."""

    eqs: tuple
    unnumbered: str | None


def formula(func=None, *, eqs=(), unnumbered=None, kernel=True):
    """Mark a model formula (returns it unchanged, with its :class:`Tag` as ``__formula__``).

    Used as ``@formula(eqs=("41",))`` or ``@formula(unnumbered="reason")``; exactly one of the two
    is required (a bare ``@formula`` is refused: every formula says what it implements).
    ``kernel=False``: a vectorised formula that the compiled kernel does not call.
    """
    if func is not None:
        raise TypeError(f"@formula needs eqs=(...) or unnumbered='...' (what {func.__qualname__} implements), "
                        "not a bare @formula")
    eqs = tuple(eqs)
    if bool(eqs) == (unnumbered is not None):
        raise TypeError(f"formula needs exactly one of eqs (equation numbers) and unnumbered (why there is none), "
                        f"got eqs={eqs!r}, unnumbered={unnumbered!r}")
    if not all(isinstance(e, str) and re.fullmatch(r"\d+", e) for e in eqs):
        raise ValueError(f"eqs must be equation numbers of the paper as strings of digits, got {eqs!r}")
    if unnumbered is not None and not (isinstance(unnumbered, str) and unnumbered.strip()):
        raise ValueError(f"unnumbered must say why the formula has no equation number, got {unnumbered!r}")
    tag = Tag(eqs=eqs, unnumbered=unnumbered)

    def mark(f):
        f.__formula__ = tag
        TAGGED.append(f)
        if kernel:
            FORMULAS.append(f)
        return f
    return mark


def kernel_helper(func):
    """Mark ``func`` (returned unchanged) as a step of a kernel formula that implements no formula of its
    own: :func:`selfalign.solvers.jit.kernel` registers it with numba with :data:`FORMULAS`, so that the
    compiled formulas call it compiled; it is not in the equation index."""
    HELPERS.append(func)
    return func


def name(func) -> str:
    """``module.qualname`` of a function."""
    return f"{func.__module__}.{func.__qualname__}"


def owners(funcs) -> dict:
    """Equation number -> the names of the functions among ``funcs`` tagged with it."""
    out: dict = {}
    for f in funcs:
        for eq in f.__formula__.eqs:
            out.setdefault(eq, []).append(name(f))
    return out


def equation_index(funcs=None) -> dict:
    """Equation number -> ``module.qualname`` of the one function implementing it, for every
    numbered equation among ``funcs`` (default: every marked function of the modules imported so
    far; :mod:`selfalign.cli.equations` imports all that define formulas), in equation order.
    ValueError if an equation has two owners (tests/test_formulas.py keeps it from happening)."""
    found = owners(TAGGED if funcs is None else funcs)
    twice = {eq: names for eq, names in found.items() if len(names) > 1}
    if twice:
        raise ValueError(f"equations with more than one implementing function: {twice}")
    return {eq: found[eq][0] for eq in sorted(found, key=int)}


#: A sentence end: ". " not after an abbreviation the docstrings use (eq., eqs., Sect., e.g., i.e.).
_SENTENCE_END = re.compile(r"(?<!\beq)(?<!\beqs)(?<!\bSect)(?<!\be\.g)(?<!\bi\.e)\.\s")


def summary(func) -> str:
    """The first sentence of a function's docstring (what it computes), on one line."""
    text = " ".join((func.__doc__ or "").split())
    end = _SENTENCE_END.search(text)
    return text if end is None else text[:end.start() + 1]


def _cell(text: str) -> str:
    """``text`` as a Markdown table cell (a bar would end the cell)."""
    return text.replace("|", "\\|")


def equation_table(funcs=None) -> str:
    """The equation index of ``funcs`` (as :func:`equation_index`) as Markdown tables: equation,
    what it is, function; then the formulas without a number, with the reason."""
    funcs = TAGGED if funcs is None else funcs
    by_name = {name(f): f for f in funcs}
    lines = ["| Equation | What it is | Function |", "| --- | --- | --- |"]
    for eq, owner in equation_index(funcs).items():
        lines.append(f"| ({eq}) | {_cell(summary(by_name[owner]))} | `{owner}` |")
    lines += ["", "| Function | What it is | Why it has no number |", "| --- | --- | --- |"]
    for f in funcs:
        if f.__formula__.unnumbered is not None:
            lines.append(f"| `{name(f)}` | {_cell(summary(f))} | {_cell(f.__formula__.unnumbered)} |")
    return "\n".join(lines) + "\n"


#: An implementation marker (module docstring): a comment or a docstring line that starts with the
#: equation.  Group 1 holds the numbers: "41", "(41)", "7-9", "(7)-(9)", "15-20, 43".
_COMMENT = re.compile(r"#\s*eqs?\.\s*((?:\(?\d+\)?\s*(?:[-,]|and)?\s*)+)", re.IGNORECASE)
_DOC = re.compile(r"^\s*implements\s+eqs?\.\s*((?:\(?\d+\)?\s*(?:[-,]|and)?\s*)+)", re.IGNORECASE)


def _numbers(text: str) -> list:
    """Equation numbers of a marker's number list, ranges expanded ("7-9" -> 7, 8, 9)."""
    out = []
    for part in re.split(r",|and", text):
        ends = [int(n) for n in re.findall(r"\d+", part)]
        if len(ends) == 2 and "-" in part and ends[0] <= ends[1]:
            out += [str(n) for n in range(ends[0], ends[1] + 1)]
        else:
            out += [str(n) for n in ends]
    return out


def implementation_markers(source: str, module: str) -> list:
    """(``module.qualname``, equation, line) of every implementation marker inside a function of
    ``source`` (the convention of the module docstring); a marker in a nested function counts
    for the outermost function holding it, a class body's methods by their qualname."""
    tree = ast.parse(source)
    comments = [(tok.start[0], tok.string) for tok in tokenize.generate_tokens(io.StringIO(source).readline)
                if tok.type == tokenize.COMMENT]
    found = []

    def visit(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.")
            elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                qual = f"{module}.{prefix}{child.name}"
                doc = ast.get_docstring(child, clean=False) or ""
                for text in doc.splitlines():
                    match = _DOC.match(text)
                    if match:
                        found.extend((qual, eq, child.lineno) for eq in _numbers(match.group(1)))
                for number, text in comments:
                    match = _COMMENT.match(text)
                    if match and child.lineno <= number <= child.end_lineno:
                        found.extend((qual, eq, number) for eq in _numbers(match.group(1)))
    visit(tree, "")
    return found


def misplaced_markers(markers, index: dict) -> list:
    """The markers (of :func:`implementation_markers`) that cite an equation another function owns."""
    return [(where, eq, line) for where, eq, line in markers if eq in index and index[eq] != where]
