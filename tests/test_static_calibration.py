"""Multi-position calibration, the calibration file, ``memsnav calibrate``,
and ``estimate="determinable"`` (docs/how-to/calibrate-an-imu.md). The simulated
sessions with known parameters (recovery within σ, z-scores over seeds) are
Rust tests: crates/memsnav-core/src/calibration/static_poses/tests.rs."""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from doc_runs import nonlinear_errors, nonlinear_fit, plain_fit, plain_jacobian, plain_model
from figures import figures as doc_figures
from report_checks import capture_figures, page_problems
from shared_data import shared_data

import memsnav as mn
from memsnav.calibration.config import load_calibration_config
from memsnav.cli import main

HERE = Path(__file__).resolve().parent
EXCERPT = HERE / "data" / "imu-static-poses" / "xsens_excerpt.csv.gz"
EXAMPLE = HERE.parent / "examples" / "xsens_static.toml"
GRAVITY = 9.81744  # given with the data
NOMINAL = {
    "accel_scale": GRAVITY / 3724.0,
    "accel_offset": 32768.0,
    "gyro_scale": 2.1e-4,
    "gyro_offset": 32768.0,
}


@pytest.fixture(scope="module")
def excerpt():
    table = np.loadtxt(EXCERPT, delimiter=",")
    return table[:, 0] * 1e-6, table[:, 1:4], table[:, 4:7]


@pytest.fixture(scope="module")
def calibration(excerpt):
    # No warning: 19 poses for the 9 parameters AICc keeps (with the 12 of
    # the nonlinearity, "too few observations").
    return mn.calibrate_static(*excerpt, gravity=GRAVITY, **NOMINAL)


def test_the_excerpt_meets_the_figures_of_merit(calibration):
    s = mn.static_summary(calibration)
    assert s["poses"] == 19 and s["poses_held_out"] == 0 and s["turns"] == 18
    # The rest, then 18 poses of 2-11 s, each at least a window away from motion.
    poses = np.asarray(calibration.poses)
    assert poses[0, 0] <= 60 and poses[0, 1] > 4900
    assert np.all(poses[1:, 0] > poses[:-1, 1])
    assert s["magnitude_rms_after_fit_m_s2"] < 1.5e-3 < 0.5 < s["magnitude_rms_before_fit_m_s2"]
    assert s["turn_rms_after_fit_deg"] < 1.2 < 5.0 < s["turn_rms_before_fit_deg"]
    # The pose means of the corrected readings have the magnitude of gravity.
    f, w = calibration.correct(*excerpt_arrays())
    for a, b in poses:
        assert abs(np.linalg.norm(f[a:b].mean(axis=0)) - GRAVITY) < 5e-3
        assert np.linalg.norm(w[a:b].mean(axis=0)) < 2e-3  # rad/s: the rests do not turn


def excerpt_arrays():
    table = np.loadtxt(EXCERPT, delimiter=",")
    return table[:, 1:4], table[:, 4:7]


def test_parameters_come_with_sigma_crb_and_names(calibration):
    names = calibration.parameter_names
    assert len(names) == 36 and names[0] == "accelerometer bias_u"
    assert names[-1] == "gyroscope g_sensitivity_rw"
    cov = np.asarray(calibration.covariance)
    assert cov.shape == (36, 36) and np.allclose(cov, cov.T, rtol=0, atol=1e-12 * cov.max())
    sigma = np.sqrt(np.diag(cov))
    assert np.allclose(sigma[:3], calibration.accelerometer_std.bias)
    assert np.allclose(sigma[15:18], calibration.gyroscope_std.bias)
    # The body frame is the accelerometer's: its upper misalignments are 0.
    m = calibration.accelerometer.misalignment
    assert m[0, 1] == m[0, 2] == m[1, 2] == 0.0
    crb = np.sqrt(np.diag(np.asarray(calibration.crb)))
    estimated = sigma > 0
    assert np.all(crb[estimated] > 0)
    # Hand-held poses are not white noise: σ at or above the white-noise bound.
    assert np.median(sigma[estimated] / crb[estimated]) > 0.9
    assert np.allclose(np.asarray(calibration.parameters)[:3], calibration.accelerometer.bias)


def test_the_calibration_file_round_trips(calibration, tmp_path):
    path = mn.save_calibration(calibration, tmp_path / "cal.json", source={"data": "excerpt"})
    content = json.loads(path.read_text())
    assert content["format"] == "memsnav-imu-calibration" and content["version"] == 1
    assert content["session"] == "static-poses" and content["source"] == {"data": "excerpt"}
    assert len(content["covariance"]) == 36 and content["gravity_m_s2"] == GRAVITY
    loaded = mn.load_calibration(path)
    assert np.array_equal(loaded.covariance, calibration.covariance)
    assert loaded.accelerometer == calibration.accelerometer
    assert loaded.gyroscope == calibration.gyroscope
    assert loaded.gyroscope_std == calibration.gyroscope_std
    accel, gyro = excerpt_arrays()
    for mine, theirs in zip(
        loaded.correct(accel, gyro), calibration.correct(accel, gyro), strict=True
    ):
        assert np.array_equal(mine, theirs)
    # Saved again, the file is the same (floats round-trip exactly).
    again = loaded.save(tmp_path / "again.json")
    assert json.loads(again.read_text()) == content


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda c: c.update(format="other"), "format is 'other'"),
        (lambda c: c.update(version=99), "version 99 is newer"),
        (lambda c: c.pop("gyroscope"), "missing field gyroscope"),
        (lambda c: c["accelerometer"].pop("bias"), "missing field accelerometer.bias"),
        (lambda c: c.update(session="turntable"), "session must be one of"),
        (lambda c: c.update(covariance=[[0.0]]), "covariance must be 36 x 36"),
    ],
)
def test_a_bad_calibration_file_names_file_and_field(calibration, tmp_path, edit, message):
    path = mn.save_calibration(calibration, tmp_path / "cal.json")
    content = json.loads(path.read_text())
    edit(content)
    path.write_text(json.dumps(content))
    with pytest.raises(ValueError, match=message) as e:
        mn.load_calibration(path)
    assert str(path) in str(e.value)
    path.write_text("{not json")
    with pytest.raises(ValueError, match="not a calibration file"):
        mn.load_calibration(path)


