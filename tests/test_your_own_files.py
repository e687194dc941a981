"""A user's own GNSS and truth files, as they are (docs/how-to/your-own-files.md):
``memsnav simulate``'s outputs navigated against their own truth, the
``[truth]`` and ``[gnss]`` reading keys and their errors, and the foreign
drive (``examples/foreign_drive.toml``) checked against a computation of
its own from the CSVs."""

from __future__ import annotations

import json
import re
from pathlib import Path

import foreign_drive_datum as datum
import numpy as np
import pytest
from figures import figures
from run_record import check_run
from shared_data import data_root, shared_data

import memsnav as mn
from memsnav.realdata.readers import UNIX_TO_GPS_S
from memsnav.simulate import simulate

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "foreign_drive.toml"

# --- memsnav simulate's files as inputs --------------------------------------

SIMULATED = """
name = "{name}"
output = "{out}"
[imu]
file = "{imu}"
accel_unit = "m/s^2"
gyro_unit = "rad/s"
time_unit = "s"
time_reference = "column_gps"
[imu.columns]
t = "gps_time_s"
ax = "accel_x_m_s2"
ay = "accel_y_m_s2"
az = "accel_z_m_s2"
gx = "gyro_x_rad_s"
gy = "gyro_y_rad_s"
gz = "gyro_z_rad_s"
[gnss]
{gnss}
[truth]
pos = "{truth}"
[report]
html = false
"""


@pytest.fixture(scope="module")
def simulation(tmp_path_factory) -> tuple[Path, object]:
    folder = tmp_path_factory.mktemp("simulation")
    return folder, simulate(folder / "sim", duration=120.0, seed=3)


def _navigate(folder: Path, files, name: str, gnss: str) -> mn.LogNavigationResult:
    cfg = folder / f"{name}.toml"
    cfg.write_text(
        SIMULATED.format(
            name=name, out=folder / name, imu=files.imu, gnss=gnss, truth=files.trajectory
        )
    )
    return mn.navigate(cfg)


def test_the_simulated_trajectory_reads_as_the_truth_it_is(simulation):
    """trajectory.csv through the fixes CSV reader, as it is, against the
    trajectory drawn again from the seed simulation.json records: the
    positions, the attitude and the GPS times of gnss.csv."""
    _, files = simulation
    truth = mn.read_fixes_csv(files.trajectory)
    meta = json.loads(files.metadata.read_text())
    drawn = mn.Trajectory.random(
        duration=120.0, rate=100.0, seed=meta["derived_seeds"]["trajectory"]
    )
    np.testing.assert_allclose(
        mn.geodetic_to_ecef(truth.lla), drawn.position_ecef, rtol=0, atol=1e-4
    )
    roll, pitch, yaw = drawn.euler_ned()[500]
    # C_b^n of the z-y-x angles, written out (Groves eq. 2.22 transposed).
    cr, sr, cp, sp, cy, sy = (np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch),
                              np.cos(yaw), np.sin(yaw))  # fmt: skip
    c_b_n = np.array(
        [
            [cp * cy, -cr * sy + sr * sp * cy, sr * sy + cr * sp * cy],
            [cp * sy, cr * cy + sr * sp * sy, -sr * cy + cr * sp * sy],
            [-sp, sr * cp, cr * cp],
        ]
    )
    np.testing.assert_allclose(truth.attitude[500], c_b_n, atol=1e-9)
    gnss = np.loadtxt(files.gnss, delimiter=",", skiprows=1)
    offset = gnss[0, 1] - gnss[0, 0]
    np.testing.assert_allclose(truth.gps_time, drawn.time + offset, rtol=0, atol=1e-9)
    assert meta["start_gps_time_s"] == pytest.approx(offset)
    assert set(truth.quality.tolist()) == {1}
    assert np.isnan(truth.std_ned).all()


