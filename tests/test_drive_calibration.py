"""The paper's GNSS-reference calibration on a drive (docs/how-to/calibrate-an-imu.md,
"A drive"): the core's window references against an error-free simulated
IMU, recovery of known sensor errors within the reported σ, the
``calibrate`` drive session on drive_0708 end to end, ``[imu] calibration``
in ``navigate``, and the configuration errors."""

import contextlib
import io
import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from doc_pages import CALIBRATION_GUIDE, doc_text
from report_checks import capture_figures, page_problems
from shared_data import shared_data

import memsnav as mn
from memsnav.calibration.config import load_calibration_config
from memsnav.calibration.drive import calibrate_drive
from memsnav.cli import main

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"
# A simulated IMU does not vibrate, so the IMU standstill test cannot tell
# rest from smooth driving (the navigate guide): the simulations run
# without ZUPT and ZARU, as a vehicle with a vibration-free IMU must.
NO_STANDSTILL = {"aids": {"zupt": False, "zaru": False}}


def _drive(seed: int, accel: mn.AccelerometerModel, gyro: mn.GyroscopeModel):
    """A 600 s random drive measured by the given models, with RTK-grade
    fixes (2 cm, 5 cm/s) at 4 Hz."""
    trajectory = mn.Trajectory.random(600.0, seed=seed, stationary_start=20.0)
    t = trajectory.time
    f = accel.measure(trajectory.specific_force, seed=seed)
    w = gyro.measure(trajectory.angular_rate, trajectory.specific_force, seed=seed + 1)
    k = np.arange(0, len(t), 25)
    fixes = mn.fixes_from_solution(
        t[k],
        trajectory.position_geodetic()[k],
        np.full((len(k), 3), 0.02),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.05),
        added_position_noise_ned=[0.02, 0.02, 0.02],
        added_velocity_noise=0.05,
        seed=seed,
    )
    return t, f, w, fixes


def test_references_of_an_error_free_imu_match_its_outputs():
    zero3, zero33 = np.zeros(3), np.zeros((3, 3))
    t, f, w, fixes = _drive(
        1,
        mn.AccelerometerModel(zero3, zero3, zero33, zero3),
        mn.GyroscopeModel(zero3, zero3, zero33, zero33),
    )
    run = mn.navigate_log(t, f, w, fixes, settings={**NO_STANDSTILL, "filter": {"smoother": True}})
    refs = run.smoothed.calibration_references(t, f, w, window_s=2.0)
    assert abs(refs["window_s"] - 2.0) < 1e-9
    assert len(refs["time"]) > 250
    df = refs["measured_specific_force"] - refs["reference_specific_force"]
    dw = refs["measured_angular_rate"] - refs["reference_angular_rate"]
    # The references' mean offset is the smoothed solution's own bias
    # error, within its σ (which the references report); around it they
    # agree with the exact outputs to centimetres per second squared
    # against a car's ~1 m/s², and to a few hundredths of a degree per second.
    bias_std = np.sqrt(np.diag(refs["accel_bias_covariance"]))
    assert np.all(np.abs(df.mean(axis=0)) < 3.0 * bias_std + 1e-3), (df.mean(axis=0), bias_std)
    assert np.std(df, axis=0).max() < 0.03
    assert np.degrees(np.sqrt((dw**2).mean(axis=0))).max() < 0.05
    # The same drive from an IMU mounted yawed by 90° and rolled by 180°:
    # the references are in the sensor's axes.
    mounting = np.asarray(mn.mounting_matrix([[180.0, 0.0, 90.0]]))
    f_s, w_s = f @ mounting, w @ mounting  # rows of Mᵀ x: body = M · sensor
    settings = {**NO_STANDSTILL, "filter": {"smoother": True}}
    settings["imu"] = {"mounting_rpy_deg": [[180.0, 0.0, 90.0]]}
    rotated = mn.navigate_log(t, f_s, w_s, fixes, settings=settings)
    refs_s = rotated.smoothed.calibration_references(t, f_s, w_s, window_s=2.0)
    df_s = refs_s["measured_specific_force"] - refs_s["reference_specific_force"]
    np.testing.assert_allclose(df_s @ mounting.T, df, atol=2e-3)
    with pytest.raises(ValueError, match="time"):
        run.smoothed.calibration_references(t[1:], f[1:], w[1:])
    with pytest.raises(ValueError, match="window_s"):
        run.smoothed.calibration_references(t, f, w, window_s=0.0)


