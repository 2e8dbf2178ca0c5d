"""Scene files: validation messages, SI conversion, round trip (selfalign.scene)."""

import math

import pytest
import yaml

import selfalign as sa
from selfalign import SceneError, SIScale, StopZone, load_scene, scene_from_dict

BASE = """\
profile: {kind: three_phase, dt: 1.05, dy: 0.084, y2: 2.2, y3: 0.9}
surface: {kind: stop_zone, x_mu: 0.5, c_mu: 2.5}
body: {width: 0.05}
start: {x0: 0.0, v0: 0.0, phase: 0.0}
horizon: {periods: 3}
"""

#: (case, edit of BASE, text the one-line message must contain after the file name)
BAD = [
    ("unknown key", ("start: {", "start: {x1: 2, "), "start: unknown key 'x1'"),
    ("unknown top-level key", (BASE, BASE + "colour: red\n"), "<top level>: unknown key 'colour'"),
    ("unknown profile key", ("y3: 0.9}", "y3: 0.9, y4: 1}"), "profile: unknown key 'y4'"),
    ("wrong type", ("dt: 1.05", "dt: fast"), "profile.dt: expected number"),
    ("wrong type integer", ("periods: 3", "periods: 2.5"), "horizon.periods: expected integer"),
    ("negative period", ("dt: 1.05", "dt: -1.05"), "profile.dt: must be > 0"),
    ("NaN", ("dy: 0.084", "dy: .nan"), "profile.dy: must be a finite number"),
    ("infinity", ("x0: 0.0", "x0: .inf"), "start.x0: must be a finite number"),
    ("w = 0", ("width: 0.05", "width: 0"), "body.width: must be > 0"),
    ("w < 0", ("width: 0.05", "width: -0.05"), "body.width: must be > 0"),
    ("c_mu < 1", ("c_mu: 2.5", "c_mu: 0.5"), "surface.c_mu: must be >= 1"),
    ("missing key", ("dy: 0.084, ", ""), "profile: 'dy' is a required property"),
    ("missing block", ("horizon: {periods: 3}\n", ""), "<top level>: 'horizon' is a required property"),
    ("stop zone without body", ("body: {width: 0.05}\n", ""), "body.width is required"),
    ("infeasible profile", ("dy: 0.084", "dy: 0.5"), "profile: no physical three-phase profile (case 0)"),
    ("bad YAML", ("horizon: {periods: 3}", "horizon: {periods: 3"), "not valid YAML at line 6"),
    ("phase = 1", ("phase: 0.0", "phase: 1.0"), "start.phase: must be < 1"),
    ("phase < 0", ("phase: 0.0", "phase: -0.1"), "start.phase: must be >= 0"),
    ("not a mapping", (BASE, "- a\n- b\n"), "a scene must be a mapping"),
    ("duplicate key", (BASE, BASE + "surface: {kind: uniform}\n"),
     "key 'surface' at line 6 is given already at line 2 (a key may appear once in a mapping)"),
    ("duplicate inner key", ("c_mu: 2.5}", "c_mu: 2.5, x_mu: 0.7}"), "key 'x_mu' at line 2 is given already at line 2"),
    ("underscore in a number", ("dt: 1.05", "dt: 1_05"),
     "profile.dt: expected number, got str '1_05' (YAML 1.2 reads it as text: write the number without '_' or ':')"),
    ("sexagesimal", ("periods: 3", "periods: 1:30"), "horizon.periods: expected integer, got str '1:30' (YAML 1.2"),
    ("YAML 1.1 boolean", (BASE, BASE + "record: {events: yes}\n"),
     "record.events: expected boolean, got str 'yes' (YAML 1.2: the booleans are true and false)"),
    ("body on a uniform surface", ("kind: stop_zone, x_mu: 0.5, c_mu: 2.5", "kind: uniform"),
     "body: does nothing on a uniform surface (the body width is the transition width of a stop zone, eq. 7)"),
    ("arcs without arcs", (BASE, BASE + "solver: {method: moreau}\nrecord: {arcs: true}\n"),
     "record.arcs: does nothing with method 'moreau' (closed-form arcs are the exact solver's)"),
    ("events without events", (BASE, BASE + "solver: {method: moreau}\nrecord: {events: true}\n"),
     "record.events: does nothing with method 'moreau'"),
    ("si scale without finite units", (BASE, BASE + "si: {mu: 1.0e-300, g: 1.0e-150, L: 1.0e+20}\n"),
     "si: mu = 1e-300, g = 1e-150, L = 1e+20 give no finite unit of"),
    ("zone beyond double resolution", ("x_mu: 0.5", "x_mu: 1.0e+308"),
     "surface: stop zone x_mu = 1e+308 is more than 2**32 times its width w = 0.05"),
    ("max_periods with periods", ("periods: 3", "periods: 3, max_periods: 10"),
     "horizon.max_periods: does nothing with periods: N (it is the budget of until: rest)"),
]


def test_base_scene_loads(tmp_path):
    path = tmp_path / "good.yaml"
    path.write_text(BASE)
    scene = load_scene(path)
    assert scene.name == "good" and scene.horizon_periods == 3
    assert isinstance(scene.surface, StopZone) and scene.surface.w == 0.05