def test_simulate_then_navigate_against_its_own_truth(simulation):
    """The round trip: simulate, then navigate its imu.csv and gnss.csv
    (tight) with its trajectory.csv as the truth, from a configuration and
    no edited file. The scores read through the file are those against the
    trajectory drawn again in memory (to the file's digits), and small: the
    simulated 3 m pseudorange noise, not a misread time or frame."""
    folder, files = simulation
    result = _navigate(folder, files, "tight", f'mode = "tight"\ntable = "{files.gnss}"')
    meta = json.loads(files.metadata.read_text())
    drawn = mn.Trajectory.random(
        duration=120.0, rate=100.0, seed=meta["derived_seeds"]["trajectory"]
    )
    exact = result.run.score(drawn.time + meta["start_gps_time_s"], drawn.position_ecef)
    read = result.summary["errors_vs_truth"]["all"]
    assert read["epochs"] == exact["all"]["epochs"] > 11_000
    assert read["rms_horizontal_m"] == pytest.approx(exact["all"]["rms_horizontal_m"], abs=1e-4)
    assert read["rms_vertical_m"] == pytest.approx(exact["all"]["rms_vertical_m"], abs=1e-4)
    # Measured 0.54 m horizontal, 1.9 m vertical; a second of time off at
    # the drive's 10-20 m/s would be ten metres and more.
    assert read["rms_horizontal_m"] < 1.5 and read["rms_vertical_m"] < 4.0
    assert result.summary["truth"]["name"] == "trajectory.csv"


def test_the_noise_free_truth_as_fixes_scores_near_zero(simulation):
    """trajectory.csv is also loose coupling's input once noise plays a
    receiver (the file has no σ: the noise is the fixes' σ): 1 cm of noise
    at its 1 Hz grid, scored against the same noise-free truth. Measured
    1.1 cm horizontal, 0.8 cm vertical; the fixes alone 1.4 cm."""
    folder, files = simulation
    gnss = (
        f'mode = "loose"\npos = "{files.trajectory}"\nrate_hz = 1.0\n'
        "position_noise_m = [0.01, 0.01, 0.01]\nquality = [1]"
    )
    result = _navigate(folder, files, "loose", gnss)
    scored = result.summary["errors_vs_truth"]["all"]
    assert scored["rms_horizontal_m"] < 0.03 and scored["rms_vertical_m"] < 0.03
    fixes = result.summary["gnss_errors_vs_truth"]
    # 1 cm per axis: a horizontal RMS of √2 cm, a vertical one of 1 cm.
    assert fixes["rms_horizontal_m"] == pytest.approx(0.01 * np.sqrt(2), rel=0.15)
    assert fixes["rms_vertical_m"] == pytest.approx(0.01, rel=0.15)
    # Without the noise the σ-less file cannot weight its fixes.
    with pytest.raises(ValueError, match=r"gnss.pos: .*trajectory.csv gives no position σ"):
        _navigate(
            folder, files, "exact", f'mode = "loose"\npos = "{files.trajectory}"\nquality = [1]'
        )


# --- the reading keys ----------------------------------------------------------

FIXES = """time,lat,lon,h,sn,se,sd
{rows}"""


def _own_files(folder: Path) -> tuple[Path, Path]:
    """A drive north at 10 m/s, 60 s: fixes (own names, Unix-like GPS
    seconds) and a truth with a quaternion, both on a tenth of a second."""
    t = 1.7e9 + np.arange(0.0, 60.0, 0.1)
    lat = np.radians(40.0) + 10.0 * (t - t[0]) / 6.37e6
    fixes = folder / "own_fixes.csv"
    fixes.write_text(
        "time,lat,lon,h,sn,se,sd\n"
        + "".join(
            f"{ti:.3f},{np.degrees(la):.9f},-105.0,1600.0,1,1,2\n"
            for ti, la in zip(t, lat, strict=True)
        )
    )
    truth = folder / "own_truth.csv"
    truth.write_text(
        "time_s,lat_deg,lon_deg,height_m,qw,qx,qy,qz\n"
        + "".join(
            f"{ti:.3f},{np.degrees(la):.9f},-105.0,1600.0,1,0,0,0\n"
            for ti, la in zip(t, lat, strict=True)
        )
    )
    return fixes, truth