def test_smoothed_covariance_is_valid_across_the_heading_reset():
    """A static start sets the heading at the first motion (a reset of the
    heading component): the smoothed variances stay non-negative and never
    exceed the forward ones, before the reset as after it."""
    zero3, zero33 = np.zeros(3), np.zeros((3, 3))
    t, f, w, fixes = _drive(
        2,
        mn.AccelerometerModel(zero3, zero3, zero33, zero3, noise_density=0.002),
        mn.GyroscopeModel(zero3, zero3, zero33, zero33, noise_density=np.radians(0.01)),
    )
    run = mn.navigate_log(t, f, w, fixes, settings={**NO_STANDSTILL, "filter": {"smoother": True}})
    resets = run.solution.resets
    assert "heading" in [str(k) for k in resets["kind"]]
    forward = np.asarray(run.solution.covariance_diagonal)
    smoothed = np.asarray(run.smoothed.solution.covariance_diagonal)
    assert smoothed.min() >= 0.0
    assert np.all(smoothed <= forward * (1 + 1e-9) + 1e-15)
    refs = run.smoothed.calibration_references(t, f, w)
    assert refs["skipped_for_resets"] <= 1


def test_drive_calibration_recovers_known_errors_within_sigma():
    """Biases and scale factors drawn at random over three seeds: the
    estimates' z-scores against the truth. The vertical accelerometer scale
    factor is zero in the truth and not scored: a drive hardly separates it
    from the bias (the vertical specific force is g throughout; it is held
    or poorly determined)."""
    z_bias, z_scale, z_vertical = [], [], []
    for seed in range(3):
        rng = np.random.default_rng(100 + seed)
        a_bias, a_scale = rng.normal(0, 0.05, 3), rng.normal(0, 0.005, 3)
        a_scale[2] = 0.0
        g_bias, g_scale = rng.normal(0, np.radians(0.2), 3), rng.normal(0, 0.005, 3)
        accel = mn.AccelerometerModel(
            a_bias, a_scale, np.zeros((3, 3)), np.zeros(3), noise_density=0.002
        )
        gyro = mn.GyroscopeModel(
            g_bias, g_scale, np.zeros((3, 3)), np.zeros((3, 3)), noise_density=np.radians(0.01)
        )
        t, f, w, fixes = _drive(seed, accel, gyro)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cal = calibrate_drive(t, f, w, fixes, settings=NO_STANDSTILL)
        sa, sg = cal.std("accelerometer"), cal.std("gyroscope")
        z_accel = (cal.accelerometer.model.bias - a_bias) / sa.bias
        z_bias += list(z_accel[:2])
        z_vertical.append(z_accel[2])
        z_bias += list((cal.gyroscope.model.bias - g_bias) / sg.bias)
        z_scale += list(
            (cal.accelerometer.model.scale_factor[:2] - a_scale[:2]) / sa.scale_factor[:2]
        )
        z_scale += list((cal.gyroscope.model.scale_factor[2:] - g_scale[2:]) / sg.scale_factor[2:])
    z_bias, z_scale = np.array(z_bias), np.array(z_scale)
    # Measured (docs/how-to/calibrate-an-imu.md): the horizontal accelerometer and the
    # gyro biases and these scale factors are within their σ (mean z² ≈ 1-2);
    # the vertical accelerometer bias's σ is optimistic (|z| up to ~7): it
    # shares the vertical axis with the scale factor and nonlinearity.
    assert np.abs(z_bias).max() < 4.0, z_bias
    assert np.mean(z_bias**2) < 3.0, z_bias
    # docs/explanation/few-satellites.md: "its bias z-scores went back to a mean z² of
    # 0.7" (these biases, these three seeds).
    page = " ".join(doc_text("explanation/few-satellites.md").split())
    quoted = re.search(r"bias z-scores went back to a mean z² of (\d+(?:\.\d+)?)", page)
    assert quoted, "docs/explanation/few-satellites.md no longer quotes the bias z-scores"
    assert abs(np.mean(z_bias**2) - float(quoted.group(1))) <= 0.05, np.mean(z_bias**2)
    assert np.abs(z_scale).max() < 4.0, z_scale
    assert np.abs(z_vertical).max() < 10.0, z_vertical


