"""HDF5 result files, written atomically and reproducibly.

A pipeline that is interrupted (killed job, full disk, exception in a
writer) must never leave a half-written output behind, or Snakemake and a
later reader would take it for a finished result.  Every file therefore goes
through :func:`atomic_path`: it is written under a hidden temporary name in
the destination directory, flushed to disk, and only then renamed over the
destination in one step.  The helper is generic so that figures and rerun
recordings use the same guarantee.

Temporary files.  A writer that is killed (SIGKILL, out of memory, node
failure) cannot remove its temporary file.  The temporary file must lie in
the destination's directory (a rename across file systems is not atomic), so
instead it is named for its writer, ``.<target>.<host>.<pid>.<random>.tmp``
(:func:`temporary_name`), and every write to a target first removes the
temporary files of that target left by processes of this host that no longer
run (:func:`remove_stale_temporaries`).  Such a file is never taken for a
result in the meantime: it is hidden and ends in ``.tmp``, which no result
name or glob matches.  A temporary file of a live process, or of a process on
another host sharing the file system, is left alone.

Reproducibility.  :func:`write_h5` makes its output byte-for-byte
deterministic: no HDF5 object timestamps (``track_times=False`` on the file and
every dataset), objects and attributes in the order the content names them,
and no measured value (CPU or wall-clock time) outside the datasets marked
``measurement = True`` (:mod:`selfalign.io.quantities`).  So two runs with the
same inputs on the same commit give files that differ only in the data of
those datasets, and :func:`reproducible_bytes`, which zeroes exactly those
bytes, gives the same bytes for both.

Self-description
----------------
Every dataset gets the attributes ``units`` and ``description`` (and
``legend``, code -> name, for coded values; ``si_units`` and ``si_factor``
when the file's scene has an SI scale) from :mod:`selfalign.io.quantities`;
a dataset not documented there is refused.  Every file gets the provenance
root attributes ``selfalign_version``, ``git_commit`` (:func:`source_commit`)
and the input that made it: the root attribute ``scene`` (YAML text, set by
the builders of scene-based results) or ``config`` (YAML text of the
``config`` argument, for results built from workflow settings).

Attribute encoding
------------------
Numbers, strings, bools and non-empty lists of numbers (all ints that fit in
int64, or all floats) are stored as native HDF5 attributes.  Anything else —
dicts, ``None``, empty, nested or mixed lists — is stored as a string
``"json:" + json.dumps(value)``.  A genuine string that starts with
``"json:"`` is JSON-encoded too, so :func:`read_h5` can decode every
attribute back unambiguously, and so is one holding a NUL character, which
HDF5 strings cannot.  Read-back values are plain Python objects
(``int``, ``float``, ``bool``, ``str``, ``list``, ``dict``, ``None``); tuples
and numpy arrays come back as lists.
"""

from __future__ import annotations

import functools
import json
import os
import re
import secrets
import socket
import subprocess
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import h5py
import numpy as np
import yaml

from ..model.units import SIScale
from .quantities import MEASUREMENT_ATTR, quantity

#: Prefix of attribute strings that hold a JSON-encoded value.
JSON_PREFIX = "json:"
#: Root attributes stamped on every file by :func:`write_h5`: package version and source commit.
VERSION_ATTR = "selfalign_version"
COMMIT_ATTR = "git_commit"
#: Root attributes naming what a file was made from (one of them is present in every result).
SOURCE_ATTRS = ("scene", "config")

_INT64 = np.iinfo(np.int64)
_GROUP_KEYS = {"datasets", "attrs", "groups"}


def _host() -> str:
    """This host's name in the characters a file name can always hold."""
    return re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname()) or "host"


def temporary_name(path: Path) -> str:
    """The name of a temporary file for ``path`` written by this process:
    ``.<name>.<host>.<pid>.<random>.tmp`` (the random part keeps two writes of one process apart)."""
    return f".{path.name}.{_host()}.{os.getpid()}.{secrets.token_hex(4)}.tmp"


