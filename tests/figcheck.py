"""Figure regression checks on numbers rather than pixels.

Pixel comparisons break on every matplotlib, FreeType or font update and
say nothing about *what* changed.  :func:`figure_data` instead extracts what
a figure shows — axis labels, limits and scales, the data of every line,
filled area, scatter, mesh, image, patch and text — as plain JSON-able data,
so a figure can be checked against a stored reference with tolerances
(:func:`compare_figure_data`) and every difference is reported by where it
is (``axes[0].lines[1].y``).  :func:`compare_pixels` remains for the final
rendered look.

matplotlib is imported inside the functions that need it.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from selfalign.io.hdf5 import atomic_write

#: JSON key marking an encoded non-finite float ({"$float": "nan"}); strict JSON has no NaN.
_FLOAT_KEY = "$float"


def figure_data(fig) -> dict:
    """The numeric and textual content of a matplotlib Figure, as plain data.

    The result depends only on what the figure shows, not on object ids or
    rendering, and lists everything in drawing order, so equal figures give
    equal dicts.  Arrays become nested lists; masked values become NaN.
    """
    return {
        "suptitle": fig.get_suptitle(),
        "texts": [_text(t) for t in fig.texts],
        "axes": [_axes(ax) for ax in fig.axes],
    }


def _axes(ax) -> dict:
    return {
        "title": ax.get_title(),
        "xlabel": ax.get_xlabel(),
        "ylabel": ax.get_ylabel(),
        "xlim": _floats(ax.get_xlim()),
        "ylim": _floats(ax.get_ylim()),
        "xscale": ax.get_xscale(),
        "yscale": ax.get_yscale(),
        "lines": [_line(line) for line in ax.lines],
        "collections": [_collection(c) for c in ax.collections],
        "patches": [_patch(p) for p in ax.patches],
        "images": [{"array": _floats(im.get_array()), "extent": _floats(im.get_extent())} for im in ax.images],
        "texts": [_text(t) for t in ax.texts],
    }


def _line(line) -> dict:
    """x and y after unit conversion (dates, categories), as drawn."""
    xy = line.get_xydata()
    return {"label": line.get_label(), "x": _floats(xy[:, 0]), "y": _floats(xy[:, 1])}


def _collection(coll) -> dict:
    """Offsets and colour values for all; geometry where it carries data.

    A scatter's paths are only its marker shape, and a mesh's geometry is
    its coordinate grid, so those store that instead of per-path vertices.
    """
    from matplotlib.collections import PathCollection, QuadMesh

    out = {"type": type(coll).__name__, "label": coll.get_label()}
    if isinstance(coll, QuadMesh):
        out["coordinates"] = _floats(coll.get_coordinates())
    elif not isinstance(coll, PathCollection):
        out["paths"] = [_floats(p.vertices) for p in coll.get_paths()]
    out["offsets"] = _floats(coll.get_offsets())
    array = coll.get_array()
    out["array"] = None if array is None else _floats(array)
    return out


def _patch(patch) -> dict:
    """Vertices in the patch's own coordinates (data coordinates for bars and polygons)."""
    vertices = patch.get_patch_transform().transform(patch.get_path().vertices)
    return {"type": type(patch).__name__, "label": patch.get_label(), "vertices": _floats(vertices)}


def _text(text) -> dict:
    return {"text": text.get_text(), "position": _floats(text.get_position())}


def _floats(values):
    """Nested lists of Python floats; masked entries become NaN."""
    arr = np.ma.asarray(values, dtype=float)
    return np.ma.filled(arr, np.nan).tolist()


def compare_figure_data(actual, reference, rtol: float = 1e-6, atol: float = 1e-9) -> list[str]:
    """Differences between two :func:`figure_data` results; empty when they match.

    Numbers (and arrays of them) match when ``|a - r| <= atol + rtol * |r|``
    or both are NaN; arrays must have equal shapes; everything else must be
    equal.  Each entry names the path of the difference.
    """
    diffs: list[str] = []
    _compare(actual, reference, "figure", rtol, atol, diffs)
    return diffs


def _numeric(x) -> np.ndarray | None:
    """``x`` as a float array if it is a (nested) list of numbers, else None."""
    if not isinstance(x, list):
        return None
    try:
        arr = np.asarray(x)
    except ValueError:  # ragged nesting
        return None
    return arr.astype(float) if arr.dtype.kind in "biuf" else None


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _compare(a, r, where: str, rtol: float, atol: float, diffs: list[str]) -> None:
    if isinstance(a, dict) and isinstance(r, dict):
        for key in r:
            if key in a:
                _compare(a[key], r[key], f"{where}.{key}", rtol, atol, diffs)
            else:
                diffs.append(f"{where}.{key}: missing")
        diffs.extend(f"{where}.{key}: unexpected" for key in a if key not in r)
        return
    arr_a, arr_r = _numeric(a), _numeric(r)
    if arr_a is not None and arr_r is not None:
        _compare_arrays(arr_a, arr_r, where, rtol, atol, diffs)
        return
    if isinstance(a, list) and isinstance(r, list):
        if len(a) != len(r):
            diffs.append(f"{where}: {len(a)} entries, reference has {len(r)}")
            return
        for i, (x, y) in enumerate(zip(a, r)):
            _compare(x, y, f"{where}[{i}]", rtol, atol, diffs)
        return
    if _is_number(a) and _is_number(r):
        if not np.isclose(a, r, rtol=rtol, atol=atol, equal_nan=True):
            diffs.append(f"{where}: {a!r} != reference {r!r}")
        return
    if type(a) is not type(r) or a != r:
        diffs.append(f"{where}: {a!r} != reference {r!r}")