@pytest.mark.parametrize(
    ("kwargs", "argument"),
    [
        ({"gravity": 0.0}, "gravity"),
        ({"gravity": GRAVITY, "estimate": "some"}, "estimate"),
        ({"gravity": GRAVITY, "holdout_every": 1}, "holdout_every"),
        ({"gravity": GRAVITY, "gyro_scale": [1.0, 2.0]}, "gyro_scale"),
        ({"gravity": GRAVITY, "initial_rest": 400.0}, "time"),
        ({"gravity": GRAVITY, "window": -1.0}, "window_s"),
    ],
)
def test_bad_arguments_name_the_argument(excerpt, kwargs, argument):
    with pytest.raises(ValueError, match=f"^{argument}:"):
        mn.calibrate_static(*excerpt, **kwargs)
    t, a, g = excerpt
    with pytest.raises(ValueError, match=r"^accel:"):
        mn.calibrate_static(t, a[:, :2], g, gravity=GRAVITY)
    moving = a.copy()
    moving[1000:1500, 0] += 500.0 * np.sin(np.arange(500) / 10.0)
    with pytest.raises(ValueError, match=r"^initial_rest_s: the first 50 s are not at rest"):
        mn.calibrate_static(t, moving, g, gravity=GRAVITY, **NOMINAL)


def test_static_gyro_data_give_bias_and_g_sensitivity_when_asked():
    rng = np.random.default_rng(3)
    up = rng.normal(size=(30, 3))
    f = np.repeat(9.8 * up / np.linalg.norm(up, axis=1, keepdims=True), 40, axis=0)
    w = np.zeros_like(f)
    gyr = mn.GyroscopeModel(
        [0.01, -0.02, 0.005], [0.01, 0.0, 0.0], np.zeros((3, 3)), 2e-4 * np.eye(3), noise_std=1e-4
    )
    s = gyr.measure(w, f, seed=1)
    with pytest.raises(mn.UnobservableError, match="scale_factor"):
        mn.calibrate_gyroscope(s, w, f)
    cal = mn.calibrate_gyroscope(s, w, f, estimate="determinable")
    held = [name for name, _ in cal.held]
    assert sorted(held) == sorted(
        [f"scale_factor_{a}" for a in "pqr"]
        + [f"misalignment_{a}{b}" for a in "pqr" for b in "pqr" if a != b]
    )
    assert np.all(cal.std.scale_factor == 0.0) and np.all(cal.std.g_sensitivity > 0.0)
    assert np.allclose(cal.model.g_sensitivity, 2e-4 * np.eye(3) * [1.01, 1, 1], atol=2e-5)


def _write_session(tmp_path: Path) -> tuple[Path, Path]:
    table = np.loadtxt(EXCERPT, delimiter=",")
    t = table[:, :1] * 1e-6
    accel, gyro = tmp_path / "acc.txt", tmp_path / "gyro.txt"
    np.savetxt(accel, np.hstack([t, table[:, 1:4]]))
    np.savetxt(gyro, np.hstack([t, table[:, 4:7]]))
    return accel, gyro


CONFIG = """
name = "excerpt"
output = "{out}"
[session]
kind = "static-poses"
[imu]
accel_file = "{accel}"
gyro_file = "{gyro}"
accel_scale = {accel_scale}
accel_offset = 32768
gyro_scale = {gyro_scale}
gyro_offset = 32768
[static]
gravity_m_s2 = 9.81744
holdout_every = 0
"""


