"""Every name ``selfalign`` exports documents itself in the numpydoc format
(https://numpydoc.readthedocs.io/en/latest/format.html) and shows its use in examples that run.

The exported names are the keys of ``selfalign._EXPORTS`` (the package's lazy public API).  Their
docstrings are parsed with numpydoc (:mod:`numpydoc.docscrape`) and checked with its validator
(:func:`numpydoc.validate.validate`); their Examples run under :mod:`doctest` with the flags
ELLIPSIS and NORMALIZE_WHITESPACE, so a wrapped line of output or a ``...`` for digits that do not
matter is allowed, a different result is not."""

import doctest
import enum
import inspect
import io
import warnings

import numpydoc.validate
import pytest
from numpydoc.docscrape import NumpyDocString

import selfalign

EXPORTED = sorted(selfalign._EXPORTS)
#: Result records the library builds: their constructors take fields and check nothing, so their
#: docstrings need no Raises section.
RESULTS = {"BatchResult", "CornerAlignment", "Design", "DriftMap", "FloquetResult", "LineAlignment", "LyapunovTrace",
           "OptimalProfile", "Positioning", "SteadyDrift", "SteadyState", "Trajectory"}
#: numpydoc validation checks every exported docstring passes (numpydoc.validate.ERROR_MSGS).
#: Left out: SS02, PR08 and RT04 (a summary or description may start with a symbol, e.g.
#: "x_{n+1}" or "``x0``"), SS05 (a summary may say what a function returns rather than start
#: with a verb), SA01 (See Also only where useful) and YD01 (no generator is exported).
CHECKS = ("GL01", "GL02", "GL03", "GL05", "GL06", "GL07", "GL08", "GL10", "SS01", "SS03", "SS04", "SS06",
          "ES01", "PR01", "PR02", "PR03", "PR04", "PR05", "PR06", "PR07", "PR09", "PR10", "RT01", "RT02",
          "RT03", "RT05", "SA02", "SA04", "EX01")
#: Checks of the constructor's parameters, which an enum does not have (its members are looked up
#: by value; they are documented as Attributes).
PARAMETER_CHECKS = ("PR01", "PR02", "PR03")
OPTIONFLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def exported(name):
    return getattr(selfalign, name)


def kind(obj) -> str:
    """"enum", "error", "class" or "function"."""
    if inspect.isclass(obj):
        if issubclass(obj, enum.Enum):
            return "enum"
        if issubclass(obj, BaseException):
            return "error"
        return "class"
    return "function"


