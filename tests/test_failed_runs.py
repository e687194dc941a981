"""A ``navigate`` run that fails still reports (docs/how-to/when-a-run-fails.md, "When a
run fails"): whatever goes wrong once its output folder is accepted (an
input, the start, a filter that leaves the range of a solution or
diverges, a gyro unit the GNSS course contradicts, the report), the folder
gets ``summary.json`` with a ``failure`` entry and ``report.html`` naming
it, with what was computed before; the command exits non-zero naming the
failure and the report; an earlier run's outputs never stay behind looking
current. And the gyro's unit is checked against the GNSS course on every
IMU log of the shared data, with both unit mistakes."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import page_measurements
import pytest
from figures import figures
from record_agreement import agree
from shared_data import shared_data
from test_navigate import DATA, EX, _config

import memsnav as mn
from memsnav import cli
from memsnav._files import MARKER
from memsnav.realdata import readers

DEG = float(np.degrees(1.0))


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


def _run_cli(cfg: Path, capsys, *more: str) -> tuple[int, str, str]:
    with warnings.catch_warnings():
        # The reader's and the run's warnings are checked in the summary.
        warnings.simplefilter("ignore")
        code = cli.main(["navigate", "--config", str(cfg), "--data-root", str(DATA), *more])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# --- a wrong gyro unit ------------------------------------------------------


def test_deg_s_data_read_as_rad_s_fails_with_the_hint(tmp_path, capsys):
    """The drive excerpt's gyro (°/s) declared as rad/s: the run is made
    and written, the failure names gyro_unit and "deg/s", the reader's own
    hint is among the hints, and the command says where the report is."""
    cfg = _config(tmp_path, **{'gyro_unit = "deg/s"': 'gyro_unit = "rad/s"'})
    code, out, err = _run_cli(cfg, capsys)
    assert code == 1
    folder = tmp_path / "out"
    summary = _summary(folder)
    failure = summary["failure"]
    assert failure["stage"] == "units"
    assert failure["message"].startswith("gyro_unit: ")
    assert 'is gyro_unit "deg/s"' in failure["message"]
    # The reader's plausibility warning (rates above 573 °/s) is a hint.
    assert any("drive_60s.csv: gyro_unit" in h for h in failure["hints"])
    # What was computed is there: the whole run, its files, its figures.
    assert summary["imu_samples"] > 6000 and (folder / "drive_60s.pos").exists()
    ratio = summary["gyro_scale"]["ratio"]
    assert abs(ratio / DEG - 1.0) < 0.1, ratio
    report = (folder / "report.html").read_text()
    assert "The run failed" in report and "is gyro_unit &quot;deg/s&quot;" in report
    assert report.index("The run failed") < report.index("The answer")
    # The terminal: the answer names the failure; the error names it and
    # where the report is.
    assert "FAILED (units)" in out.splitlines()[1]
    assert "memsnav: error: FAILED (units)" in err and str(folder / "report.html") in err


def _imu_in_rad_s(tmp_path: Path) -> Path:
    """The drive excerpt's IMU as a CSV in g and rad/s on GPS time (the
    time tag applied): a log whose gyro is in rad/s."""
    log = readers.read_imu_csv(EX / "drive_60s.csv", accel_unit="g", gyro_unit="deg/s")
    t, _ = readers.gps_time_from_tag(log, readers.read_time_tag(EX / "drive_60s.csv.tag"))
    table = np.column_stack([t, log.specific_force / 9.80665, log.angular_rate])
    path = tmp_path / "imu_rad_s.csv"
    np.savetxt(path, table, delimiter=",", fmt="%.9f", header="t,ax,ay,az,gx,gy,gz", comments="")
    return path


@pytest.mark.slow
def test_rad_s_data_read_as_deg_s_fails_with_the_hint(tmp_path, capsys):
    """The user's case: a gyro in rad/s declared as deg/s, where no IMU-only
    check can tell (the rates are small, not absurd): the GNSS course can."""
    imu = _imu_in_rad_s(tmp_path)
    cfg = _config(
        tmp_path,
        **{
            'file = "real-imu-gnss/drive_60s.csv"': f'file = "{imu}"\ncolumns = {{'
            't = "t", ax = "ax", ay = "ay", az = "az", gx = "gx", gy = "gy", gz = "gz"}',
            'time_unit = "ms"': 'time_unit = "s"\ntime_reference = "column_gps"',
            'time_tag = "real-imu-gnss/drive_60s.csv.tag"\n': "",
        },
    )
    # Read as declared in its right unit, the same log passes.
    right = cfg.read_text().replace('gyro_unit = "deg/s"', 'gyro_unit = "rad/s"')
    (tmp_path / "right.toml").write_text(right.replace(str(tmp_path / "out"), "right"))
    # (The check takes the whole log whatever the run's duration.)
    result = mn.navigate(tmp_path / "right.toml", data_root=DATA, duration_s=5.0)
    assert result.failure is None and abs(result.summary["gyro_scale"]["ratio"] - 1) < 0.1
    code, _, err = _run_cli(cfg, capsys, "--duration", "5")
    assert code == 1
    failure = _summary(tmp_path / "out")["failure"]
    assert failure["stage"] == "units"
    assert (
        'the angular rates look like radians read as degrees: is gyro_unit "rad/s"'
        in (failure["message"])
    )
    assert 'is gyro_unit "rad/s"' in err
    # The Python API raises the error, with the written result.
    with pytest.raises(ValueError, match=r"run\.toml: imu\.gyro_unit: the gyro turns") as caught:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mn.navigate(cfg, data_root=DATA, duration_s=5.0)
    written = caught.value.result  # type: ignore[attr-defined]
    assert written.failure["stage"] == "units" and Path(written.files["report"]).exists()


# --- what goes wrong, and what is kept ---------------------------------------


def _falling_log(tmp_path: Path) -> tuple[Path, float]:
    """A simulated drive written as the user's files (IMU CSV on GPS time,
    fixes CSV): 20 s at rest, then driving; GNSS out from 50 s after the
    start; from 70 s of the log the accelerometer's z axis reads 60 m/s²
    too much (a failed sensor), so the coasting solution falls through the
    Earth. Returns the configuration and the time of the fault."""
    trajectory = mn.Trajectory.random(110.0, seed=4, stationary_start=20.0)
    t0 = 1.4e9
    t = trajectory.time + t0
    f = trajectory.specific_force.copy()
    fault = t0 + 70.0
    f[t >= fault, 2] += 60.0
    imu = np.column_stack([t, f, trajectory.angular_rate])
    np.savetxt(
        tmp_path / "imu.csv",
        imu,
        delimiter=",",
        fmt="%.9f",
        header="t,ax,ay,az,gx,gy,gz",
        comments="",
    )
    k = np.arange(0, len(t), 100)
    lla = trajectory.position_geodetic()[k]
    v = trajectory.velocity_ned()[k]
    fixes = np.column_stack(
        [
            t[k],
            np.degrees(lla[:, 0]),
            np.degrees(lla[:, 1]),
            lla[:, 2],
            np.full((len(k), 3), 0.5),
            v,
            np.full((len(k), 3), 0.05),
        ]
    )
    header = (
        "gps_time_s,lat_deg,lon_deg,height_m,std_n_m,std_e_m,std_d_m,vn_m_s,ve_m_s,vd_m_s,"
        "std_vn_m_s,std_ve_m_s,std_vd_m_s"
    )
    np.savetxt(
        tmp_path / "fixes.csv", fixes, delimiter=",", fmt="%.10f", header=header, comments=""
    )
    config = tmp_path / "falling.toml"
    config.write_text(
        'name = "falling"\noutput = "out"\n'
        '[imu]\nfile = "imu.csv"\n'
        'columns = {t = "t", ax = "ax", ay = "ay", az = "az", gx = "gx", gy = "gy", gz = "gz"}\n'
        'accel_unit = "m/s^2"\ngyro_unit = "rad/s"\ntime_unit = "s"\n'
        'time_reference = "column_gps"\n'
        '[gnss]\nmode = "loose"\npos = "fixes.csv"\nquality = [5]\n'
        "[outages]\nwindows_s = [[50.0, 55.0]]\n"
    )
    return config, fault


def test_a_state_beyond_a_solution_stops_the_run_and_keeps_what_it_computed(tmp_path, capsys):
    """The coasting solution falls below −10 km: the run stops at that
    sample (a solution file cannot hold it: the .pos writer refused such a
    height), the solution up to it is written and readable, the summary
    and the report say what stopped where, and the command exits 1."""
    cfg, fault = _falling_log(tmp_path)
    code, _, err = _run_cli(cfg, capsys)
    assert code == 1, err
    folder = tmp_path / "out"
    summary = _summary(folder)
    failure = summary["failure"]
    assert failure["stage"] == "run"
    assert "height" in failure["message"] and "-1e4" in failure["message"]
    # 60 m/s² of fall from the fault: −10 km within 20 s of it (½ a t²).
    assert fault < failure["gps_time_s"] < fault + 20.0
    assert failure["time_s"] == pytest.approx(failure["gps_time_s"] - summary["start_gps_time_s"])
    pos = mn.read_pos(folder / "falling.pos")
    csv = np.loadtxt(folder / "falling.csv", delimiter=",", skiprows=1)
    assert csv[-1, 0] < failure["gps_time_s"] and pos.gps_time[-1] <= csv[-1, 0] + 1e-6
    assert np.all(csv[:, 3] > -1e4)  # every row a writer takes
    report = (folder / "report.html").read_text()
    assert "The run failed" in report and "up to where it stopped" in report
    assert "FAILED (run," in err


def test_navigate_log_returns_what_it_computed_when_it_stops(tmp_path):
    """The engine's face: a run that stops returns its solution up to the
    last sample before the failure, with ``failure``, and warns."""
    _, fault = _falling_log(tmp_path)
    log = readers.read_imu_csv(
        tmp_path / "imu.csv",
        {k: k for k in ("t", "ax", "ay", "az", "gx", "gy", "gz")},
        accel_unit="m/s^2",
        gyro_unit="rad/s",
        time_unit="s",
    )
    fixes_log = mn.read_fixes_csv(tmp_path / "fixes.csv")
    fixes = mn.fixes_from_solution(
        fixes_log.gps_time,
        fixes_log.lla,
        fixes_log.std_ned,
        velocity_ned=fixes_log.velocity_ned,
        velocity_std_ned=fixes_log.velocity_std_ned,
    )
    settings = {"outages": {"windows_s": [[50.0, 55.0]]}}
    with pytest.warns(UserWarning, match=r"the run stopped at t = .* the state left the range"):
        run = mn.navigate_log(
            log.time, log.specific_force, log.angular_rate, fixes, settings=settings
        )
    assert run.failure is not None and fault < run.failure.time < fault + 20.0
    assert run.time[-1] < run.failure.time and len(run) > 1000
    assert np.all(np.asarray(run.geodetic)[:, 2] > -1e4)
    run.write(tmp_path / "kept.pos")  # the writer takes all of it
    assert len(mn.read_pos(tmp_path / "kept.pos").gps_time) > 100


def test_a_report_that_cannot_be_drawn_is_a_page_naming_the_failure(tmp_path, monkeypatch):
    """The report failing (here, drawing it) is a failure of the run, not
    a crash: the solution files and summary.json are written, report.html
    is a plain page naming what failed."""
    from memsnav.realdata import report

    def broken(result, out):
        raise RuntimeError("no display")

    monkeypatch.setattr(report, "write_report", broken)
    with pytest.raises(RuntimeError, match="no display") as caught:
        mn.navigate(_config(tmp_path), data_root=DATA, duration_s=5.0)
    folder = tmp_path / "out"
    failure = _summary(folder)["failure"]
    assert (failure["stage"], failure["message"]) == ("report", "no display")
    page = (folder / "report.html").read_text()
    assert "The run failed" in page and "drawing the report" in page and "no display" in page
    assert (folder / "drive_60s.csv").exists()
    assert caught.value.result.files["report"] == str(folder / "report.html")  # type: ignore[attr-defined]


# --- an earlier run's outputs --------------------------------------------------


@pytest.mark.slow
def test_a_failed_run_never_leaves_an_earlier_runs_outputs_looking_current(tmp_path, capsys):
    """A good run, then runs into the same folder that fail at each stage:
    reading an input (nothing computed), the units (a whole run), the
    report. Each time the folder holds that run's summary (with its
    failure) and report, and none of the earlier run's files."""
    out = tmp_path / "out"
    good = mn.navigate(_config(tmp_path), data_root=DATA, duration_s=5.0)
    assert good.failure is None and "failure" not in _summary(out)
    first = _summary(out)["processing_s"]

    missing = _config(tmp_path, **{'"real-imu-gnss/drive_60s.csv"': '"real-imu-gnss/nope.csv"'})
    code, stdout, err = _run_cli(missing, capsys)
    assert code == 1
    summary = _summary(out)
    assert summary["failure"]["stage"] == "inputs"
    assert "imu.file: no such file 'real-imu-gnss/nope.csv'" in summary["failure"]["message"]
    assert "duration_s" not in summary and summary["processing_s"] != first
    # Nothing of the good run is left: only what the failed run wrote.
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "report.html", "summary.json"]
    assert json.loads((out / MARKER).read_text())["files"] == ["report.html", "summary.json"]
    page = (out / "report.html").read_text()
    assert "The run failed" in page and "Nothing was computed" in page
    assert "FAILED (inputs)" in stdout and "memsnav: error: FAILED (inputs)" in err

    wrong = _config(tmp_path, **{'gyro_unit = "deg/s"': 'gyro_unit = "rad/s"'})
    assert _run_cli(wrong, capsys, "--duration", "5")[0] == 1
    assert _summary(out)["failure"]["stage"] == "units"
    assert (out / "drive_60s.csv").exists()

    # A good run again replaces the failed one's outputs, failure and all.
    mn.navigate(_config(tmp_path), data_root=DATA, duration_s=5.0)
    assert "failure" not in _summary(out)


