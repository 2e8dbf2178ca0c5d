"""The command line (docs/reference/cli.md) through its real entry points: ``python -m selfalign``
in a subprocess and the ``[project.scripts]`` callable; its numbers are the library's."""

import json
import os
import subprocess
import sys
import tomllib
from importlib import import_module

import pytest
from conftest import REPO as REPO_PATH

import selfalign as sa
from selfalign.io.hdf5 import read_h5

pytest.importorskip("click", reason="the command line needs click (pip install -e '.[test]')")

REPO = str(REPO_PATH)
SCENES = os.path.join(REPO, "workflow", "scenes")
FIG18 = ["--dt", "1.05", "--dy", "0.084", "--y2", "2.2", "--y3", "0.9"]
CASE4 = ["--dt", "1.0", "--dy", "0.084", "--y2", "1.4", "--y3", "1.3"]  # fig09_case4.yaml: slip-slip
NON_PHYSICAL = ["--dt", "1", "--dy", "0.5", "--y2", "0.2", "--y3", "0.3"]  # case 0


def run(*args, prelude=None, cwd=None):
    """``python -m selfalign ARGS`` (or ``prelude`` before main()) with this checkout's package."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [REPO, os.environ.get("PYTHONPATH")]))}
    command = ["-m", "selfalign", *args] if prelude is None else [
        "-c", f"{prelude}; from selfalign.cli import main; main({list(args)!r})"]
    return subprocess.run([sys.executable, *command], capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=120)


def scene(name):
    return os.path.join(SCENES, f"{name}.yaml")


def test_simulate_writes_the_library_result(tmp_path):
    """simulate -o writes an HDF5 result whose x_end, status and method are selfalign.simulate's,
    and --rerun writes the recording the workflow writes of that result (series, events, scene)."""
    out, rrd = tmp_path / "run.h5", tmp_path / "run.rrd"
    proc = run("simulate", scene("stop_zone"), "-o", str(out), "--rerun", str(rrd))
    assert proc.returncode == 0, proc.stderr
    expected = sa.simulate(sa.load_scene(scene("stop_zone")))
    attrs = read_h5(out)["attrs"]
    assert attrs["x_end"] == expected.x_end
    assert (attrs["status"], attrs["method"]) == (expected.status.value, expected.method)
    assert "status accumulation" in proc.stdout and repr(expected.x_end)[:6] in proc.stdout
    from selfalign.io.recording import read_documents, read_logs

    assert len(read_logs(rrd)["events"].texts) == len(read_h5(out)["groups"]["events"]["datasets"]["t"])
    assert "stop_zone" in read_documents(rrd)["scene"]


def test_simulate_method_and_periods_override_the_scene(tmp_path):
    """--method and --periods reach the solver: the result is the scene's with that method (default
    options) and exactly that many periods."""
    out = tmp_path / "run.h5"
    proc = run("simulate", scene("si_example"), "--method", "moreau", "--periods", "3", "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    loaded = sa.load_scene(scene("si_example"))
    expected = sa.simulate(loaded.replace(method="moreau", solver_options={}, periods=3))
    attrs = read_h5(out)["attrs"]
    assert (attrs["method"], attrs["period_end"], attrs["x_end"]) == ("moreau", 3, expected.x_end)


def test_simulate_refuses_a_rerun_without_series_before_running(tmp_path):
    """--rerun on a scene that records no series is one line, exit 2, and no file is written."""
    proc = run("simulate", scene("si_example"), "-o", str(tmp_path / "a.h5"), "--rerun", str(tmp_path / "a.rrd"))
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "record.series" in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_check_reports_one_line_per_problem(tmp_path):
    """check prints "path: problem" for each bad file and "path: ok" for good ones; exit 1 if any
    file is bad, 0 if all are fine."""
    non_physical = tmp_path / "non_physical.yaml"
    non_physical.write_text("profile: {kind: three_phase, dt: 1, dy: 0.5, y2: 0.2, y3: 0.3}\nhorizon: {periods: 2}\n")
    unknown_key = tmp_path / "unknown_key.yaml"
    unknown_key.write_text("profile: {kind: polynomial, dt: 1, dy: 0.01}\nhorizon: {periods: 2}\nspeed: 3\n")
    good = scene("fig03")
    proc = run("check", good, str(non_physical), str(unknown_key))
    assert proc.returncode == 1
    lines = proc.stdout.splitlines()
    assert lines[0] == f"{good}: ok"
    assert lines[1].startswith(f"{non_physical}: profile: no physical three-phase profile")
    assert lines[2].startswith(f"{unknown_key}: ") and "'speed'" in lines[2]
    assert len(lines) == 3
    fine = run("check", good, scene("stop_zone"))
    assert fine.returncode == 0
    assert fine.stdout.splitlines() == [f"{good}: ok", f"{scene('stop_zone')}: ok"]


def test_steady_state_json_is_the_library_result():
    """steady-state --json gives steady_state's fields, classify's case and floquet's multipliers
    (a slip-slip case, where the second multiplier is c4 of eq. 33); NaN becomes null."""
    proc = run("steady-state", *CASE4, "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    profile = sa.ThreePhaseProfile(1.0, 0.084, 1.4, 1.3)
    state = sa.steady_state(profile)
    assert out["case"] == sa.classify(profile) == 4
    assert (out["vbar"], out["f"], out["v0"]) == (state.vbar, state.f, state.v0)
    assert out["floquet_multipliers"] == sa.floquet(profile).multipliers.tolist()
    pure_stick = json.loads(run("steady-state", "--dt", "1", "--dy", "0.01", "--y2", "0.5", "--y3", "0.5",
                                "--json").stdout)
    assert (pure_stick["case"], pure_stick["vbar"], pure_stick["f"]) == (5, 0.0, None)


def test_steady_state_si_matches_an_si_scene():
    """--si MU G L converts like a scene's si block: the SI values of si_example.yaml give the same
    dimensionless profile and vbar, and vbar in m/s is vbar L / T."""
    loaded = sa.load_scene(scene("si_example"))
    proc = run("steady-state", "--dt", "0.0749618", "--dy", "0.00084", "--y2", "4.3164", "--y3", "1.7658",
               "--si", "0.2", "9.81", "0.01", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    p = loaded.profile
    assert (out["dt"], out["dy"], out["y2"], out["y3"]) == (p.dt, p.dy, p.y2, p.y3)
    assert out["vbar"] == sa.steady_state(p).vbar
    assert out["si"]["vbar"] == pytest.approx(out["vbar"] * loaded.si.L / loaded.si.T, rel=1e-15)


def test_positioning_json_is_the_library_result():
    """positioning --json gives sa.positioning's Delta_x_d and outcome fractions for the setting."""
    proc = run("positioning", *FIG18, "--w", "0.05", "--c-mu", "2.5", "--n-entries", "8", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    expected = sa.positioning(sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9), w=0.05, c_mu=2.5, n_entries=8)
    for key in ("dx_d", "x_d", "x_stick_min", "frac_accumulate", "frac_stop", "frac_never_stop", "accumulation"):
        assert out[key] == getattr(expected, key), key