@pytest.mark.slow
def test_the_command_writes_the_file_and_the_report(tmp_path, capsys):
    accel, gyro = _write_session(tmp_path)
    config = tmp_path / "cal.toml"
    out = tmp_path / "out"
    config.write_text(
        CONFIG.format(
            out=out, accel=accel, gyro=gyro, accel_scale=NOMINAL["accel_scale"], gyro_scale=1 / 6258
        )
    )
    assert main(["calibrate", "--config", str(config)]) == 0
    printed = capsys.readouterr()
    assert "calibration:" in printed.out and "fit: |f| - g RMS" in printed.out
    assert "differs from the nominal by +31 %" in printed.err
    loaded = mn.load_calibration(out / "calibration.json")
    assert loaded.source["samples"] == 26200 and loaded.fit["poses"] == 19
    html = (out / "report.html").read_text()
    assert "CRB σ" in html and "held out" in html and "+31 %" in html
    assert "Model selection" in html and "accelerometer nonlinearity" in html
    assert not page_problems(html), page_problems(html)
    assert (out / "figures" / "session.png").is_file()


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda s: s.replace("holdout_every", "hold_out"), r"unknown key\(s\) \['hold_out'\]"),
        (
            lambda s: s.replace('kind = "static-poses"', 'kind = "tilt"'),
            "session.kind: must be one of",
        ),
        (lambda s: s.replace("gravity_m_s2 = 9.81744", ""), "missing required key static.gravity"),
        (
            lambda s: s.replace("gyro_offset = 32768", 'gyro_offset = "x"'),
            "imu.gyro_offset: must be a finite number, got 'x'",
        ),
        (
            lambda s: s.replace("[2.1e-4, 2.1e-4, 2.1e-4]", "[1, 2]"),
            "imu.gyro_scale: must be a list of 3 entries, got 2",
        ),
        (
            lambda s: s.replace("holdout_every = 0", "holdout_every = 1"),
            "static.holdout_every: must be 0",
        ),
        (
            lambda s: s + "holdout_from_s = nan\n",
            "static.holdout_from_s: must be a finite number, got nan",
        ),
        (lambda s: s + "[extra]\n", r"unknown table \[extra\]"),
    ],
)
def test_the_configuration_is_checked(tmp_path, edit, message):
    config = tmp_path / "cal.toml"
    text = CONFIG.format(
        out="o", accel="a", gyro="g", accel_scale=1.0, gyro_scale="[2.1e-4, 2.1e-4, 2.1e-4]"
    )
    config.write_text(edit(text))
    with pytest.raises(ValueError, match=message):
        load_calibration_config(config)


def test_the_example_configuration_is_valid():
    """The example reads; its recordings resolve under the data root, and a
    data root without them is an error naming the key and both places
    tried."""
    accel = shared_data("imu-static-poses/xsens_acc.mat")
    cfg = load_calibration_config(EXAMPLE, data_root=accel.parents[1])
    assert cfg["session"]["kind"] == "static-poses" and cfg["static"]["holdout_every"] == 4
    assert cfg.data_path("imu", "accel_file") == accel
    elsewhere = load_calibration_config(EXAMPLE, data_root="/nowhere")
    with pytest.raises(ValueError, match=r"imu\.accel_file: no such file .*/nowhere/"):
        elsewhere.data_path("imu", "accel_file")


def test_the_full_xsens_session_meets_the_issue_figures(tmp_path, capsys, monkeypatch):
    """The required figures: |f| - g RMS <= 1.5 mm/s² and gravity-direction error <=
    1.2° RMS, in the fit and on held-out poses (every 4th), against the
    nominal scales. The figures of merit come first; the
    example runs without a warning about itself; the report's figures show
    their data."""
    figures = capture_figures(monkeypatch)
    data = shared_data("imu-static-poses/xsens_acc.mat").parents[1]
    assert (
        main(
            [
                "calibrate",
                "--config",
                str(EXAMPLE),
                "--data-root",
                str(data),
                "--output",
                str(tmp_path),
            ]
        )
        == 0
    )
    printed = capsys.readouterr()
    assert printed.out.startswith("fit: |f| - g RMS")
    assert printed.out.splitlines()[1].startswith("held out: |f| - g RMS")
    # The shipped example starts from the fitted gyro scale: no warning asks
    # the user to fix it.
    warned = [line for line in printed.err.splitlines() if line.startswith("warning:")]
    assert not warned, printed.err
    assert figures and not any(figures.values())
    fit = mn.load_calibration(tmp_path / "calibration.json").fit
    assert fit["poses"] == 38 and fit["poses_held_out"] == 9
    for subset in ("fit", "held_out"):
        assert fit[f"magnitude_rms_after_{subset}_m_s2"] <= 1.5e-3
        assert fit[f"turn_rms_after_{subset}_deg"] <= 1.2
        assert fit[f"magnitude_rms_before_{subset}_m_s2"] > 0.5
        assert fit[f"turn_rms_before_{subset}_deg"] > 10.0
    # docs/how-to/calibrate-an-imu.md shows these figures from
    # docs/data/xsens_session.json (docs/doc_runs.py): today's run agrees
    # with it within half the last digit shown.
    recorded = doc_figures("xsens_session")["merit"]
    for key, unit, scale, steps in (
        ("magnitude", "m_s2", 1e3, {"before": 0.5, "after": 0.005}),
        ("turn", "deg", 1.0, {"before": 0.05, "after": 0.0005}),
    ):
        for stage in ("before", "after"):
            for subset in ("fit", "held_out"):
                run = fit[f"{key}_rms_{stage}_{subset}_{unit}"] * scale
                shown = recorded[f"{key}_{stage}_{subset}"]
                assert abs(run - shown) <= steps[stage] + 1e-9, (key, stage, subset, run, shown)


def test_warnings_are_python_warnings(excerpt):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cal = mn.calibrate_static(*excerpt, gravity=GRAVITY, **{**NOMINAL, "gyro_scale": 1 / 6258})
    messages = [str(w.message) for w in caught]
    assert messages == list(cal.warnings)
    assert any("differs from the nominal by +31 %" in m for m in messages)