def test_own_columns_and_time_reference_read_from_a_configuration(tmp_path):
    """[gnss]/[truth] columns and time_reference reach the reader: the same
    epochs as the file written in memsnav's names on GPS time since 1980."""
    from memsnav.realdata.pipeline import read_solution, read_truth

    fixes, truth = _own_files(tmp_path)
    cfg = tmp_path / "own.toml"
    cfg.write_text(
        f"""name = "own"
[imu]
file = "imu.csv"
accel_unit = "g"
gyro_unit = "deg/s"
time_unit = "s"
[gnss]
mode = "loose"
pos = "{fixes}"
quality = [5]
time_reference = "column_unix_gpst"
[gnss.columns]
gps_time_s = "time"
lat_deg = "lat"
lon_deg = "lon"
height_m = "h"
std_n_m = "sn"
std_e_m = "se"
std_d_m = "sd"
[truth]
pos = "{truth}"
quality = [5]
time_reference = "column_unix_gpst"
lever_arm_m = [-2.0, 0.0, 0.0]
[truth.columns]
gps_time_s = "time_s"
"""
    )
    config = mn.load_config(cfg, tmp_path)
    solution, keep, _ = read_solution(config, "gnss")
    assert keep.all() and len(solution) == 600
    assert solution.gps_time[0] == pytest.approx(1.7e9 - 315_964_800.0, abs=1e-6)
    np.testing.assert_allclose(solution.std_ned[0], [1.0, 1.0, 2.0])
    read = read_truth(config)
    assert read is not None and read.name == "own_truth.csv"
    # Level and heading north (qw = 1): the antenna 2 m behind is 2 m south.
    moved = read.position_ecef()
    at_point = mn.geodetic_to_ecef(read.geodetic)
    np.testing.assert_allclose(mn.ecef_to_ned(moved[0], at_point[0]), [-2.0, 0.0, 0.0], atol=1e-6)


@pytest.mark.parametrize(
    ("replace", "message"),
    [
        # A misspelled memsnav name: the key and the name meant.
        (
            ('gps_time_s = "time_s"', 'gps_time = "time_s"'),
            r'truth.columns: unknown key "gps_time" \(did you mean "gps_time_s"\?\)',
        ),
        # A header name the file lacks: the file, its header line, the column meant.
        (
            ('gps_time_s = "time_s"', 'gps_time_s = "times"'),
            r'own_truth.csv:1: columns.gps_time_s: the header has no column "times" '
            r'\(did you mean "time_s"\?\)',
        ),
        (
            ('time_reference = "column_unix_gpst"\nlever', 'time_reference = "unix"\nlever'),
            r"truth.time_reference: must be one of \['column_gps', 'column_unix_gpst'\]",
        ),
        (
            ("lever_arm_m = [-2.0, 0.0, 0.0]", "lever_arm_m = [-2.0, 0.0]"),
            r"truth.lever_arm_m: must be a list of 3 entries",
        ),
        (
            ("lever_arm_m = [-2.0, 0.0, 0.0]", 'offset_ned_m = "from_fixes"'),
            r"truth.offset_ned_m: must be a list or one of \['from_gnss'\], got 'from_fixes'",
        ),
        (
            ("lever_arm_m = [-2.0, 0.0, 0.0]", "offset_ned_m = [0.0, 1.0]"),
            r"truth.offset_ned_m: must be a list of 3 entries",
        ),
    ],
)
def test_truth_key_errors_name_the_key(tmp_path, replace: tuple[str, str], message: str):
    _, truth = _own_files(tmp_path)
    text = f"""name = "own"
[imu]
file = "imu.csv"
accel_unit = "g"
gyro_unit = "deg/s"
time_unit = "s"
[gnss]
mode = "loose"
pos = "x.pos"
[truth]
pos = "{truth}"
quality = [5]
time_reference = "column_unix_gpst"
lever_arm_m = [-2.0, 0.0, 0.0]
[truth.columns]
gps_time_s = "time_s"
"""
    assert replace[0] in text
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text.replace(*replace))
    from memsnav.realdata.pipeline import read_truth

    with pytest.raises(ValueError, match=message):
        read_truth(mn.load_config(cfg, tmp_path))


def test_a_lever_arm_needs_the_truths_attitude(tmp_path):
    """A truth without attitude columns and a lever arm: an error naming the
    key and the file; the columns for a file that is not a CSV: likewise."""
    from memsnav.realdata.pipeline import read_truth

    fixes, _ = _own_files(tmp_path)
    base = f"""name = "own"
[imu]
file = "imu.csv"
accel_unit = "g"
gyro_unit = "deg/s"
time_unit = "s"
[gnss]
mode = "loose"
pos = "x.pos"
[truth]
pos = "{fixes}"
quality = [5]
time_reference = "column_unix_gpst"
lever_arm_m = [-2.0, 0.0, 0.0]
[truth.columns]
gps_time_s = "time"
lat_deg = "lat"
lon_deg = "lon"
height_m = "h"
"""
    cfg = tmp_path / "no_attitude.toml"
    cfg.write_text(base)
    with pytest.raises(ValueError, match=r"truth.lever_arm_m: .*own_fixes.csv gives no attitude"):
        read_truth(mn.load_config(cfg, tmp_path))
    cfg.write_text(base.replace("quality = [5]", 'quality = [5]\nformat = "nmea"'))
    with pytest.raises(ValueError, match=r"truth.columns: only a fixes CSV .* is read as 'nmea'"):
        read_truth(mn.load_config(cfg, tmp_path))