@pytest.mark.parametrize("args, named", [
    (["steady-state", *NON_PHYSICAL], "case 0"),
    (["steady-state", "--dt", "abc", "--dy", "1", "--y2", "2", "--y3", "2"], "'--dt'"),
    (["positioning", *FIG18, "--w", "0.05", "--c-mu", "0.5"], "c_mu must be > 1"),
    (["simulate", "no_such_scene.yaml"], "cannot read scene file"),
])
def test_bad_input_is_one_line_and_exit_2(args, named):
    """A bad value or file ends with one line on stderr naming it, exit code 2, no traceback."""
    proc = run(*args)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and named in proc.stderr
    assert proc.stderr.startswith(f"selfalign {args[0]}: error: ")
    assert "Traceback" not in proc.stderr and proc.stdout == ""


POSITIONING = ["positioning", *FIG18, "--w", "0.05", "--c-mu", "2.5"]


@pytest.mark.parametrize("args, named", [
    ([*POSITIONING, "--n-entries", "1e9"],
     "n_entries = 1,000,000,000 entries for each of 1 setting(s) need about 615 GiB"),
    ([*POSITIONING, "--max-periods", "1e21"], "max_periods must be an integer in [1, 9.0072e+15]"),
    ([*POSITIONING, "--max-periods", "1000000000000000000000"], "max_periods must be an integer in [1, 9.0072e+15]"),
    (["simulate", scene("fig07"), "--periods", "1e21"], "horizon.periods must be an integer in [1, 9.0072e+15]"),
    (["steady-state", "--dt", "1", "--dy", "1", "--y2", "1e20", "--y3", "1.7e308"], "y3 must lie in [1e-30, 1e+30]"),
    (["steady-state", "--dt", "1", "--dy", "2.2", "--y2", "1e150", "--y3", "5e-324"], "y2 must lie in"),
    ([*POSITIONING[:-4], "--w", "1e-20", "--c-mu", "2.5", "--si", "1e-300", "1e-150", "1e20"],
     "si: mu = 1e-300, g = 1e-150, L = 1e+20 give no finite unit of"),
])
def test_sizes_and_scales_are_refused_in_one_line(args, named):
    """--n-entries 1e9 was killed by the kernel at 24 GB, --max-periods 10**21 an OverflowError
    traceback, extreme profiles leaked numpy RuntimeWarnings to stderr and extreme --si scales
    ended in ZeroDivisionError.  Expected: one line naming the option and its limit, exit code 2,
    before any work; no warning, no traceback."""
    proc = run(*args)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and named in proc.stderr, proc.stderr
    assert "Warning" not in proc.stderr and "Traceback" not in proc.stderr and proc.stdout == ""