@pytest.fixture(scope="module")
def drive_run(tmp_path_factory):
    data = shared_data("real-imu-gnss/drive_0708/imu_1934.csv").parents[2]
    out = tmp_path_factory.mktemp("drive_cal")
    printed = io.StringIO()
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(printed):
        figures = capture_figures(patch)
        code = main(
            [
                "calibrate",
                "--config",
                str(EXAMPLES / "drive_0708_calibration.toml"),
                "--data-root",
                str(data),
                "--output",
                str(out),
            ]
        )
    assert code == 0
    DRIVE_RUN.update(figures=figures, printed=printed.getvalue())
    return data, out


# What the fixture's run printed and the figures its report drew.
DRIVE_RUN: dict = {}


@pytest.mark.slow
def test_drive_session_answers_first_and_its_figures_read(drive_run):
    """The terminal opens with the outage errors raw and calibrated, the
    first outage included (a calibration from the first minutes need not
    help it); the report's figures show their data."""
    _, out = drive_run
    nav = json.loads((out / "calibration.json").read_text())["fit"]["navigation"]
    lines = DRIVE_RUN["printed"].splitlines()
    for line, (view, key) in zip(
        lines, [("forward", "after_fit"), ("forward", "first")], strict=False
    ):
        raw, cal = nav["raw"][view][key], nav["calibrated"][view][key]
        assert line.startswith(f"{view}, ")
        assert (
            f"horizontal RMS {raw['rms_horizontal_m']:.2f} -> {cal['rms_horizontal_m']:.2f} m"
            in line
        )
    assert lines.index(f"calibration: {out / 'calibration.json'}") > 4
    assert DRIVE_RUN["figures"] and not any(DRIVE_RUN["figures"].values())
    report = (out / "report.html").read_text()
    assert ">-0<" not in report and "2.00002" not in report
    # Held parameters' reasons in plain numbers (was "sigma 1.332e0 would
    # exceed its physical size 5.000e-2").
    held = mn.load_calibration(out / "calibration.json").held
    assert held and not any(re.search(r"\de[-+]?\d(?!\d)", why) for _, why in held), held
    assert not page_problems(report), page_problems(report)


@pytest.mark.slow
def test_readme_quotes_the_drive_calibration(drive_run):
    """ "changes by +8 % (1.67 → 1.81 m RMS, inside the 1.53-2.29 m of ten
    calibrations drawn [...]), and the first outage [...] gets slightly
    worse (1.45 → 1.52 m)": within their rounding."""
    _, out = drive_run
    text = " ".join((HERE.parent / "README.md").read_text().split())
    gain = re.search(r"changes by ([+−-]?\d+) % \(([\d.]+) → ([\d.]+) m RMS", text)
    first = re.search(r"gets slightly worse \(([\d.]+) → ([\d.]+) m\)", text)
    assert gain and first, "the README no longer quotes the drive calibration"
    forward = json.loads((out / "calibration.json").read_text())["fit"]["navigation"]
    raw, cal = forward["raw"]["forward"], forward["calibrated"]["forward"]
    after = raw["after_fit"]["rms_horizontal_m"], cal["after_fit"]["rms_horizontal_m"]
    change = float(gain.group(1).replace("−", "-"))
    assert abs(100 * (after[1] / after[0] - 1) - change) <= 0.5
    assert abs(after[0] - float(gain.group(2))) <= 0.005
    assert abs(after[1] - float(gain.group(3))) <= 0.005
    assert abs(raw["first"]["rms_horizontal_m"] - float(first.group(1))) <= 0.005
    assert abs(cal["first"]["rms_horizontal_m"] - float(first.group(2))) <= 0.005
    drawn = re.search(r"inside the ([\d.]+)-([\d.]+) m of (\w+) calibrations drawn", text)
    assert drawn, "the README no longer quotes the calibrations drawn from the covariance"
    draws = [d["forward"]["after_fit"]["rms_horizontal_m"] for d in forward["draws"]]
    assert abs(min(draws) - float(drawn.group(1))) <= 0.005
    assert abs(max(draws) - float(drawn.group(2))) <= 0.005
    assert drawn.group(3) == ["none", "one", "two", "three", "four", "five", "six", "seven",
                              "eight", "nine", "ten"][len(draws)]  # fmt: skip