# The issue-27 comparison: memsnav against a plain 9-parameter least-squares
# fit of the accelerometer (bias, scale factors, non-orthogonality; imu_tk's
# model, Tedaldi et al. 2014 eq. 10-12) written here with scipy, on the same
# pose means, scored on the same held-out poses.


def _aicc(rss: float, n: int, parameters: int) -> float:
    """Hurvich and Tsai (1989): K counts the residual variance."""
    k = parameters + 1
    return n * np.log(rss / n) + 2 * k + 2 * k * (k + 1) / (n - k - 1)


@pytest.fixture(scope="module")
def xsens():
    data = shared_data("imu-static-poses/xsens_acc.mat").parent
    accel = np.loadtxt(data / "xsens_acc.mat")
    gyro = np.loadtxt(data / "xsens_gyro.mat")
    return accel[:, 0], accel[:, 1:], gyro[:, 1:]


def _xsens_split(xsens, split: str, estimate: str = "determinable", **options):
    """memsnav's calibration of the Xsens session, the poses of `split`
    held out ("every 4th pose", "first half, second half" or "none"), with
    the guide's nominal scales and any further `options`."""
    t, accel, gyro = xsens
    holdout = {
        "every 4th pose": {"holdout_every": 4},
        "first half, second half": {"holdout_from": (t[0] + t[-1]) / 2},
        "none": {},
    }[split]
    with warnings.catch_warnings(record=True):  # the gyro's nominal scale is 31 % off
        warnings.simplefilter("always")
        return mn.calibrate_static(
            t,
            accel,
            gyro,
            gravity=GRAVITY,
            estimate=estimate,
            **{**NOMINAL, "gyro_scale": 1 / 6258},
            **holdout,
            **options,
        )


#: The splits' keys in docs/data/xsens_splits.json.
SPLIT_KEYS = {"every 4th pose": "every_4th", "first half, second half": "halves"}


@pytest.mark.slow
@pytest.mark.parametrize("split", ["every 4th pose", "first half, second half"])
def test_xsens_held_out_poses_are_at_least_as_good_as_aplain_fit(xsens, split):
    """On poses the fit never saw, |f| - g RMS no worse than the
    plain 9-parameter fit's, the gyro's gravity direction after the held-out
    turns within 0.2°, and the model AICc chose is the one of smallest AICc."""
    _, accel, _ = xsens
    cal = _xsens_split(xsens, split)
    summary = mn.static_summary(cal)
    held_out = np.asarray(cal.pose_held_out)
    means = np.array([accel[a:b].mean(axis=0) for a, b in cal.poses])
    x = plain_fit(means[~held_out])
    plain = np.linalg.norm(plain_model(x, means), axis=1) - GRAVITY
    plain_held_out = np.sqrt(np.mean(plain[held_out] ** 2))
    plain_in_fit = np.sqrt(np.mean(plain[~held_out] ** 2))
    assert summary["magnitude_rms_after_held_out_m_s2"] <= 1.01 * plain_held_out
    assert summary["turn_rms_after_held_out_deg"] <= 0.2
    # docs/how-to/calibrate-an-imu.md's table of the splits is
    # docs/data/xsens_splits.json (docs/doc_runs.py): today's figures agree
    # with it within half the last digit shown (0.01 mm/s², 0.001°).
    recorded = doc_figures("xsens_splits")[SPLIT_KEYS[split]]
    before = mn.static_summary(_xsens_split(xsens, split, estimate="all"))
    for column, fresh in (("now", summary), ("before", before)):
        for key, name, scale in (
            ("fit_mm_s2", "magnitude_rms_after_fit_m_s2", 1e3),
            ("held_out_mm_s2", "magnitude_rms_after_held_out_m_s2", 1e3),
        ):
            value = scale * fresh[name]
            assert abs(value - recorded[column][key]) <= 0.005 + 1e-9, (split, column, key)
        turns = fresh["turn_rms_after_held_out_deg"]
        assert abs(turns - recorded[column]["turns_deg"]) <= 0.0005 + 1e-9, (split, column)
    for key, value in (("fit_mm_s2", plain_in_fit), ("held_out_mm_s2", plain_held_out)):
        assert abs(1e3 * value - recorded["plain"][key]) <= 0.005 + 1e-9, (split, key)
    assert recorded["poses"]["held_out"] == held_out.sum()
    assert recorded["poses"]["fit"] == (~held_out).sum()
    # The required figures still hold on the every-4th split.
    if split == "every 4th pose":
        assert summary["magnitude_rms_after_held_out_m_s2"] <= 1.5e-3
    # The rule: every admissible candidate's AICc from its fit, the
    # smallest chosen; the 9-parameter candidate is the plain fit.
    (accel_selection,) = [
        m for m in cal.model_selection if m["stage"] == "accelerometer nonlinearity"
    ]
    candidates = accel_selection["candidates"]
    assert candidates[0]["terms"] == [] and candidates[0]["parameters"] == 9
    assert candidates[0]["residual_rms"] == pytest.approx(plain_in_fit, rel=1e-6)
    admissible = [c for c in candidates if c["aicc"] is not None]
    for c in admissible:
        n = c["observations"]
        rss = n * c["residual_rms"] ** 2
        assert c["aicc"] == pytest.approx(_aicc(rss, n, c["parameters"]), abs=1e-6)
    best = min(admissible, key=lambda c: c["aicc"])
    assert candidates[accel_selection["chosen"]] is not None
    assert candidates[accel_selection["chosen"]]["terms"] == best["terms"]
    assert summary["model"]["accelerometer nonlinearity"] == best["terms"]


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="the target is 1.2 mm/s² on the second half; the first half's 18 poses give "
    "about 1.9: docs/decisions/0021-xsens-second-half-target-left-unmet.md",
)
def test_xsens_first_half_fit_meets_the_target_on_the_second_half(xsens):
    summary = mn.static_summary(_xsens_split(xsens, "first half, second half"))
    assert summary["magnitude_rms_after_held_out_m_s2"] <= 1.2e-3


