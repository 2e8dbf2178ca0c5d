"""Progress reports of long loops (selfalign.progress): periodic log lines, a terminal bar or
nothing, and their wiring into the positioning grid, the bisection, the SQP and the accuracy study."""

import io
import logging
from dataclasses import fields

import numpy as np
import pytest

from selfalign import progress as progress_module
from selfalign.analysis import positioning as positioning_module
from selfalign.analysis.accuracy import StudySettings, study
from selfalign.analysis.fourier_design import optimise_fourier
from selfalign.analysis.positioning import positioning_grid
from selfalign.analysis.sqp import minimise
from selfalign.analysis.steady_simulation import three_phase_simulated_steady_state
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.model.scene import Scene
from selfalign.progress import ENVIRONMENT, Progress, duration, resolve_mode
from selfalign.stages.common import logged


class FakeClock:
    """A clock the test moves by hand."""

    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


class Terminal(io.StringIO):
    def isatty(self):
        return True


@pytest.fixture(autouse=True)
def no_environment_choice(monkeypatch):
    monkeypatch.delenv(ENVIRONMENT, raising=False)


def progress_lines(caplog):
    return [r.getMessage() for r in caplog.records if r.name == "selfalign.progress"]


def test_log_mode_reports_every_interval_with_count_rate_and_eta(caplog):
    """Log mode writes a line only once LOG_INTERVAL seconds have passed since the last one, with
    done/total, the mean rate since the start and the time the rest takes at that rate; closing
    writes the final count and the time taken."""
    caplog.set_level(logging.INFO, logger="selfalign.progress")
    clock, total, step = FakeClock(), 40, 1.0
    with Progress(total, "grid", unit="rows", mode="log", clock=clock) as bar:
        for _ in range(total // 2):
            clock.now += step
            bar.advance(2)
    lines = progress_lines(caplog)
    periodic = int(total // 2 * step // progress_module.LOG_INTERVAL)
    assert len(lines) == periodic + 1
    # The first line: LOG_INTERVAL seconds in, 2 rows per step.
    done = int(2 * progress_module.LOG_INTERVAL / step)
    rate = done / progress_module.LOG_INTERVAL
    assert lines[0] == (f"grid: {done}/{total} rows ({100 * done / total:.0f} %), {rate:.3g} rows/s, "
                        f"ETA {duration((total - done) / rate)}")
    assert lines[-1] == f"grid: done: {total}/{total} rows in {duration(total // 2 * step)}, {rate:.3g} rows/s"


def test_log_mode_final_line_says_where_a_failure_stopped(caplog):
    """An exception inside the block ends the report with 'stopped after' and the count reached."""
    caplog.set_level(logging.INFO, logger="selfalign.progress")
    clock = FakeClock()
    with pytest.raises(RuntimeError), Progress(10, "study", unit="runs", mode="log", clock=clock) as bar:
        bar.advance(3, note="Moreau h = dt/100")
        raise RuntimeError("solver failed")
    assert progress_lines(caplog) == ["study: stopped after 3/10 runs in 0 s; Moreau h = dt/100"]


def test_bar_redraws_at_most_every_bar_interval_and_ends_with_a_newline():
    """On a terminal one line is redrawn in place (carriage returns, no newline until the end),
    at most once per BAR_INTERVAL however often advance is called, and a newline ends it."""
    clock, stream, calls = FakeClock(), Terminal(), 1000
    with Progress(calls, "map", unit="rows", stream=stream, clock=clock) as bar:
        assert bar.mode == "bar"
        for _ in range(calls):
            clock.now += 0.001
            bar.advance()
    text = stream.getvalue()
    redraws = text.count("\r")
    assert 1 < redraws <= calls * 0.001 / progress_module.BAR_INTERVAL + 1
    assert text.endswith("\n") and text.count("\n") == 1
    final = text.rstrip("\n").split("\r")[-1]
    assert final.startswith(f"map [{'#' * progress_module.BAR_WIDTH}] {calls}/{calls} rows (100 %)")


def test_quiet_emits_nothing(caplog):
    """Quiet mode writes to no stream and logs nothing, even on a terminal with a handler set."""
    caplog.set_level(logging.INFO, logger="selfalign.progress")
    clock, stream = FakeClock(), Terminal()
    with Progress(5, "quiet work", mode="quiet", stream=stream, clock=clock) as bar:
        for _ in range(5):
            clock.now += 10.0
            bar.advance()
    assert stream.getvalue() == "" and progress_lines(caplog) == []


def test_auto_mode_follows_environment_then_log_handler_then_terminal(monkeypatch, tmp_path):
    """auto: SELFALIGN_PROGRESS wins; else log lines when the selfalign logger has a handler
    (a workflow job, whose stderr may be a shared terminal); else a bar on a terminal only."""
    assert resolve_mode("auto", Terminal()) == "bar"
    assert resolve_mode("auto", io.StringIO()) == "quiet"
    with logged(tmp_path / "job.log"):
        assert resolve_mode("auto", Terminal()) == "log"
        monkeypatch.setenv(ENVIRONMENT, "quiet")
        assert resolve_mode("auto", Terminal()) == "quiet"
    assert resolve_mode("bar", io.StringIO()) == "bar"


@pytest.mark.parametrize("call, message", [
    (lambda: resolve_mode("verbose"), "progress must be one of"),
    (lambda: Progress(-1, "x"), "progress total must be an integer >= 0"),
    (lambda: positioning_grid(1.0, 0.084, 2.0, 1.0, w=0.05, c_mu=2.5, progress="loud"), "progress must be one of"),
])
def test_bad_mode_or_total_is_refused(call, message):
    """An unknown mode or a negative total is a one-line ValueError naming the allowed values."""
    with pytest.raises(ValueError, match=message):
        call()


def test_bad_environment_value_is_refused(monkeypatch):
    """A misspelt SELFALIGN_PROGRESS is an error, not silently ignored."""
    monkeypatch.setenv(ENVIRONMENT, "silent")
    with pytest.raises(ValueError, match=f"{ENVIRONMENT} must be one of"):
        resolve_mode("auto")


GRID = dict(dt=1.0, dy=0.084, y2=np.array([[1.8], [2.0], [2.3]]), y3=np.array([[0.9, 1.1, 1.3]]))
ZONE = dict(w=0.05, c_mu=2.5, n_entries=8, max_periods=200, levels=(0.99,))


def test_positioning_grid_logs_per_chunk_and_chunks_do_not_change_a_bit(monkeypatch, tmp_path):
    """A grid run inside a workflow log writes a progress line per chunk of settings (interval 0)
    and a final one into the log file; with chunks of 2 settings the result equals, bit for bit,
    the quiet run in one chunk."""
    quiet = positioning_grid(**GRID, **ZONE, progress="quiet")
    monkeypatch.setattr(positioning_module, "CHUNK_MEMBERS", 2 * ZONE["n_entries"])
    monkeypatch.setattr(progress_module, "LOG_INTERVAL", 0.0)
    with logged(tmp_path / "shard.log"):
        chunked = positioning_grid(**GRID, **ZONE)
    moving = int(quiet.moving.sum())
    assert moving > 2
    lines = [line for line in (tmp_path / "shard.log").read_text().splitlines() if "positioning grid" in line]
    assert len(lines) == -(-moving // 2) + 1
    assert f"{moving}/{moving} settings (100 %)" in lines[-2] and f"done: {moving}/{moving} settings" in lines[-1]
    for f in fields(quiet):
        a, b = getattr(quiet, f.name), getattr(chunked, f.name)
        assert np.asarray(a).tobytes() == np.asarray(b).tobytes(), f.name


def test_bisection_reports_each_period_map_and_keeps_its_result(monkeypatch, caplog):
    """The simulated steady state of a map reports every bisection step (about 2 + log2(1/rtol)
    of them) and gives the same bits as without reports."""
    quiet = three_phase_simulated_steady_state(1.0, 0.084, GRID["y2"], GRID["y3"], progress="quiet")
    caplog.set_level(logging.INFO, logger="selfalign.progress")
    monkeypatch.setattr(progress_module, "LOG_INTERVAL", 0.0)
    logged_run = three_phase_simulated_steady_state(1.0, 0.084, GRID["y2"], GRID["y3"], progress="log")
    lines = progress_lines(caplog)
    steps = int(np.nanmax(quiet.periods))
    assert len(lines) == steps + 1 and "members bracketing" in lines[-2]
    assert np.asarray(quiet.vbar).tobytes() == np.asarray(logged_run.vbar).tobytes()


def test_sqp_calls_back_after_every_iteration():
    """minimise's callback sees every accepted iterate and its value: the values it receives are
    the history after the start, in order."""
    seen = []
    result = minimise(lambda x: float(np.sum((x - 3.0) ** 2)), lambda x: 2.0 * (x - 3.0), np.zeros(2),
                      np.eye(2), np.array([1.0, 2.0]), first_step=0.5, min_step=1e-12, max_iter=20,
                      callback=lambda x, f: seen.append(f))
    assert result.iterations > 1
    assert seen == result.history[1:].tolist()


def test_fourier_optimisation_logs_each_iteration_with_its_f(monkeypatch, caplog):
    """The Fig. 6 optimisation logs one line per SQP iteration whose f is the one it records in
    history_f after that iteration, then a final line."""
    caplog.set_level(logging.INFO, logger="selfalign.progress")
    monkeypatch.setattr(progress_module, "LOG_INTERVAL", 0.0)
    opt = optimise_fourier(0.072, 0.021, 3.2, 1275.0, order=3, max_iter=3, progress="log")
    lines = progress_lines(caplog)
    assert len(lines) == opt.iterations + 1
    assert [line.rsplit("f = ", 1)[1] for line in lines[:-1]] == [f"{f:.6g}" for f in opt.history_f[1:]]


def test_accuracy_study_reports_every_run(monkeypatch, caplog):
    """The accuracy study logs one line per timed run (exact, each Moreau step, each ivp
    tolerance, the event-log run) and a final count equal to their number."""
    settings = StudySettings(moreau_steps_per_period=(10, 100, 3), ivp_rtol=(1e-3, 1e-4, 2),
                             fit_min_steps_per_period=10, min_timing=1e-9)
    caplog.set_level(logging.INFO, logger="selfalign.progress")
    monkeypatch.setattr(progress_module, "LOG_INTERVAL", 0.0)
    scene = Scene(ThreePhaseProfile(1.05, 0.084, 2.2, 0.9), periods=2)
    study(scene, settings)
    runs = 2 + settings.steps_per_period().size + settings.rtols().size
    lines = progress_lines(caplog)
    assert len(lines) == runs + 1
    assert "Moreau h = dt/10" in lines[1] and f"done: {runs}/{runs} runs" in lines[-1]