@pytest.mark.slow
def test_the_guide_quotes_the_drive_calibration(drive_run):
    """docs/how-to/calibrate-an-imu.md's table of the outages raw and calibrated
    (RMS / max, forward and smoothed) and its range over the calibrations
    drawn from the covariance, each within its rounding."""
    _, out = drive_run
    nav = json.loads((out / "calibration.json").read_text())["fit"]["navigation"]
    page = doc_text(*CALIBRATION_GUIDE)
    for label, key in (
        ("after the calibration span (6, never seen by the fit)", "after_fit"),
        ("inside the span (5)", "in_fit"),
        ("the first one (at 35.5 s)", "first"),
    ):
        row = re.search(rf"^\| {re.escape(label)} \|(.*)$", page, re.M)
        assert row, f"docs/how-to/calibrate-an-imu.md no longer has the row {label!r}"
        quoted = [tuple(map(float, c.split(" / "))) for c in row.group(1).strip(" |").split(" | ")]
        runs = [
            nav[imu][view][key] for view in ("forward", "smoothed") for imu in ("raw", "calibrated")
        ]
        assert len(quoted) == len(runs) == 4
        for (rms, largest), run in zip(quoted, runs, strict=True):
            assert abs(run["rms_horizontal_m"] - rms) <= 0.005, (label, run, rms)
            assert abs(run["max_horizontal_m"] - largest) <= 0.005, (label, run, largest)
    text = " ".join(page.split())
    spread = re.search(
        r"the forward RMS there spans ([\d.]+)-([\d.]+) m \(median ([\d.]+) m; (\w+) of the ten "
        r"above the raw ([\d.]+) m\) and the smoothed ([\d.]+)-([\d.]+) m",
        text,
    )
    assert spread, "docs/how-to/calibrate-an-imu.md no longer quotes the drawn calibrations"
    forward = [d["forward"]["after_fit"]["rms_horizontal_m"] for d in nav["draws"]]
    smoothed = [d["smoothed"]["after_fit"]["rms_horizontal_m"] for d in nav["draws"]]
    raw = nav["raw"]["forward"]["after_fit"]["rms_horizontal_m"]
    figures = [min(forward), max(forward), float(np.median(forward))]
    figures += [raw, min(smoothed), max(smoothed)]
    quoted = [float(spread.group(k)) for k in (1, 2, 3, 5, 6, 7)]
    assert np.allclose(figures, quoted, atol=0.005), (figures, quoted)
    above = sum(v > raw for v in forward)
    words = ["none", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "all"]
    assert spread.group(4) == words[above]