def test_unwritable_output_directory_fails_before_the_run(tmp_path):
    """-o into a directory that takes no files failed only after the run (its summary printed).
    Expected: one line naming the directory, exit code 2, nothing run.  (/proc takes no new files,
    also for root, for whom a read-only mode would not stop the write.)"""
    if not os.path.isdir("/proc"):
        pytest.skip("needs /proc")
    proc = run("simulate", scene("fig07"), "-o", "/proc/result.h5")
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.startswith("selfalign simulate: error: Invalid value for '-o' / '--output': cannot write into "
                                  "directory '/proc'") and proc.stderr.count("\n") == 1


def test_debug_shows_the_traceback():
    """--debug prints the traceback of the library's error, then the same line, exit code 2."""
    proc = run("steady-state", *NON_PHYSICAL, "--debug")
    assert proc.returncode == 2
    assert "Traceback" in proc.stderr and "NonPhysicalProfile" in proc.stderr
    assert proc.stderr.splitlines()[-1].startswith("selfalign steady-state: error: no physical")


def test_missing_click_is_one_line():
    """Without click, main() says to install selfalign[cli] in one line and exits 2."""
    proc = run("check", scene("fig03"), prelude="import sys; sys.modules['click'] = None")
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "selfalign[cli]" in proc.stderr


def project_script():
    """The callable that pyproject's [project.scripts] names for the selfalign command."""
    with open(os.path.join(REPO, "pyproject.toml"), "rb") as f:
        target = tomllib.load(f)["project"]["scripts"]["selfalign"]
    module, name = target.split(":")
    return target, getattr(import_module(module), name)


def test_project_script_is_the_command_line(monkeypatch, capsys):
    """[project.scripts] names selfalign.cli:main, and that callable runs the command line from sys.argv."""
    target, main = project_script()
    assert target == "selfalign.cli:main"
    monkeypatch.setattr(sys, "argv", ["selfalign", "check", scene("fig03")])
    with pytest.raises(SystemExit) as exit_:
        main()
    assert exit_.value.code == 0
    assert capsys.readouterr().out == f"{scene('fig03')}: ok\n"


@pytest.mark.parametrize("command, section", [
    ("simulate", "Sect. 3"), ("check", "Sect. 3"), ("steady-state", "Sect. 4.4.3"),
    ("steady-state", "Sect. 6.1"), ("positioning", "Sect. 7.1"),
])
def test_help_names_the_paper_section(command, section, capsys):
    """Each command's --help names the section of the paper it implements."""
    _, main = project_script()
    with pytest.raises(SystemExit) as exit_:
        main([command, "--help"])
    assert exit_.value.code == 0
    assert section in " ".join(capsys.readouterr().out.split())