def test_an_interrupt_leaves_the_folder_as_it_was(tmp_path, monkeypatch):
    """Ctrl-C is not a failure of the run: no half-written folder, the
    earlier outputs kept (the user stopped it and knows)."""
    from memsnav.realdata import pipeline

    cfg = _config(tmp_path, extra="[report]\nhtml = false\n")
    mn.navigate(cfg, data_root=DATA, duration_s=5.0)
    before = (tmp_path / "out" / "summary.json").read_text()

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(pipeline._mn, "navigate_log", interrupted)
    with pytest.raises(KeyboardInterrupt):
        mn.navigate(cfg, data_root=DATA, duration_s=5.0)
    assert (tmp_path / "out" / "summary.json").read_text() == before


# --- the gyro's unit against the GNSS course, on every log ---------------------


def test_the_gyro_unit_check_on_every_shared_log_and_both_mistakes():
    """On every IMU log of the shared data the gyro turns as much as the
    GNSS course (ratio 0.9-1.2, no warning); its rates divided by 180/π
    (radians read as degrees) or multiplied (the reverse) are named, with
    the unit they look like. The ratios and their pairs are the record
    docs/how-to/when-a-run-fails.md's table shows (``python
    docs/doc_runs.py gyro_scale_logs``), within the digits it shows."""
    shared_data("foreign-drive/vn100_imu.csv")  # a skip naming what is missing
    checks = page_measurements.gyro_scale_checks(shared_data("real-imu-gnss").parent)
    checked = set()
    for name, by_factor in checks.items():
        for key, (factor, unit) in page_measurements.GYRO_FACTORS.items():
            result = by_factor[key]
            if result["error"] is not None:
                # A start the wrong rates spoil carries the warning.
                assert unit is not None and f"is gyro_unit {unit}" in result["error"], (
                    name,
                    result["error"],
                )
                continue
            check = result["gyro_scale"]
            assert check is not None and check["conclusive"], (name, check)
            checked.add(name)
            if unit is None:
                assert 0.9 < check["ratio"] < 1.2, (name, check)
                assert check["warning"] is None and result["warnings"] == [], (name, result)
            else:
                assert abs(np.log(check["ratio"] / factor)) < np.log(1.2), (name, check)
                assert f"is gyro_unit {unit}" in check["warning"], (name, check)
                assert any(f"is gyro_unit {unit}" in m for m in result["warnings"]), name
    assert len(checked) == 4
    # The table shows the ratios to two figures, the divided rates' to
    # three, the multiplied rates' to the unit; the pairs exactly.
    tolerance = {
        "as_given": {"ratio": 0.005, "pairs": 0},
        "divided": {"ratio": 5e-4, "pairs": 0},
        "multiplied": {"ratio": 0.5, "pairs": 0},
    }
    fresh = page_measurements.gyro_scale_figures(checks)
    differ = agree(fresh, figures("gyro_scale_logs"), tolerance, "gyro_scale_logs")
    assert not differ, f"{differ}: rerun python docs/doc_runs.py gyro_scale_logs if this is meant"