@pytest.mark.slow
def test_drive_session_end_to_end(drive_run):
    _, out = drive_run
    raw = json.loads((out / "calibration.json").read_text())
    assert raw["session"] == "drive"
    assert (out / "report.html").is_file()
    cal = mn.load_calibration(out / "calibration.json")
    assert cal.identity_nominal
    # The z gyro's bias: the in-run estimate of the drive is about 0.17 °/s
    # in magnitude (the navigate guide); the calibration finds it within 0.05.
    assert 0.10 < abs(np.degrees(cal.gyroscope.bias[2])) < 0.22
    assert np.all(np.asarray(cal.gyroscope_std.bias) > 0)
    nav = raw["fit"]["navigation"]
    raw_after = nav["raw"]["forward"]["after_fit"]
    cal_after = nav["calibrated"]["forward"]["after_fit"]
    assert raw_after["outages"] == cal_after["outages"] >= 4
    # The paper's question on real data, on outages the fit never saw: the
    # calibration's effect, gain or loss, is within what its own
    # uncertainty explains (the raw run and the calibrated one both inside
    # the range of ten calibrations drawn from its covariance; since issue
    # 29 the raw filter leaves it nothing to gain: docs/how-to/calibrate-an-imu.md).
    drawn = [d["forward"]["after_fit"]["rms_horizontal_m"] for d in nav["draws"]]
    assert len(drawn) == 10
    assert min(drawn) < cal_after["rms_horizontal_m"] < max(drawn)
    assert min(drawn) < raw_after["rms_horizontal_m"] < max(drawn)