@pytest.mark.parametrize("case, edit, expected", BAD, ids=[b[0] for b in BAD])
def test_bad_scene_is_one_line_naming_file_and_key(tmp_path, case, edit, expected):
    """Bad input raises SceneError before any work: one line, '<file>: <key>: <problem>'."""
    old, new = edit
    assert old in BASE
    path = tmp_path / "bad.yaml"
    path.write_text(BASE.replace(old, new))
    with pytest.raises(SceneError) as info:
        load_scene(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: {expected}"), message


@pytest.mark.parametrize("old, new, value", [("dt: 1.05", "dt: 105e-2", 1.05), ("x0: 0.0", "x0: 1e-3", 1e-3),
                                            ("x0: 0.0", "x0: -2E3", -2000.0), ("x0: 0.0", "x0: 010", 10.0)])
def test_numbers_are_read_as_yaml_1_2_numbers(tmp_path, old, new, value):
    """YAML 1.1 (PyYAML's resolver) read 1e-3 and -2E3 as strings ("got str", no dot) and 010 as
    octal 8; a scene file is YAML 1.2: they are the numbers 0.001, -2000 and 10."""
    path = tmp_path / "s.yaml"
    path.write_text(BASE.replace(old, new))
    scene = load_scene(path)
    assert (scene.profile.dt if old.startswith("dt") else scene.x0) == value


def test_record_arcs_reaches_the_trajectory(tmp_path):
    """record.arcs was dropped by the loader (never passed to Record): the exact solver's arc log
    is now kept, as for a Scene built in Python with Record(arcs=True)."""
    path = tmp_path / "s.yaml"
    path.write_text(BASE + "record: {arcs: true}\n")
    scene = load_scene(path)
    assert scene.record.arcs
    assert len(sa.simulate(scene).arcs) > 0


def test_binary_file_is_named(tmp_path):
    """A binary file failed with a UnicodeDecodeError naming no file; now one SceneError line."""
    path = tmp_path / "blob.yaml"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\xff" * 8)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert str(info.value) == f"{path}: not a scene file: not UTF-8 text (byte 0x89 at offset 0)"


def test_missing_file_is_named(tmp_path):
    with pytest.raises(SceneError, match=r"nope\.yaml: cannot read scene file"):
        load_scene(tmp_path / "nope.yaml")


@pytest.mark.parametrize("name", ["fig07", "polynomial", "stop_zone", "si_example"])
def test_workflow_scenes_load(repo, name):
    scene = load_scene(repo / f"workflow/scenes/{name}.yaml")
    assert scene.name == name


SI = {"mu": 0.2, "g": 9.81, "L": 0.01}


def si_scene_dict():
    """A scene in SI units: seconds, metres, m/s, m/s^2."""
    return {
        "units": "si", "si": dict(SI),
        "profile": {"kind": "three_phase", "dt": 0.075, "dy": 0.00084, "y2": 4.3, "y3": 1.8},
        "surface": {"kind": "stop_zone", "x_mu": 0.005, "c_mu": 2.5},
        "body": {"width": 0.0005},
        "start": {"x0": 0.001, "v0": -0.01, "phase": 0.25},
        "horizon": {"periods": 2},
    }


def test_si_block_converts_to_dimensionless_and_back():
    """Sect. 3.2: x = x~/L, t = t~/T with T = sqrt(L/(mu g)); velocities scale by L/T,
    accelerations by mu g; phase and c_mu are dimensionless.  rtol 1e-14 both ways."""
    data = si_scene_dict()
    scene = scene_from_dict(data)
    T = math.sqrt(SI["L"] / (SI["mu"] * SI["g"]))
    p, s = scene.profile, scene.surface
    expected = {p.dt: 0.075 / T, p.dy: 0.00084 / SI["L"], p.y2: 4.3 / (SI["mu"] * SI["g"]),
                p.y3: 1.8 / (SI["mu"] * SI["g"]), s.x_mu: 0.005 / SI["L"], s.w: 0.0005 / SI["L"],
                scene.x0: 0.001 / SI["L"], scene.v0: -0.01 * T / SI["L"]}
    for got, want in expected.items():
        assert got == pytest.approx(want, rel=1e-14)
    assert scene.phase == 0.25 and s.c_mu == 2.5
    si = scene.si
    assert si == SIScale(**SI) and si.T == pytest.approx(T, rel=1e-15)
    back = {si.to_si(p.dt, "time"): 0.075, si.to_si(p.dy, "length"): 0.00084,
            si.to_si(p.y2, "acceleration"): 4.3, si.to_si(scene.v0, "velocity"): -0.01,
            si.to_si(s.w, "length"): 0.0005}
    for got, want in back.items():
        assert got == pytest.approx(want, rel=1e-14)


def test_si_without_block_is_rejected():
    data = si_scene_dict()
    del data["si"]
    with pytest.raises(SceneError, match="units: 'si' needs an si block"):
        scene_from_dict(data, source="s.yaml")


@pytest.mark.parametrize("data", [
    yaml.safe_load(BASE),
    si_scene_dict(),
    {"profile": {"kind": "polynomial", "dt": 0.05, "dy": 0.02, "forward_fraction": 0.7},
     "horizon": {"until": "rest", "max_periods": 50},
     "solver": {"method": "moreau", "options": {"h": 1e-4}},
     "record": {"series": ["x", "v"], "samples_per_period": 50, "rerun": True}},
    {"profile": {"kind": "fourier", "dt": 0.072, "cos_coeffs": [0.01, 0.0], "sin_coeffs": [0.0, 0.002]},
     "horizon": {"periods": 1}, "description": "two harmonics"},
], ids=["stop_zone", "si", "polynomial_rest", "fourier"])
def test_to_dict_round_trip(data):
    """scene_from_dict(scene.to_dict()) is the same scene (to_dict is in dimensionless units)."""
    scene = scene_from_dict(data, name="rt")
    again = scene_from_dict(scene.to_dict())
    assert again.to_dict() == scene.to_dict()
    assert repr(again.profile) == repr(scene.profile) and again.si == scene.si