def test_the_xsens_parameters_are_the_record(xsens):
    """docs/how-to/calibrate-an-imu.md's parameter table of the Xsens session
    (every 4th pose held out, as its example) and the fitted gyro scales
    are docs/data/xsens_parameters.json (docs/doc_runs.py): today's
    calibration agrees with it within half the last digit shown (biases
    and scale factors to 1e-5, the gyro's misalignments to 1e-4, the
    scales to four figures)."""
    import doc_runs

    assert doc_runs.XSENS_NOMINAL == {**NOMINAL, "gyro_scale": 1 / 6258}
    assert doc_runs.XSENS_GRAVITY == GRAVITY
    cal = _xsens_split(xsens, "every 4th pose")
    recorded = doc_figures("xsens_parameters")
    for sensor, model, std, misalignment_step in (
        ("accelerometer", cal.accelerometer, cal.accelerometer_std, 5e-6),
        ("gyroscope", cal.gyroscope, cal.gyroscope_std, 5e-5),
    ):
        for term, step in (
            ("bias", 5e-6),
            ("scale_factor", 5e-6),
            ("misalignment", misalignment_step),
        ):
            for suffix, of in (("", model), ("_sigma", std)):
                fresh = np.asarray(getattr(of, term))
                shown = np.asarray(recorded[sensor][term + suffix])
                np.testing.assert_allclose(
                    fresh, shown, rtol=0, atol=step + 1e-12, err_msg=f"{sensor} {term}{suffix}"
                )
    fitted = np.asarray(cal.nominal["gyro_scale"]) / (1 - np.asarray(cal.gyroscope.scale_factor))
    np.testing.assert_allclose(fitted, recorded["fitted_gyro_scale"], rtol=0, atol=5e-8)


@pytest.mark.slow
def test_the_full_sessions_sigma_against_the_bound_is_the_record(tmp_path):
    """docs/how-to/calibrate-an-imu.md shows, from docs/data/xsens_session.json,
    the estimated parameters' σ over their white-noise Cramér-Rao bound
    (least and most, per sensor) and the accelerometer biases' σ: the
    example's run today agrees within half the 0.1 shown, and σ is never
    below the bound."""
    import doc_runs

    data = shared_data("imu-static-poses/xsens_acc.mat").parents[1]
    fresh, recorded = doc_runs.xsens_session(data), doc_figures("xsens_session")
    for sensor in ("accelerometer", "gyroscope"):
        for end in ("least", "most"):
            value = fresh["sigma_over_bound"][sensor][end]
            assert abs(value - recorded["sigma_over_bound"][sensor][end]) <= 0.05, (sensor, end)
        assert fresh["sigma_over_bound"][sensor]["least"] >= 1.0
    for end in ("least", "most"):
        value = fresh["accel_bias_sigma_mm_s2"][end]
        assert abs(value - recorded["accel_bias_sigma_mm_s2"][end]) <= 0.05, (end, value)


# docs/how-to/calibrate-an-imu.md, "Which terms to estimate": the prose after the splits
# table. The poses are memsnav's (38 on the Xsens log whatever is held out),
# numbered from the rest (pose 0) as cal.poses lists them.

PAGE = "docs/how-to/calibrate-an-imu.md"
#: The detector, the model and the fit.
EXPLANATION = "docs/explanation/calibration.md"


def _rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(values))))