@pytest.mark.slow
def test_navigate_applies_a_drive_calibration(drive_run, tmp_path):
    data, out = drive_run
    text = (EXAMPLES / "drive_0708.toml").read_text()
    text = text.replace(
        'time_tag = "real-imu-gnss/drive_0708/imu_1934.csv.tag"',
        'time_tag = "real-imu-gnss/drive_0708/imu_1934.csv.tag"\n'
        f'calibration = "{out / "calibration.json"}"',
    )
    config = tmp_path / "drive_cal.toml"
    config.write_text(text)
    cfg = mn.load_config(config, data)
    from memsnav.realdata import pipeline

    _, f, w, _ = pipeline.read_imu(cfg)
    cfg_raw = mn.load_config(EXAMPLES / "drive_0708.toml", data)
    _, f_raw, w_raw, _ = pipeline.read_imu(cfg_raw)
    f_expected, w_expected = mn.load_calibration(out / "calibration.json").correct(f_raw, w_raw)
    np.testing.assert_allclose(f, f_expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(w, w_expected, rtol=0, atol=1e-12)
    result = mn.navigate(config, data_root=data, output=tmp_path / "nav", duration_s=60.0)
    assert result.summary["imu_calibration"] == str(out / "calibration.json")


def test_navigate_refuses_a_calibration_of_raw_counts(tmp_path):
    data = shared_data("real-imu-gnss/drive_0708/imu_1934.csv").parents[2]
    zero3, zero33 = np.zeros(3), np.zeros((3, 3))
    from memsnav.calibration.file import ImuCalibration

    cal = ImuCalibration(
        session="static-poses",
        accelerometer=mn.AccelerometerModel(zero3, zero3, zero33, zero3),
        gyroscope=mn.GyroscopeModel(zero3, zero3, zero33, zero33),
        accelerometer_std=mn.AccelerometerModel(zero3, zero3, zero33, zero3),
        gyroscope_std=mn.GyroscopeModel(zero3, zero3, zero33, zero33),
        parameter_names=["accelerometer bias_u"],
        covariance=np.zeros((1, 1)),
        nominal={
            "accel_scale": np.full(3, 0.0026),
            "accel_offset": np.full(3, 32768.0),
            "gyro_scale": np.full(3, 1.6e-4),
            "gyro_offset": np.full(3, 32768.0),
        },
        sample_rate=100.0,
    )
    cal.save(tmp_path / "counts.json")
    text = (EXAMPLES / "drive_0708.toml").read_text()
    text = text.replace(
        "skip_first_line = true",
        f'skip_first_line = true\ncalibration = "{tmp_path / "counts.json"}"',
    )
    config = tmp_path / "c.toml"
    config.write_text(text)
    with pytest.raises(ValueError, match=r"imu\.calibration: .* calibrates raw readings"):
        mn.navigate(config, data_root=data, output=tmp_path / "o", duration_s=10.0)


def test_drive_configuration_errors(tmp_path):
    def config(body: str) -> Path:
        p = tmp_path / "cal.toml"
        p.write_text('name = "x"\n[session]\nkind = "drive"\n' + body)
        return p

    with pytest.raises(ValueError, match=r"missing required key drive\.navigate"):
        load_calibration_config(config("[drive]\nwindow_s = 2.0\n"), tmp_path)
    with pytest.raises(ValueError, match=r"table \[static\] is for session kind 'static-poses'"):
        load_calibration_config(
            config('[drive]\nnavigate = "n.toml"\n[static]\ngravity_m_s2 = 9.8\n'), tmp_path
        )
    with pytest.raises(
        ValueError, match=r"cal\.toml: drive\.window_s: must be a finite number > 0, got 0"
    ):
        load_calibration_config(config('[drive]\nnavigate = "n.toml"\nwindow_s = 0\n'), tmp_path)
    cfg = load_calibration_config(config('[drive]\nnavigate = "n.toml"\n'), tmp_path)
    assert cfg.config_path("drive", "navigate") == tmp_path / "n.toml"
    assert cfg["drive"]["window_s"] == 2.0


@pytest.mark.slow
def test_the_guide_quotes_the_drive_calibrations_parameters(drive_run):
    """docs/how-to/calibrate-an-imu.md's "Result on drive_0708": the windows fitted and
    left out, the table of biases and scale factors with their σ (three
    decimals; "held" where the fit holds the term), the x accelerometer
    scale factor in per cent and the accelerometer fit's condition number."""
    _, out = drive_run
    raw = json.loads((out / "calibration.json").read_text())
    fit = raw["fit"]
    text = " ".join(doc_text(*CALIBRATION_GUIDE).split())
    windows = re.search(
        r"`examples/drive_0708_calibration.toml`: (\d+) windows of ([\d.]+) s from the first "
        r"(\d+) s \((\d+) before the heading is known and (\d+) around resets left out\)",
        text,
    )
    assert windows, "docs/how-to/calibrate-an-imu.md no longer quotes the drive's windows"
    assert [float(v) for v in windows.groups()] == [
        fit["windows"],
        round(fit["window_s"], 2),
        fit["until_s"],
        fit["skipped_before_heading"],
        fit["skipped_for_resets"],
    ]
    page = doc_text(*CALIBRATION_GUIDE)
    page = page[page.index("`examples/drive_0708_calibration.toml`: ") :]  # not the static table
    for label, sensor, term, scale in (
        ("accelerometer bias, m/s²", "accelerometer", "bias", 1.0),
        ("accelerometer scale factor", "accelerometer", "scale_factor", 1.0),
        ("gyro bias, °/s", "gyroscope", "bias", np.degrees(1.0)),
        ("gyro scale factor", "gyroscope", "scale_factor", 1.0),
    ):
        row = re.search(rf"^\| {re.escape(label)} \|(.*)\|$", page, re.M)
        assert row, f"docs/how-to/calibrate-an-imu.md no longer has the row {label!r}"
        cells = [c.strip().replace("−", "-") for c in row.group(1).split("|")]
        for cell, value, sigma in zip(
            cells, raw[sensor][term], raw[f"{sensor}_std"][term], strict=True
        ):
            if cell == "held":
                assert sigma == 0.0, (label, cell)
                continue
            quoted, quoted_sigma = (float(v) for v in cell.split(" ± "))
            assert abs(value * scale - quoted) <= 0.0005 + 1e-12, (label, value * scale, cell)
            assert abs(sigma * scale - quoted_sigma) <= 0.0005 + 1e-12, (label, sigma, cell)
    x_scale, x_sigma = re.search(
        r"The x accelerometer scale factor is ([−\d.]+) ± ([\d.]+) %", text
    ).groups()
    assert (
        abs(100 * raw["accelerometer"]["scale_factor"][0] - float(x_scale.replace("−", "-")))
        <= 0.05
    )
    assert abs(100 * raw["accelerometer_std"]["scale_factor"][0] - float(x_sigma)) <= 0.05
    (condition,) = re.search(r"The accelerometer fit's condition number is ([\d.]+)", text).groups()
    assert all(abs(c - float(condition)) <= 0.05 for c in fit["condition_number"]["accelerometer"])