def sections(obj) -> tuple[NumpyDocString, list[str]]:
    """The numpydoc sections of ``obj``'s own docstring and numpydoc's warnings about it (an
    unknown or malformed section)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        doc = NumpyDocString(obj.__doc__ or "")
    return doc, [str(w.message) for w in caught]


def required_sections(name, obj) -> list[str]:
    """The sections the docstring of the exported ``obj`` must have: Parameters for callables with
    parameters, Returns and Raises for functions, Attributes for classes (their properties, fields
    or members), Raises for classes whose constructor checks its parameters, Examples for all."""
    what = kind(obj)
    need = ["Summary", "Extended Summary"]
    if what in ("function", "class") and inspect.signature(obj).parameters:
        need.append("Parameters")
    if what == "function":
        need += ["Returns", "Raises"]
    if what in ("class", "enum"):
        need.append("Attributes")
    if what == "class" and inspect.signature(obj).parameters and name not in RESULTS:
        need.append("Raises")
    return need + ["Examples"]


def run_examples(obj, name) -> tuple[int, int, str]:
    """(failed, attempted, report) of the doctest examples in ``obj``'s docstrings (its own and
    those of its methods), each run in a fresh namespace; the report shows every failure."""
    report = io.StringIO()
    runner = doctest.DocTestRunner(optionflags=OPTIONFLAGS)
    failed = attempted = 0
    for test in doctest.DocTestFinder().find(obj, name, globs={}):
        result = runner.run(test, out=report.write)
        failed, attempted = failed + result.failed, attempted + result.attempted
    return failed, attempted, report.getvalue()


def test_exported_names_are_the_public_api():
    """The names checked here are ``selfalign.__all__`` without ``__version__``, each resolvable."""
    assert EXPORTED == sorted(set(selfalign.__all__) - {"__version__"})
    for name in EXPORTED:
        assert exported(name) is not None


@pytest.mark.parametrize("name", EXPORTED)
def test_docstring_has_the_numpydoc_sections(name):
    """The docstring parses as numpydoc without warnings and holds every section
    :func:`required_sections` asks of its kind, none of them empty; an enum documents every
    member under Attributes."""
    obj = exported(name)
    doc, problems = sections(obj)
    assert not problems, f"selfalign.{name}: {problems}"
    missing = [section for section in required_sections(name, obj) if not doc[section]]
    assert not missing, f"selfalign.{name}: no {', '.join(missing)} section"
    if kind(obj) == "enum":
        documented = {n.strip() for p in doc["Attributes"] for n in p.name.split(",")}
        undocumented = sorted(set(obj.__members__) - documented)
        assert not undocumented, f"selfalign.{name}: members {undocumented} not under Attributes"


@pytest.mark.parametrize("name", EXPORTED)
def test_docstring_renders_on_the_documentation_site(name):
    """The documentation site renders these docstrings with napoleon and resolves every type as a
    cross-reference (docs/conf.py, ``sphinx-build -n``): each Attributes entry names one attribute
    (napoleon renders them one by one), and a type is plain type names, its default and choices
    in the description (napoleon would look up "default 0.0" or '{"exact"' as classes)."""
    doc, _ = sections(exported(name))
    combined = [p.name for p in doc["Attributes"] if "," in p.name]
    assert not combined, f"selfalign.{name}: Attributes entries with several names: {combined}"
    bad = [f"{p.name} : {p.type}" for section in ("Parameters", "Attributes") for p in doc[section]
           if "{" in p.type or "default" in p.type]
    assert not bad, f"selfalign.{name}: types with a default or a set of choices: {bad}"


@pytest.mark.parametrize("name", EXPORTED)
def test_docstring_passes_numpydoc_validation(name):
    """numpydoc's validator finds none of :data:`CHECKS` in the docstring: one-line summary ending
    with a period, extended summary, every parameter documented with a type and a description in
    signature order and none that does not exist, a Returns section for what a function returns,
    sections in numpydoc's order, examples."""
    checks = [c for c in CHECKS if not (kind(exported(name)) == "enum" and c in PARAMETER_CHECKS)]
    result = numpydoc.validate.validate(f"selfalign.{name}")
    errors = [f"{code}: {message}" for code, message in result["errors"] if code in checks]
    assert not errors, f"selfalign.{name}:\n" + "\n".join(errors)


@pytest.mark.slow
def test_every_example_runs_and_prints_what_it_shows():
    """The Examples of every exported name run under doctest (ELLIPSIS, NORMALIZE_WHITESPACE) and
    print exactly the output shown; every exported name has at least one example.  The failure
    message lists every failing example with what it printed instead."""
    failures, without = [], []
    for name in EXPORTED:
        failed, attempted, report = run_examples(exported(name), name)
        if failed:
            failures.append(report)
        if not attempted:
            without.append(name)
    assert not without, f"exported names without examples: {without}"
    assert not failures, "failing examples:\n" + "\n".join(failures)


def test_a_wrong_example_is_reported():
    """The example check can fail: an example whose shown output differs from what it prints is
    counted and reported with both outputs."""
    def wrong():
        """An example that shows the wrong sum.

        >>> 1 + 2
        4
        """

    failed, attempted, report = run_examples(wrong, "wrong")
    assert (failed, attempted) == (1, 1)
    assert "Expected:\n    4\nGot:\n    3" in report