def _compare_arrays(a: np.ndarray, r: np.ndarray, where: str, rtol: float, atol: float,
                    diffs: list[str]) -> None:
    if a.shape != r.shape:
        diffs.append(f"{where}: shape {a.shape} != reference {r.shape}")
        return
    close = np.isclose(a, r, rtol=rtol, atol=atol, equal_nan=True)
    if close.all():
        return
    with np.errstate(invalid="ignore"):
        # A NaN or infinity against a number is the worst kind of mismatch.
        err = np.where(close, -1.0, np.nan_to_num(np.abs(a - r), nan=np.inf))
    worst = np.unravel_index(np.argmax(err), a.shape)
    diffs.append(f"{where}: {np.count_nonzero(~close)} of {a.size} values differ; "
                 f"at {list(map(int, worst))}: {float(a[worst])!r} != reference {float(r[worst])!r}")


def save_reference(data: dict, path) -> Path:
    """Store :func:`figure_data` output as strict JSON (non-finite floats encoded), atomically."""
    text = json.dumps(_encode(data), indent=1, sort_keys=True, allow_nan=False) + "\n"
    return atomic_write(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))


def load_reference(path) -> dict:
    """Read a reference written by :func:`save_reference`."""
    return json.loads(Path(path).read_text(encoding="utf-8"), object_hook=_decode)


def _encode(x):
    if isinstance(x, float) and not math.isfinite(x):
        return {_FLOAT_KEY: repr(x)}
    if isinstance(x, dict):
        return {k: _encode(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_encode(v) for v in x]
    return x


def _decode(obj: dict):
    if obj.keys() == {_FLOAT_KEY}:
        return float(obj[_FLOAT_KEY])
    return obj


def compare_pixels(png_a, png_b, tol: float) -> float | None:
    """RMS pixel difference of ``png_a`` against the reference ``png_b``, or None within ``tol``.

    On a mismatch matplotlib writes a ``*-failed-diff.png`` beside
    ``png_a`` to look at; images of different sizes raise
    ``matplotlib.testing.exceptions.ImageComparisonFailure``.
    """
    from matplotlib.testing.compare import compare_images

    result = compare_images(str(png_b), str(png_a), tol, in_decorator=True)
    return None if result is None else float(result["rms"])


#: A stream object of a PDF file: its dictionary and its bytes.
_PDF_STREAM = re.compile(rb"\d+ 0 obj\s*<<((?:(?!endobj).)*?)>>\s*stream\r?\n(.*?)endstream", re.S)
#: Tokens of a PDF content stream: numbers, names, strings and operators.
_PDF_TOKEN = re.compile(rb"[-+]?(?:\d+\.?\d*|\.\d+)|/[^\s/\[\]<>()]+|<[0-9A-Fa-f\s]*>|\([^)]*\)|[^\s\[\]<>()/]+|[\[\]]")


def pdf_drawing(path) -> list[list]:
    """What a PDF file draws: the tokens of each of its streams but the font programs
    (decompressed; numbers as floats, the rest as bytes), in file order.

    Metadata, object offsets and the embedded font files are left out, so two files that draw
    the same thing compare equal whatever wrote their bytes; numbers are compared with a
    tolerance by :func:`compare_pdf`.
    """
    import zlib

    drawing = []
    for head, body in _PDF_STREAM.findall(Path(path).read_bytes()):
        if b"/Length1" in head:  # an embedded TrueType font program
            continue
        data = zlib.decompress(body) if b"/FlateDecode" in head else body
        drawing.append([float(t) if re.fullmatch(rb"[-+]?(?:\d+\.?\d*|\.\d+)", t) else t
                        for t in _PDF_TOKEN.findall(data)])
    return drawing


def compare_pdf(pdf, reference, atol: float = 0.01) -> list[str]:
    """Differences of what ``pdf`` draws from what ``reference`` draws (:func:`pdf_drawing`),
    numbers within ``atol`` (points: 0.01 pt is 3.5 micrometres) being equal; empty if they agree."""
    a, b = pdf_drawing(pdf), pdf_drawing(reference)
    if len(a) != len(b):
        return [f"{len(a)} drawing streams, reference has {len(b)}"]
    diffs = []
    for k, (s, r) in enumerate(zip(a, b)):
        if len(s) != len(r):
            diffs.append(f"stream {k}: {len(s)} tokens, reference has {len(r)}")
            continue
        for i, (x, y) in enumerate(zip(s, r)):
            same = abs(x - y) <= atol if isinstance(x, float) and isinstance(y, float) else x == y
            if not same:
                diffs.append(f"stream {k} token {i}: {x!r} != {y!r}")
                break
    return diffs


def pdf_page_size(path) -> tuple[float, float]:
    """Width and height of the (single) page of a PDF file, in millimetres."""
    box = re.search(rb"/MediaBox\s*\[\s*([-\d.\s]+)\]", Path(path).read_bytes())
    x0, y0, x1, y1 = (float(v) for v in box.group(1).split())
    return (x1 - x0) * 25.4 / 72, (y1 - y0) * 25.4 / 72


def pdf_font_sizes(path) -> set[float]:
    """Every font size a PDF file sets (the operand of each ``Tf``), in points at print size."""
    sizes = set()
    for stream in pdf_drawing(path):
        sizes.update(stream[i - 1] for i, t in enumerate(stream) if t == b"Tf" and isinstance(stream[i - 1], float))
    return sizes