def _running(pid: int) -> bool:
    """Whether a process ``pid`` runs on this host (one of another user counts)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_temporaries(path) -> list[Path]:
    """Remove the temporary files of ``path`` (:func:`temporary_name`) whose writer, a process of
    this host, no longer runs; return them.  A pid reused since only keeps a file until a later
    write; files of other hosts are left alone (their processes cannot be checked from here)."""
    path = Path(path)
    pattern = re.compile(re.escape(f".{path.name}.{_host()}.") + r"(\d+)\.[0-9a-f]+\.tmp")
    removed = []
    if path.parent.is_dir():
        for candidate in path.parent.iterdir():
            match = pattern.fullmatch(candidate.name)
            if match and not _running(int(match[1])):
                candidate.unlink(missing_ok=True)
                removed.append(candidate)
    return removed


@contextmanager
def atomic_path(path) -> Iterator[Path]:
    """Yield a temporary path to write ``path``'s content to.

    On normal exit the temporary file is fsynced and renamed onto ``path``
    (replacing any existing file in one step); on any exception it is
    removed and ``path`` is left untouched.  The temporary file lives in the
    same directory (a rename across file systems would not be atomic), is
    hidden (starts with ".") and ends in ".tmp" so that no glob for real
    outputs matches it; it is named for this process (:func:`temporary_name`),
    and those of ``path`` left by killed writers are removed first
    (:func:`remove_stale_temporaries`).  Writers that pick a format from the
    file extension (e.g. ``Figure.savefig``) must be told the format
    explicitly.  Missing parent directories are created.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(path)
    tmp = path.parent / temporary_name(path)
    try:
        yield tmp
        _fsync(tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    _fsync(path.parent)


def atomic_write(path, writer: Callable[[Path], object]) -> Path:
    """Call ``writer(tmp)`` to write a file, then move it to ``path`` atomically."""
    with atomic_path(path) as tmp:
        writer(tmp)
    return Path(path)


def _fsync(path: Path) -> None:
    """Flush ``path`` (a file or, for the rename itself, a directory) to disk."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_h5(path, datasets: dict, attrs: dict | None = None,
             groups: dict[str, dict] | None = None, *, config: dict | None = None) -> Path:
    """Write an HDF5 file atomically and deterministically.

    ``datasets`` maps names to array-likes (stored at the root), ``attrs``
    holds root attributes (encoded as described in the module docstring) and
    ``groups`` maps group names to dicts with the optional keys
    ``"datasets"``, ``"attrs"`` and ``"groups"`` (nested the same way).
    Names may not contain "/": nesting is spelled with ``groups``.  Every
    dataset must be documented in :mod:`selfalign.io.quantities` (ValueError
    naming it otherwise, before anything is written).  ``config``, the
    settings a result was built from, is stored as YAML text in the root
    attribute ``config``.  The root attributes ``selfalign_version`` and
    ``git_commit`` are added automatically and may not be passed in ``attrs``.
    """
    from .. import __version__  # here, not at the top: the package __init__ may import this module

    attrs = dict(attrs or {})
    reserved = {VERSION_ATTR, COMMIT_ATTR} | ({"config"} if config is not None else set())
    if reserved & set(attrs):
        raise ValueError(f"attributes {sorted(reserved & set(attrs))} are reserved: write_h5 sets them")
    attrs[VERSION_ATTR] = __version__
    attrs[COMMIT_ATTR] = source_commit()
    if config is not None:
        attrs["config"] = yaml.safe_dump(config, sort_keys=False)
    content = {"datasets": datasets, "attrs": attrs, "groups": groups or {}}
    documented = _documentation(content, "", _si_scale(attrs))

    def writer(tmp: Path) -> None:
        with h5py.File(tmp, "w", track_times=False) as f:
            _write_group(f, content, "", documented)

    return atomic_write(path, writer)


@functools.cache
def source_commit() -> str:
    """``git rev-parse HEAD`` of the checkout this package runs from, with ``-dirty`` if tracked
    files differ from it; ``"unknown"`` when the package is not a git checkout (e.g. installed).
    ``--no-optional-locks``: parallel jobs must not race for the index lock."""
    top = Path(__file__).resolve().parents[2]

    def git(*args) -> str:
        return subprocess.run(["git", "-C", str(top), *args], capture_output=True, text=True,
                              check=True).stdout.strip()

    try:
        if Path(git("rev-parse", "--show-toplevel")).resolve() != top:
            return "unknown"
        dirty = git("--no-optional-locks", "status", "--porcelain", "--untracked-files=no")
        return git("rev-parse", "HEAD") + ("-dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _si_scale(attrs: dict) -> SIScale | None:
    """The SI scale of the scene stored in ``attrs["scene"]``, if it has one."""
    scene = attrs.get("scene")
    si = yaml.safe_load(scene).get("si") if isinstance(scene, str) else None
    return SIScale(**si) if si else None


def _documentation(content: dict, where: str, si: SIScale | None) -> dict[str, dict]:
    """Check the layout of ``content`` and return dataset path -> its attributes (units, description, ...)."""
    unknown = set(content) - _GROUP_KEYS
    if unknown:
        raise ValueError(f"group {where or '/'!r}: unknown keys {sorted(unknown)}; allowed: {sorted(_GROUP_KEYS)}")
    datasets = content.get("datasets") or {}
    subgroups = content.get("groups") or {}
    for name in list(datasets) + list(subgroups):
        if not isinstance(name, str) or not name or "/" in name or name == ".":
            raise ValueError(f"group {where or '/'!r}: invalid name {name!r} (a non-empty string without '/')")
    clash = set(datasets) & set(subgroups)
    if clash:
        raise ValueError(f"group {where or '/'!r}: {sorted(clash)} named both as dataset and as group")
    found = {f"{where}/{name}": quantity(f"{where}/{name}").attrs(si) for name in datasets}
    for name, sub in subgroups.items():
        found.update(_documentation(sub, f"{where}/{name}", si))
    return found


def measured_datasets(path) -> list[str]:
    """Paths of the datasets of an HDF5 file marked as measured values (``measurement = True``)."""
    return [name for name, attrs in read_dataset_attrs(path).items() if attrs.get(MEASUREMENT_ATTR) is True]


def reproducible_bytes(path) -> bytes:
    """The bytes of the HDF5 file ``path`` with the data of every measured dataset
    (:func:`measured_datasets`) set to zero: the same for two writes of one result.

    Only the stored values are zeroed (at their offsets in the file, so nothing else moves);
    every other byte, metadata and attributes included, is compared as written."""
    data = bytearray(Path(path).read_bytes())
    with h5py.File(path, "r") as f:
        for name in measured_datasets(path):
            dsid = f[name].id
            size = dsid.get_storage_size()
            if size:
                offset = dsid.get_offset()
                if offset is None:
                    raise ValueError(f"{path}: measured dataset {name!r} is not stored contiguously")
                data[offset:offset + size] = bytes(size)
    return bytes(data)


def _write_group(group: h5py.Group, content: dict, where: str, documented: dict[str, dict]) -> None:
    """Write ``content`` (checked by :func:`_documentation`) into ``group`` at path ``where``."""
    for name, value in (content.get("datasets") or {}).items():
        dataset = group.create_dataset(name, data=_dataset_array(value), track_times=False)
        for key, attr in documented[f"{where}/{name}"].items():
            dataset.attrs[key] = _encode_attr(attr)
    for key, value in (content.get("attrs") or {}).items():
        group.attrs[key] = _encode_attr(value)
    for name, sub in (content.get("groups") or {}).items():
        _write_group(group.create_group(name), sub, f"{where}/{name}", documented)


def _dataset_array(value) -> np.ndarray:
    """numpy's fixed-width unicode has no HDF5 type: store text as UTF-8 strings."""
    arr = np.asarray(value)
    if arr.dtype.kind == "U":
        return arr.astype(h5py.string_dtype())
    return arr


def _is_int(x) -> bool:
    return isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_))