def _plain_errors(x: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """‖a_k‖ − g of the plain model for pose means in counts, m/s²."""
    return np.linalg.norm(plain_model(x, counts), axis=1) - GRAVITY


@pytest.fixture(scope="module")
def xsens_halves(xsens):
    """The first-half split under "determinable" and "all", the pose means
    in counts and which poses are held out."""
    _, accel, _ = xsens
    now = _xsens_split(xsens, "first half, second half")
    before = _xsens_split(xsens, "first half, second half", estimate="all")
    means = np.array([accel[a:b].mean(axis=0) for a, b in now.poses])
    assert len(means) == 38 and np.array_equal(now.poses, before.poses)
    return now, before, means, np.asarray(now.pose_held_out)


@pytest.mark.slow
def test_why_memsnav_lost_on_unseen_poses_is_the_record(xsens, xsens_halves):
    """docs/how-to/calibrate-an-imu.md, "Why memsnav lost on unseen poses",
    shows docs/data/xsens_nonlinearity.json (docs/doc_runs.py): the plain
    fit on all 38 poses, N's σ on both splits and how far below 1e-3, N's
    in-fit gain on the first half, the pose N extrapolates worst (its
    specific force direction after the calibration; the first half's
    single +x pose) missed with N (estimate="all") and without, and N's
    cost held out (before − now, RMS over the held-out poses) on both
    splits. Each is computed here again and agrees with the record within
    half the last digit shown."""
    now, before, means, held = xsens_halves
    r = doc_figures("xsens_nonlinearity")
    plain_all = 1e3 * _rms(_plain_errors(plain_fit(means), means))
    assert abs(plain_all - r["all_poses_plain_mm_s2"]) <= 0.005

    every_4th = _xsens_split(xsens, "every 4th pose", estimate="all")
    sigma = np.asarray(every_4th.accelerometer_std.nonlinearity)
    worst = max(before.accelerometer_std.nonlinearity)
    # Shown to one significant figure (2e-5), two (1.2e-4), the ratios to 1.
    assert abs(sigma.max() - r["n_sigma_most"]["every_4th"]) <= 0.5e-5, sigma
    assert abs(worst - r["n_sigma_most"]["halves"]) <= 0.05e-4, worst
    assert abs(1e-3 / sigma.min() - r["times_below_1e3"]["most"]) <= 0.5
    assert abs(1e-3 / worst - r["times_below_1e3"]["least"]) <= 0.5
    assert r["times_below_1e3"]["least"] > 1.0

    after_now = np.asarray(now.magnitude_error_after)
    after_before = np.asarray(before.magnitude_error_after)
    fit = r["first_half_fit_mm_s2"]
    assert abs(1e3 * _rms(after_now[~held]) - fit["without_n"]) <= 0.005
    assert abs(1e3 * _rms(after_before[~held]) - fit["with_n"]) <= 0.005
    assert fit["with_n"] < fit["without_n"]

    pose = r["worst_pose"]
    k = pose["index"]
    assert held[k]
    f, _ = now.correct(xsens[1], xsens[2])
    a, b = now.poses[k]
    up = f[a:b].mean(axis=0) / np.linalg.norm(f[a:b].mean(axis=0))
    np.testing.assert_allclose(up, pose["direction"], rtol=0, atol=0.005)
    assert abs(1e3 * abs(after_before[k]) - pose["missed_with_n_mm_s2"]) <= 0.05
    assert abs(1e3 * abs(after_now[k]) - pose["missed_without_n_mm_s2"]) <= 0.05
    assert pose["missed_with_n_mm_s2"] > pose["missed_without_n_mm_s2"]
    # "the first half has one pose with +x and none with +x and +y"
    first = np.array([f[a:b].mean(axis=0) for a, b in np.asarray(now.poses)[~held]])
    first /= np.linalg.norm(first, axis=1, keepdims=True)
    assert np.sum(first[:, 0] > 0.5) == 1 and not np.any((first[:, 0] > 0.3) & (first[:, 1] > 0.3))

    cost = r["n_cost_mm_s2"]
    halves = 1e3 * (_rms(after_before[held]) - _rms(after_now[held]))
    assert abs(halves - cost["halves"]) <= 0.05
    every_4th_now = _xsens_split(xsens, "every 4th pose")
    held_4th = np.asarray(every_4th_now.pose_held_out)
    cost_4th = _rms(np.asarray(every_4th.magnitude_error_after)[held_4th]) - _rms(
        np.asarray(every_4th_now.magnitude_error_after)[held_4th]
    )
    assert abs(1e3 * cost_4th - cost["every_4th"]) <= 0.005
    assert cost["halves"] > 0 and cost["every_4th"] > 0


def _nonlinearity_candidates(cal) -> list[dict]:
    (selection,) = [m for m in cal.model_selection if m["stage"] == "accelerometer nonlinearity"]
    return selection["candidates"]


@pytest.mark.slow
def test_the_information_criteria_on_the_xsens_log_are_the_record(xsens, xsens_halves):
    """docs/data/xsens_criteria.json (docs/doc_runs.py), which the guide
    shows, against today's calibrations within half the last digit shown:
    AICc holds all of N on both splits and on all 38 poses (its margin
    against the best candidate with an entry of N) and keeps all of K (the
    least margin), from cal.model_selection; plain AIC
    (AICc without its third term) and BIC (K ln n for 2K) from the
    candidates' n and RSS; leave-one-out over the first half's 18 poses and
    N_v's held-out RMS from scipy fits in memsnav's parametrisation
    (nonlinear_errors, which reproduces the candidates' in-fit RMS)."""
    every_pose = _xsens_split(xsens, "none")
    now, _, means, held = xsens_halves
    cals = [_xsens_split(xsens, "every 4th pose"), now, every_pose]
    assert [int(np.sum(c.pose_held_out)) for c in cals] == [9, 20, 0]

    r = doc_figures("xsens_criteria")
    n_margins = [r["aicc_n_margin"][name] for name in ("every_4th", "halves", "all")]
    k_margins = []
    for cal, recorded in zip(cals, n_margins, strict=True):
        candidates = _nonlinearity_candidates(cal)
        assert candidates[0]["terms"] == []  # the linear model, chosen
        with_n = min(c["aicc"] for c in candidates[1:] if c["aicc"] is not None)
        assert abs(with_n - candidates[0]["aicc"] - recorded) <= 0.05, (recorded, with_n)
        assert recorded > 0  # the linear model wins
        (gyro_selection,) = [
            m for m in cal.model_selection if m["stage"] == "gyroscope g-sensitivity"
        ]
        gyro_candidates = gyro_selection["candidates"]
        chosen = gyro_candidates[gyro_selection["chosen"]]
        assert len(chosen["terms"]) == 3  # all of K
        k_margins.append(
            min(c["aicc"] for c in gyro_candidates if c is not chosen and c["aicc"] is not None)
            - chosen["aicc"]
        )
    assert abs(min(k_margins) - r["aicc_k_margin_least"]) <= 0.5, k_margins
    assert r["aicc_k_margin_least"] > 0

    aic_gaps, bic_margins = [], []
    for cal in cals:
        criteria = []
        for c in _nonlinearity_candidates(cal):
            n, k = c["observations"], c["parameters"] + 1
            fit = n * np.log(c["residual_rms"] ** 2)
            criteria.append((c["terms"], fit + 2 * k, fit + k * np.log(n)))
        aic_gaps.append(next(a for terms, a, _ in criteria if terms == ["nonlinearity_v"]))
        aic_gaps[-1] -= criteria[0][1]
        bic_margins.append(min(b for _, _, b in criteria[1:]) - criteria[0][2])
        assert min(a for _, a, _ in criteria[1:]) > criteria[0][1]  # AIC keeps it too
    for key, values in (("aic_nv_gap", aic_gaps), ("bic_margin", bic_margins)):
        assert abs(min(values) - r[key]["least"]) <= 0.05, (key, values)
        assert abs(max(values) - r[key]["most"]) <= 0.05, (key, values)

    nominal = NOMINAL["accel_scale"] * (means - NOMINAL["accel_offset"])
    in_fit = nominal[~held]
    assert len(in_fit) == r["first_half_poses"] == 18
    candidates = {tuple(c["terms"]): c for c in _nonlinearity_candidates(now)}
    loo = {}
    for terms, candidate in candidates.items():
        axes = ["uvw".index(term[-1]) for term in terms]
        theta = nonlinear_fit(in_fit, axes)
        rms = _rms(nonlinear_errors(theta, in_fit, axes))
        assert rms == pytest.approx(candidate["residual_rms"], rel=1e-6), terms
        left_out = [
            nonlinear_errors(nonlinear_fit(np.delete(in_fit, k, 0), axes), in_fit[[k]], axes)
            for k in range(len(in_fit))
        ]
        loo[terms] = _rms(np.concatenate(left_out))
        if terms == ("nonlinearity_v",):
            second_half = _rms(nonlinear_errors(theta, nominal[held], axes))
    assert min(loo, key=loo.get) == ("nonlinearity_v",), loo
    assert abs(1e3 * loo[("nonlinearity_v",)] - r["loo_mm_s2"]["nonlinearity_v"]) <= 0.005, loo
    assert abs(1e3 * loo[()] - r["loo_mm_s2"]["linear"]) <= 0.005, loo
    assert abs(1e3 * second_half - r["nv_second_half_mm_s2"]) <= 0.005


@pytest.mark.slow
def test_what_is_left_on_the_second_half_is_the_record(xsens, xsens_halves):
    """ "What is left": the plain fit on memsnav's poses (the 19 that start
    after the middle and all 20 held out), on 19 to 23 poses when the split
    moves later, the z-up poses' scatter about the all-pose fit, the spread
    of the rest's 1 s means (the magnitude of the all-pose fit's correction
    of each second's mean), σ̂ = √(RSS/(n − 9)) of the plain fits (memsnav's
    accelerometer_residual_std for the same model), the prediction by the
    first-half fit's covariance C = σ̂² (JᵀJ)⁻¹ (J the Jacobian of its
    residuals): pose k's predicted error has variance σ̂² + J_k C J_kᵀ
    (its own scatter and the parameters'; "2.3 of it from the parameters"
    is √(J_k C J_kᵀ) alone, "missed by 2.1 σ" the plain fit's miss over
    the whole), and memsnav's held-out RMS for
    detector factors 4 to 10 (here and in "The detector")."""
    t, accel, _ = xsens
    now, _, means, held = xsens_halves
    # The plain fit on memsnav's poses: docs/data/xsens_splits.json, within
    # half the 0.01 mm/s² shown.
    plain = doc_figures("xsens_splits")["halves"]["plain"]
    x = plain_fit(means[~held])
    errors = _plain_errors(x, means)
    starts_after = t[np.asarray(now.poses)[:, 0]] > (t[0] + t[-1]) / 2
    assert starts_after.sum() == 19
    assert abs(1e3 * _rms(errors[starts_after]) - plain["after_middle_mm_s2"]) <= 0.005
    assert abs(1e3 * _rms(errors[held]) - plain["held_out_mm_s2"]) <= 0.005

    # The rest: docs/data/xsens_second_half.json (docs/doc_runs.py), each
    # figure computed here again within half the last digit shown.
    r = doc_figures("xsens_second_half")
    fewest, most = r["later_split_poses"]["fewest"], r["later_split_poses"]["most"]
    later = [
        1e3 * _rms(_plain_errors(plain_fit(means[:m]), means[m:])) for m in range(fewest, most + 1)
    ]
    shown = r["later_split_mm_s2"]
    assert abs(later[0] - shown["fewest_poses"]) <= 0.005, later
    assert abs(later[-1] - shown["most_poses"]) <= 0.005, later
    assert later[0] == max(later) and later[-1] == min(later), later

    x_all = plain_fit(means)
    all_errors = _plain_errors(x_all, means)
    z_up = plain_model(x_all, means)[:, 2] / GRAVITY > 0.9
    assert z_up.sum() == r["z_up_poses"] and z_up[0]
    scatter = r["z_up_scatter_mm_s2"]
    assert abs(1e3 * all_errors[z_up].min() - scatter["least"]) <= 0.05, all_errors[z_up]
    assert abs(1e3 * all_errors[z_up].max() - scatter["most"]) <= 0.05, all_errors[z_up]
    a, b = now.poses[0]
    rate = round(1.0 / np.median(np.diff(t)))
    seconds = accel[a : a + (b - a) // rate * rate].reshape(-1, rate, 3).mean(axis=1)
    assert round((b - a) / rate) == r["rest_s"]
    spread = 1e3 * np.std(_plain_errors(x_all, seconds), ddof=1)
    assert abs(spread - r["rest_spread_mm_s2"]) <= 0.05

    n = int(np.sum(~held))
    residual_std = np.sqrt(np.sum(errors[~held] ** 2) / (n - 9))
    assert residual_std == pytest.approx(now.accelerometer_residual_std, rel=1e-6)
    sigma = r["residual_std_mm_s2"]
    assert abs(1e3 * residual_std - sigma["first_half"]) <= 0.005
    all_std = 1e3 * np.sqrt(np.sum(all_errors**2) / (38 - 9))
    assert abs(all_std - sigma["all_poses"]) <= 0.005
    jacobian = plain_jacobian(x, means[~held])
    covariance = residual_std**2 * np.linalg.inv(jacobian.T @ jacobian)
    ahead = plain_jacobian(x, means)
    from_parameters = np.einsum("ij,jk,ik->i", ahead, covariance, ahead)
    sd = np.sqrt(residual_std**2 + from_parameters)
    assert abs(1e3 * _rms(sd[held]) - r["predicted_mm_s2"]) <= 0.005
    pose = r["worst_pose"]
    k = pose["index"]
    assert k == doc_figures("xsens_nonlinearity")["worst_pose"]["index"]
    assert abs(1e3 * sd[k] - pose["predicted_mm_s2"]) <= 0.05
    assert abs(abs(errors[k]) / sd[k] - pose["missed_sigmas"]) <= 0.05
    assert abs(1e3 * np.sqrt(from_parameters[k]) - pose["from_parameters_mm_s2"]) <= 0.05

    # The detector's factors (both pages show the same record).
    factors = r["detector_factors"]
    held_out = []
    for factor in range(factors["first"], factors["last"] + 1):
        cal = _xsens_split(xsens, "first half, second half", threshold_factor=factor)
        assert len(cal.poses) in (38, 39)
        held_out.append(1e3 * mn.static_summary(cal)["magnitude_rms_after_held_out_m_s2"])
    shown = r["detector_held_out_mm_s2"]
    assert abs(min(held_out) - shown["least"]) <= 0.005, held_out
    assert abs(max(held_out) - shown["most"]) <= 0.005, held_out


@pytest.mark.slow
def test_the_detector_factors_are_the_record(xsens):
    """docs/explanation/calibration.md, "The detector", shows
    docs/data/xsens_detector.json (docs/doc_runs.py): what a factor too low
    does on the Xsens log (poses found, in-fit and held-out magnitude
    error, the held-out one with the nonlinearity estimated), and how far
    factors 4 to 10 stay from the default's figures, every 4th pose held
    out; each computed here again within half the last digit shown."""
    r = doc_figures("xsens_detector")

    def summary(factor: float, estimate: str = "determinable") -> dict:
        cal = _xsens_split(xsens, "every 4th pose", estimate, threshold_factor=factor)
        return {"poses": len(cal.poses), **mn.static_summary(cal)}

    low = summary(r["low_factor"])
    assert low["poses"] == r["low_poses"] > 38
    assert abs(1e3 * low["magnitude_rms_after_fit_m_s2"] - r["low_fit_mm_s2"]) <= 0.005
    assert abs(1e3 * low["magnitude_rms_after_held_out_m_s2"] - r["low_held_out_mm_s2"]) <= 0.005
    estimated = summary(r["low_factor"], estimate="all")
    with_n = 1e3 * estimated["magnitude_rms_after_held_out_m_s2"]
    assert abs(with_n - r["low_held_out_all_terms_mm_s2"]) <= 0.5
    default = summary(6.0)
    magnitude, turn = 0.0, 0.0
    for factor in range(4, 11):
        s = summary(factor)
        assert s["poses"] in (38, 39), factor
        for key in ("magnitude_rms_after_fit_m_s2", "magnitude_rms_after_held_out_m_s2"):
            magnitude = max(magnitude, 1e3 * abs(s[key] - default[key]))
        turn = max(
            turn, abs(s["turn_rms_after_held_out_deg"] - default["turn_rms_after_held_out_deg"])
        )
    assert abs(magnitude - r["largest_departure"]["magnitude_mm_s2"]) <= 0.005
    assert abs(turn - r["largest_departure"]["turn_deg"]) <= 0.0005