@pytest.mark.parametrize(
    ("tables", "message"),
    [
        (
            '[gnss]\nmode = "tight"\ntable = "t.csv"\ntime_reference = "column_unix_gpst"\n',
            r"gnss.time_reference: it applies to loose coupling\'s fixes \(gnss.pos\); gnss.mode "
            r'is "tight"',
        ),
        (
            '[gnss]\nmode = "loose"\npos = "f.csv"\n[truth]\noffset_ned_m = "from_gnss"\n',
            r"truth.offset_ned_m: it applies to a truth file \(truth.pos\), which is not given",
        ),
    ],
)
def test_reading_keys_where_nothing_is_read_are_errors(tmp_path, tables: str, message: str):
    """A key that says how to read a file no run reads is refused, naming
    it (not ignored: a silent omission looks like a setting that works)."""
    cfg = tmp_path / "c.toml"
    cfg.write_text(
        'name = "x"\n[imu]\nfile = "i.csv"\naccel_unit = "g"\ngyro_unit = "deg/s"\n'
        f'time_unit = "s"\n{tables}'
    )
    with pytest.raises(ValueError, match=message):
        mn.load_config(cfg, tmp_path)


def test_truth_at_point_checks_its_arguments():
    """Bad input names its argument: a lever arm without an attitude, a
    non-finite epoch, an attitude of another length, a lever arm of two."""
    g = np.array([[0.7, -1.8, 100.0], [0.7, -1.8, 101.0]])
    level = np.tile(np.eye(3), (2, 1, 1))
    with pytest.raises(ValueError, match=r"^lever_arm: the truth gives no attitude"):
        mn.truth_at_point(g, lever_arm=[1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^geodetic"):
        mn.truth_at_point(np.array([[0.7, np.nan, 100.0]]))
    with pytest.raises(ValueError, match=r"^attitude"):
        mn.truth_at_point(g, level[:1], lever_arm=[1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^lever_arm"):
        mn.truth_at_point(g, level, lever_arm=[1.0, 0.0])
    # No lever arm and no offset: the truth's own positions.
    np.testing.assert_allclose(mn.truth_at_point(g), mn.geodetic_to_ecef(g), rtol=0, atol=1e-9)


# --- the foreign drive ---------------------------------------------------------


# WGS 84 (NIMA TR8350.2): the test's own geodetic-to-ECEF.
def test_the_insd_attitude_follows_its_course():
    """The INS-D's quaternion read as body to NED, scalar first: its yaw
    is its course over ground wherever the car drives faster than 5 m/s
    (median difference measured 0.2°; a conjugated quaternion, yaw the
    wrong way round, would be off by twice the heading)."""
    reference = shared_data("foreign-drive/insd_reference.csv")
    truth = mn.read_fixes_csv(
        reference, {"gps_time_s": "time_s"}, time_reference="column_unix_gpst"
    )
    assert len(truth) == 12_908 and truth.attitude is not None
    c = np.asarray(truth.attitude)
    v = np.asarray(truth.velocity_ned)
    moving = np.hypot(v[:, 0], v[:, 1]) > 5.0
    assert moving.sum() > 5_000
    yaw = np.arctan2(c[moving, 1, 0], c[moving, 0, 0])
    course = np.arctan2(v[moving, 1], v[moving, 0])
    difference = np.degrees(np.angle(np.exp(1j * (yaw - course))))
    assert np.median(np.abs(difference)) < 1.0


@pytest.fixture(scope="module")
def foreign_drive(tmp_path_factory) -> mn.LogNavigationResult:
    shared_data("foreign-drive/vn100_imu.csv")
    out = tmp_path_factory.mktemp("foreign") / "out"
    return mn.navigate(EXAMPLE, data_root=data_root(), output=out)


@pytest.mark.slow
def test_foreign_drive_runs_from_its_files_as_they_are(foreign_drive):
    """examples/foreign_drive.toml on the whole drive (18 s): the datum
    offset it estimates and the fixes' own score against the moved truth
    are the test's own computation from the CSVs (to a millimetre), what
    the data README says (the fixes about 1 m west of and below the
    reference; about 1.0 m horizontal RMS), and what docs/how-to/your-own-files.md
    quotes; and the truth is named as the configuration names it."""
    summary = foreign_drive.summary
    folder = shared_data("foreign-drive")
    start = summary["start_gps_time_s"] + UNIX_TO_GPS_S
    span = (start, start + summary["duration_s"])
    mine = datum.independent(folder, span, datum.LEVER_ARM_M)
    truth = summary["truth"]
    offset = np.asarray(truth["datum_offset"]["ned_m"])
    assert truth["datum_offset"]["source"] == "from_gnss"
    assert truth["datum_offset"]["gnss_epochs"] == len(mine["errors"])
    np.testing.assert_allclose(offset, mine["offset"], atol=1e-3)
    north, east, down = offset
    assert abs(north) < 0.3 and -1.3 < east < -0.5 and 0.5 < down < 2.0
    fixes = summary["gnss_errors_vs_truth"]
    horizontal, vertical = datum.rms(mine["less_offset"])
    assert fixes["rms_horizontal_m"] == pytest.approx(horizontal, abs=1e-3)
    assert fixes["rms_vertical_m"] == pytest.approx(vertical, abs=1e-3)
    assert 0.9 < fixes["rms_horizontal_m"] < 1.1
    # docs/how-to/your-own-files.md shows the record: within the digits it
    # shows (the offset to the cm, RMS to the cm, the count exactly). Left
    # at the INS-D's point, the truth blames the receiver for the 2.2 m.
    fresh, recorded = datum.figures_of(summary, folder), figures("foreign_drive")
    assert fresh["fixes"] == recorded["fixes"]
    np.testing.assert_allclose(
        fresh["datum_offset_ned_m"], recorded["datum_offset_ned_m"], atol=0.005
    )
    for key in ("fixes_rms_horizontal_m", "fixes_rms_vertical_m", "unmoved_rms_horizontal_m"):
        assert abs(fresh[key] - recorded[key]) <= 0.005, key
    assert fresh["unmoved_rms_horizontal_m"] > 1.5 * fresh["fixes_rms_horizontal_m"]
    assert truth["name"].startswith("INS-D reference")
    assert truth["lever_arm_m"] == [-2.2, 0.0, 0.0] and truth["attitude"]
    # The filter ran with the engine's defaults: not diverged, scored.
    assert not summary["diverged"] and summary["errors_vs_truth"]["aided"]["epochs"] > 10_000
    # The page's text (its figures' base64 left out): the truth by its name.
    report = re.sub(r"base64,[A-Za-z0-9+/=]+", "", Path(foreign_drive.files["report"]).read_text())
    assert f"against the truth: {truth['name']}, moved to the antenna" in report
    assert "RTK" not in report.replace("RTKLIB", "")


def test_the_antenna_regression_recovers_a_lever_arm_and_a_latency():
    """docs/foreign_drive_datum.py's regression on errors made from a known
    datum offset, lever arm and latency over a track that turns and
    changes speed: it returns them (exact data, exact answer)."""
    rng = np.random.default_rng(5)
    heading = np.cumsum(rng.normal(0.0, 0.2, 400))
    forward = np.column_stack([np.cos(heading), np.sin(heading), np.zeros(400)])
    speed = 10.0 + 5.0 * np.sin(np.linspace(0.0, 12.0, 400))
    velocity = speed[:, None] * forward
    datum_m, lever_m, latency_s = np.array([0.3, -0.8, 1.6]), -2.2, 0.09
    errors = datum_m + lever_m * forward - latency_s * velocity
    joint = datum._antenna_regression(errors, forward, velocity)
    assert np.allclose(joint, [*datum_m, lever_m, latency_s], atol=1e-9)
    alone = datum._antenna_regression(errors, forward, None)
    # Without the latency term its along-track part lands on the lever
    # arm: the mean speed's worth of latency.
    assert alone[3] == pytest.approx(lever_m - latency_s * speed.mean(), abs=0.05)


def test_what_the_foreign_drive_files_show_is_the_record():
    """The foreign drive's files measured with numpy alone (~5 s), against
    the record the results page shows, to its digits; the receiver's σ at
    rest is the optimistic one, and the gyro's rest rate is steady."""
    shared_data("foreign-drive/vn100_imu.csv")
    fresh = check_run("foreign_drive_files", 0.005, needs_data=True)
    assert fresh["rest_east_sigma_m"] < 0.5 * fresh["rest_east_error_rms_m"]
    rest = fresh["gyro_rest_deg_s"]
    assert rest["spread"] < 0.3 * min(abs(v) for v in rest["mean"])