def _encode_attr(value):
    if isinstance(value, (bool, np.bool_, float, np.floating)):
        return value
    if _is_int(value):
        return value if _INT64.min <= value <= _INT64.max else _json(value)
    if isinstance(value, str):
        return _json(value) if value.startswith(JSON_PREFIX) or "\0" in value else value
    if isinstance(value, np.ndarray) and value.size and value.dtype.kind in "iuf":
        return value
    if isinstance(value, (list, tuple)) and value:
        if all(_is_int(v) and _INT64.min <= v <= _INT64.max for v in value):
            return np.asarray(value, dtype=np.int64)
        if all(isinstance(v, (float, np.floating)) for v in value):
            return np.asarray(value, dtype=np.float64)
    return _json(value)


def _json(value) -> str:
    return JSON_PREFIX + json.dumps(value, default=_json_default)


def _json_default(obj):
    """numpy values inside dicts and lists are stored as their Python equivalents."""
    if isinstance(obj, (np.generic, np.ndarray)):
        return obj.tolist()
    raise TypeError(f"attribute value of type {type(obj).__name__} cannot be stored")


def _decode_attr(value):
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, str) and value.startswith(JSON_PREFIX):
        return json.loads(value[len(JSON_PREFIX):])
    return value


def read_h5(path) -> dict:
    """Read a file written by :func:`write_h5`.

    Returns ``{"datasets": {name: ndarray}, "attrs": {name: value},
    "groups": {name: <same structure>}}``; string datasets come back as
    numpy unicode arrays and attributes are decoded to Python values.
    """
    with h5py.File(path, "r") as f:
        return _read_group(f)


def read_dataset_attrs(path) -> dict[str, dict]:
    """Every dataset's attributes (``units``, ``description``, ...), decoded, by path (``"series/mode"``)."""
    found = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, item: found.update(
            {name: {k: _decode_attr(v) for k, v in item.attrs.items()}} if isinstance(item, h5py.Dataset) else {}))
    return found


def _read_group(group: h5py.Group) -> dict:
    out = {"datasets": {}, "attrs": {k: _decode_attr(v) for k, v in group.attrs.items()}, "groups": {}}
    for name, item in group.items():
        if isinstance(item, h5py.Group):
            out["groups"][name] = _read_group(item)
        elif h5py.check_string_dtype(item.dtype) is not None:
            out["datasets"][name] = np.asarray(item.asstr()[...], dtype=str)
        else:
            out["datasets"][name] = item[...]
    return out
