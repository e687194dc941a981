"""``memsnav navigate``: the configuration, the core engine's
defaults on real excerpts (tests/data/real-imu-gnss, BSD-3, LICENSE there),
the outputs and the command line."""

from __future__ import annotations

import json
import re
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
from doc_pages import NAVIGATE_GUIDE, doc_text
from report_checks import capture_figures, hidden_by_bounds, page_problems

import memsnav as mn
from memsnav import cli
from memsnav._files import MARKER

DATA = Path(__file__).parent / "data"
EX = DATA / "real-imu-gnss"

# The drive excerpt: 65 s of a car, RTK fixes at 4 Hz, the data authors'
# mounting and lever arms, the IMU latency and the RTK velocity's latency
# behind its positions that the data give (docs/explanation/time-and-truth.md, "Time").
DRIVE = """
name = "drive_60s"
output = "{out}"
[imu]
file = "real-imu-gnss/drive_60s.csv"
accel_unit = "g"
gyro_unit = "deg/s"
time_unit = "ms"
time_tag = "real-imu-gnss/drive_60s.csv.tag"
time_offset_s = -0.22
mounting_rpy_deg = [[180.0, 0.0, 180.0], [0.0, -6.79, 5.35]]
lever_arm_m = [0.0, 0.0, -0.65]
[gnss]
mode = "loose"
pos = "real-imu-gnss/drive_60s.pos"
quality = [1, 2]
antenna_lever_arm_m = [0.0, -0.05, -0.65]
velocity_latency_s = 0.132
[truth]
pos = "real-imu-gnss/drive_60s.pos"
quality = [1]
"""

# The walk excerpt: 40 s of a hand-held walk starting with 9 s at rest,
# raw GPS L1 pseudoranges and Dopplers of four satellites.
WALK = """
name = "walk_40s"
output = "{out}"
[imu]
file = "real-imu-gnss/walk_40s.csv"
accel_unit = "g"
gyro_unit = "deg/s"
time_unit = "ms"
skip_first_line = true
time_tag = "real-imu-gnss/walk_40s.csv.tag"
mounting_rpy_deg = [[180.0, 0.0, -90.0]]
[gnss]
mode = "tight"
obs = "real-imu-gnss/walk_40s.obs"
nav = "real-imu-gnss/walk.nav"
elevation_mask_deg = 5.0
min_cn0_db_hz = 20.0
[truth]
pos = "real-imu-gnss/walk_40s.pos"
quality = [1]
height = "msl"
geoid_separation_m = -21.387
score = "precision"
"""


def _config(tmp_path: Path, template: str = DRIVE, extra: str = "", **replace: str) -> Path:
    text = template.format(out=tmp_path / "out") + extra
    for k, v in replace.items():
        text = text.replace(k, v)
    p = tmp_path / "run.toml"
    p.write_text(text)
    return p


# --- configuration ---------------------------------------------------------


def test_config_unknown_keys_and_bad_values(tmp_path):
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['acel_unit'\] in \[imu\]"):
        mn.load_config(_config(tmp_path, **{'accel_unit = "g"': 'acel_unit = "g"'}), DATA)
    with pytest.raises(ValueError, match=r"unknown table \[filtre\]"):
        mn.load_config(_config(tmp_path, extra="[filtre]\nx = 1\n"), DATA)
    with pytest.raises(ValueError, match=r"gnss.mode: must be one of \['loose', 'tight'\]"):
        mn.load_config(_config(tmp_path, **{'mode = "loose"': 'mode = "lose"'}), DATA)
    with pytest.raises(ValueError, match=r"missing required key imu.gyro_unit"):
        mn.load_config(_config(tmp_path, **{'gyro_unit = "deg/s"': ""}), DATA)
    # The engine's keys are checked by the core when the file is loaded.
    with pytest.raises(ValueError, match=r"run.toml: filter.accel_bias_std: expected a number"):
        mn.load_config(_config(tmp_path, extra='[filter]\naccel_bias_std = "0.2"\n'), DATA)
    with pytest.raises(ValueError, match=r"aids.zupt_std_m_s: must be finite and positive, got -1"):
        mn.load_config(_config(tmp_path, extra="[aids]\nzupt_std_m_s = -1.0\n"), DATA)
    with pytest.raises(ValueError, match=r"alignment.heading_deg: is needed"):
        mn.load_config(_config(tmp_path, extra='[alignment]\nmethod = "static"\n'), DATA)
    with pytest.raises(ValueError, match=r"imu.file: no such file"):
        mn.navigate(_config(tmp_path, **{'drive_60s.csv"': 'nope.csv"'}), data_root=DATA)
    with pytest.raises(ValueError, match=r"unknown unit 'G'"):
        mn.navigate(_config(tmp_path, **{'accel_unit = "g"': 'accel_unit = "G"'}), data_root=DATA)


def test_imu_spec_table_replaces_the_preset(tmp_path):
    """``[imu_spec]`` with the consumer preset's figures, over another
    preset, runs exactly as the default (the consumer preset): one path
    from a spec to the filter. Its keys are checked with the engine's."""
    from test_imu_spec import CONSUMER

    table = "".join(f"{k} = {v}\n" for k, v in CONSUMER.items())
    runs = []
    for name, extra in [
        ("preset", ""),
        ("spec", f'[filter]\nimu_preset = "tactical"\n[imu_spec]\n{table}'),
    ]:
        (tmp_path / name).mkdir()
        runs.append(mn.navigate(_config(tmp_path / name, extra=extra), data_root=DATA).run)
    for field in ("position_ecef", "velocity_ned", "euler", "position_std_ned"):
        np.testing.assert_array_equal(getattr(runs[0], field), getattr(runs[1], field))
    with pytest.raises(ValueError, match=r"run.toml: imu_spec.gyro_arw_deg_sqrt_h: must be finite"):
        mn.load_config(_config(tmp_path, extra="[imu_spec]\ngyro_arw_deg_sqrt_h = -1.0\n"), DATA)
    with pytest.raises(ValueError, match=r"filter.accel_noise_density: sets what imu_spec"):
        mn.load_config(
            _config(
                tmp_path,
                extra="[filter]\naccel_noise_density = 0.002\n"
                "[imu_spec]\naccel_vrw_m_s_sqrt_h = 0.1\n",
            ),
            DATA,
        )


def test_data_root_from_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("MEMSNAV_DATA_ROOT", str(DATA))
    cfg = mn.load_config(_config(tmp_path))
    assert cfg.data_path("imu", "file") == (DATA / "real-imu-gnss/drive_60s.csv").resolve()


def test_every_engine_key_is_documented():
    keys = mn.navigate_settings()
    assert {"filter", "alignment", "standstill", "aids", "outages"} <= set(keys)
    text = doc_text(*NAVIGATE_GUIDE)
    missing = [f"{t}.{k}" for t, ks in keys.items() for k in ks if f"`{k}`" not in text]
    assert not missing, f"the navigate guide does not mention {missing}"


# --- the engine's defaults on real data -------------------------------------


def test_defaults_follow_rtk_fixes_to_centimetres(tmp_path):
    """No [filter] or [alignment] table, RTK fixes at their full 4 Hz: the
    filter converges and stays on them (the required bar: 0.1 m while aided)."""
    result = mn.navigate(_config(tmp_path), data_root=DATA)
    s = result.summary
    assert s["start"]["kind"] == "moving"
    aided = s["errors_vs_truth"]["aided"]
    assert aided["epochs"] > 200
    assert aided["rms_horizontal_m"] < 0.1 and aided["rms_vertical_m"] < 0.1
    assert aided["within_3sigma_share"] > 0.95
    accepted = s["measurements"]["position"]["accepted"]
    assert accepted > 0.95 * 3 * aided["epochs"]
    assert s["diverged"] is False and s["warnings"] == []
    # The integrity assessment reaches summary.json: no alert, and the
    # position fixes' innovations inside (or near) their chi-square band.
    integrity = s["integrity"]
    assert integrity["alerts"] == [] and not integrity["diverged"]
    kinds = {c["kind"]: c for c in integrity["consistency"]}
    assert kinds["position"]["windows"] >= 1
    assert kinds["position"]["max_band_ratio"] < 4.0


def test_walk_starts_at_rest_and_stays_consistent(tmp_path):
    """Tight coupling with Doppler from a static start: levelled and
    bias-settled at rest (ZUPT, ZARU), heading from the first steps' course,
    the range-bias states keep the bounds honest against the metres of
    pseudorange bias of a hand-held antenna."""
    result = mn.navigate(_config(tmp_path, WALK), data_root=DATA)
    s = result.summary
    assert s["start"]["kind"] == "static"
    heading = [r for r in s["resets"] if r["kind"] == "heading"]
    assert len(heading) == 1 and 8.0 < heading[0]["time_s"] < 15.0
    assert s["standstills_s"] and s["standstills_s"][0][0] < 2.0
    assert s["measurements"]["zero_velocity"]["accepted"] > 20
    assert s["measurements"]["pseudorange_rate"]["accepted"] > 400
    assert set(s["range_biases_m"]) == {"G10", "G23", "G27", "G32"}
    # 29 states (range biases, no scale factors): no scale-factor estimates.
    assert result.run.solution.accel_scale_factor is None
    assert "accel_scale_factor_ppm" not in s["sensor_estimates"]
    aided = s["errors_vs_truth"]["aided"]
    assert aided["within_3sigma_share"] >= 0.9
    # The truth sits ~8 m off (the data README): by accuracy the offset
    # dominates both the filter and the single-point fixes; by precision
    # (each less its own mean offset, fixed epochs) the filter beats the
    # fixes it is fed (0.49 m against 1.23 m here).
    precise, spp = s["errors_vs_truth_precision"], s["spp_errors_vs_truth_precision"]
    assert aided["rms_horizontal_m"] > 5.0 and s["spp_errors_vs_truth"]["rms_horizontal_m"] > 5.0
    assert precise["aided"]["rms_horizontal_m"] < 0.6 * spp["rms_horizontal_m"]
    assert precise["aided"]["within_3sigma_share"] >= 0.9
    assert np.hypot(*precise["offset_removed_ned_m"][:2]) > 5.0


def test_gnss_quality_defaults_to_every_epoch_of_the_file(tmp_path):
    """Without [gnss] quality every epoch of the file is used, each with its
    own σ, and a warning names the qualities: here a quarter of the epochs
    turned into standalone fixes (Q = 5, σ 1.5 m), which quality = [1, 2]
    drops."""
    lines = (EX / "drive_60s.pos").read_text().splitlines()
    body = [k for k, line in enumerate(lines) if not line.startswith("%")]
    for k in body[::4]:
        fields = lines[k].split()
        fields[5] = "5.0000000"
        fields[7:10] = ["1.5000000"] * 3
        lines[k] = " ".join(fields)
    pos = tmp_path / "mixed.pos"
    pos.write_text("\n".join(lines) + "\n")
    given = _config(
        tmp_path, **{'pos = "real-imu-gnss/drive_60s.pos"\nquality = [1, 2]': f'pos = "{pos}"'}
    )
    with pytest.warns(
        UserWarning,
        match=r"gnss.quality not given: .*Q = 1 \(fix\) 195, Q = 2 \(float\) 6, "
        r"Q = 5 \(single\) 67\)",
    ):
        every = mn.navigate(given, data_root=DATA)
    two = mn.navigate(
        _config(tmp_path, **{'pos = "real-imu-gnss/drive_60s.pos"': f'pos = "{pos}"'}),
        data_root=DATA,
    )
    mixed = mn.read_pos(pos)
    single = np.asarray(mixed.quality) == 5
    start = every.summary["start_gps_time_s"]
    t = np.asarray(mixed.gps_time)
    in_run = (t >= start) & (t <= start + every.summary["duration_s"])
    added = int(np.sum(single & in_run))
    assert added > 50
    assert every.summary["gnss_epochs_used"] == two.summary["gnss_epochs_used"] + added
    # The standalone epochs' σ keeps them from pulling the solution off.
    assert every.summary["errors_vs_truth"]["aided"]["rms_horizontal_m"] < 0.1


def test_truth_heights_above_mean_sea_level(tmp_path):
    """[truth] height = "msl": the heights read are the file's plus the
    geoid separation (ellipsoidal h = H + N). On the walk the single-point
    heights (ellipsoidal, from pseudoranges) then agree with the truth to a
    couple of metres; read as ellipsoidal, the truth is 21 m high."""
    from memsnav.realdata.pipeline import read_truth

    msl = mn.load_config(_config(tmp_path, WALK), DATA)
    truth = read_truth(msl)
    assert truth is not None
    r_truth = truth.position_ecef()
    pos = mn.read_pos(EX / "walk_40s.pos")
    fixed = np.asarray(pos.quality) == 1
    heights = np.asarray(mn.ecef_to_geodetic(r_truth))[:, 2]
    np.testing.assert_allclose(heights, np.asarray(pos.lla)[fixed, 2] - 21.387, atol=1e-6)
    # The receiver's own NAV-PVT at the site: hMSL 1601.435 m, ellipsoidal
    # 1580.048 m (the data README).
    assert abs(heights.mean() - 1580.0) < 5.0
    down = {}
    for datum in ("msl", "ellipsoidal"):
        text = (
            WALK
            if datum == "msl"
            else WALK.replace('height = "msl"\ngeoid_separation_m = -21.387\n', "")
        )
        result = mn.navigate(_config(tmp_path, text), data_root=DATA, duration_s=15.0)
        down[datum] = result.summary["spp_errors_vs_truth_precision"]["offset_removed_ned_m"][2]
    # Down error = solution − truth: a truth 21.4 m too high reads as +21.4 m.
    assert abs(down["msl"]) < 4.0
    assert down["ellipsoidal"] == pytest.approx(down["msl"] + 21.387, abs=1e-3)


def test_truth_datum_keys_are_checked(tmp_path):
    with pytest.raises(ValueError, match=r"truth.geoid_separation_m: give it exactly when"):
        mn.load_config(_config(tmp_path, WALK, **{"geoid_separation_m = -21.387\n": ""}), DATA)
    with pytest.raises(ValueError, match=r"gnss.geoid_separation_m: give it exactly when"):
        mn.load_config(
            _config(tmp_path, **{'mode = "loose"': 'mode = "loose"\ngeoid_separation_m = -21.0'}),
            DATA,
        )
    with pytest.raises(ValueError, match=r"truth.geoid_separation_m: .*-120"):
        mn.load_config(_config(tmp_path, WALK, **{"-21.387": "-500.0"}), DATA)
    with pytest.raises(ValueError, match=r"truth.score: must be one of"):
        mn.load_config(_config(tmp_path, WALK, **{'"precision"': '"precise"'}), DATA)


def test_periodic_outages_are_scheduled_and_scored(tmp_path):
    extra = "[outages]\nfirst_s = 10.0\nlength_s = 5.0\nevery_s = 20.0\n"
    result = mn.navigate(_config(tmp_path, extra=extra), data_root=DATA)
    e = result.summary["errors_vs_truth"]
    assert result.summary["outages_s"] == [[10.0, 5.0], [30.0, 5.0], [50.0, 5.0]]
    assert [e[f"outage_{i}"]["epochs"] for i in (1, 2, 3)] == [20, 20, 20]
    assert e["by_outage_length_s"]["5"]["epochs"] == 60
    assert e["by_outage_length_s"]["5"]["max_horizontal_m"] < 5.0


# --- outputs ----------------------------------------------------------------


def test_outputs_are_complete_and_replace_an_earlier_run(tmp_path):
    extra = "[outages]\nwindows_s = [[30.0, 10.0]]\n"
    out = tmp_path / "out"
    out.mkdir()
    # A file an earlier navigate wrote (its marker lists it) goes.
    (out / "stale.csv").write_text("from an earlier run")
    (out / MARKER).write_text(json.dumps({"written_by": "navigate", "files": ["stale.csv"]}))
    result = mn.navigate(_config(tmp_path, extra=extra), data_root=DATA)
    assert not (out / "stale.csv").exists()
    assert "drive_60s.csv" in json.loads((out / MARKER).read_text())["files"]
    csv = np.loadtxt(out / "drive_60s.csv", delimiter=",", skiprows=1)
    assert csv.shape == (len(result.run), 16)
    back = mn.read_pos(out / "drive_60s.pos")
    k = np.searchsorted(csv[:, 0], back.gps_time[5])
    np.testing.assert_allclose(np.degrees(back.lla[5, :2]), csv[k, 1:3], atol=1e-9)
    np.testing.assert_allclose(back.velocity_ned[5], csv[k, 4:7], atol=1e-5)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["errors_vs_truth"] == result.summary["errors_vs_truth"]
    reference = doc_text("reference/summary-json.md")
    undocumented = [key for key in summary if f"`{key}`" not in reference]
    assert not undocumented, f"docs/reference/summary-json.md does not list {undocumented}"
    html = (out / "report.html").read_text()
    assert 'id="track"' in html and 'id="errors"' in html and "outage 1 (30 s)" in html
    assert (out / "figures" / "errors.png").exists()
    assert (out / "summary.json").stat().st_mode & 0o777 == 0o644


def test_report_answers_first_and_marks_what_its_figures_mean(tmp_path, monkeypatch):
    """The navigate report: the answer before the track; every outage at a
    standstill marked as the rule says (half of it or more in a detected
    standstill) and left out of its length's row, which combines the
    others' epochs; the NEES beside the share in 3σ; and errors drawn with
    their 3σ on a scale that shows both. (The drive, whose truth is its
    GNSS input, says so: test_navigate_cli_prints_the_answer_first.)"""
    figures = capture_figures(monkeypatch)
    # The walk starts with 9 s at rest: the first window lies in it.
    extra = "[outages]\nwindows_s = [[1.0, 5.0], [15.0, 5.0], [25.0, 5.0], [31.0, 4.0]]\n"
    s = mn.navigate(_config(tmp_path, WALK, extra=extra), data_root=DATA).summary
    assert figures.keys() == {"track", "errors"} and not any(figures.values()), figures
    errors = s["errors_vs_truth"]
    windows = {f"outage_{k}": w for k, w in enumerate(s["outages_s"], start=1)}
    for key, (start, length) in windows.items():
        still = sum(max(0.0, min(b, start + length) - max(a, start)) for a, b in s["standstills_s"])
        assert errors[key]["standstill_s"] == pytest.approx(still, abs=1e-6)
        assert errors[key]["at_standstill"] == (still >= 0.5 * length)
    assert errors["outage_1"]["at_standstill"]  # the test covers both kinds
    assert not errors["outage_2"]["at_standstill"]
    for length, st in errors["by_outage_length_s"].items():
        moving = [
            errors[key]
            for key, (_, window) in windows.items()
            if f"{window:g}" == length and not errors[key]["at_standstill"]
        ]
        epochs = sum(o["epochs"] for o in moving)
        assert st["epochs"] == epochs
        mean_square = sum(o["epochs"] * o["rms_horizontal_m"] ** 2 for o in moving) / epochs
        assert st["rms_horizontal_m"] == pytest.approx(mean_square**0.5)
    # The walk's truth is its own RTK solution, not the filter's input.
    assert not s["truth_is_gnss_input"]
    html = (tmp_path / "out" / "report.html").read_text()
    assert html.index("The answer") < html.index("Track")
    assert "outage 1 (1 s): at a standstill" in html
    assert "the 2 outages of 5 s in motion (of 3)" in html
    assert "NEES/dof" in html and "own GNSS input" not in html
    assert not page_problems(html), page_problems(html)


def test_a_run_without_outages_does_not_speak_of_them(tmp_path):
    """The walk schedules no outage: its answer says so, and no caption or
    statistics row mentions outages it does not have (the walk's
    caption named red outage shading)."""
    mn.navigate(_config(tmp_path, WALK), data_root=DATA, duration_s=20.0)
    html = (tmp_path / "out" / "report.html").read_text()
    answer = html[html.index("The answer") : html.index("The run")]
    assert "no GNSS outage scheduled" in answer
    captions = re.findall(r"<figcaption>(.*?)</figcaption>", html, re.S)
    assert len(captions) == 2 and not any("outage" in c for c in captions), captions
    statistics = html[html.index("Statistics") : html.index("Resets")]
    assert "outage" not in statistics.lower()
    assert not page_problems(html), page_problems(html)
    # Each reset's change with its unit: the walk's heading reset in rad and °.
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    heading = [r for r in summary["resets"] if r["kind"] == "heading"]
    assert heading and all(r["unit"] == "rad" for r in heading)
    change = heading[0]["change"]
    cell = re.search(r"<td>([-\d.]+) rad \(([-\d.]+)°\)</td>", html[html.index("Resets") :])
    assert cell, "the resets table gives no heading change in rad and degrees"
    assert float(cell.group(1)) == pytest.approx(change, rel=5e-3)
    assert float(cell.group(2)) == pytest.approx(np.degrees(change), rel=5e-3)


def test_the_scale_check_finds_errors_flattened_by_their_bounds():
    """What the reports' figure check catches: errors of 0.3 m under 3σ
    bounds of 30 m on a linear axis (the navigate figure before the report rework),
    and not the same on a scale that shows both."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    t = np.arange(100.0)
    ax.plot(t, 0.3 * np.sin(t))
    ax.plot(t, np.full_like(t, 30.0), gid="bound")
    ax.plot(t, np.full_like(t, -30.0), gid="bound")
    assert hidden_by_bounds(fig)
    ax.set_yscale("symlog", linthresh=0.1)
    assert not hidden_by_bounds(fig)
    plt.close(fig)


def test_a_name_must_not_leave_the_output_folder(tmp_path):
    for name in ("../x", "sub/x", ""):
        cfg = _config(tmp_path, **{'name = "drive_60s"': f'name = "{name}"'})
        with pytest.raises(ValueError, match=r"run\.toml: name: must be a plain file name"):
            mn.navigate(cfg, data_root=DATA, duration_s=5.0)
    assert not (tmp_path / "x").exists() and not (tmp_path / "out").exists()


def test_navigate_cli_prints_the_answer_first(tmp_path, capsys):
    """The outage errors with their schedule come first, then the aided
    errors with the NEES beside the share in 3σ, and, the truth being the
    filter's own GNSS input, a line saying so (and none scoring the fixes
    against themselves); the files after."""
    cfg = _config(tmp_path, extra="[outages]\nfirst_s = 5.0\nlength_s = 5.0\nevery_s = 15.0\n")
    args = ["navigate", "--config", str(cfg), "--data-root", str(DATA), "--duration", "40"]
    assert cli.main(args) == 0
    lines = capsys.readouterr().out.splitlines()
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    errors = summary["errors_vs_truth"]
    assert lines[0] == "drive_60s: loose coupling, 40 s; 3 GNSS outages of 5 s every 15 s from 5 s"
    # The truth by its file's name (no [truth] name), neither moved nor offset.
    assert lines[1] == "  truth: drive_60s.pos"
    del lines[1]
    outages = errors["by_outage_length_s"]["5"]
    assert lines[1] == (
        f"  the 3 outages of 5 s: horizontal RMS {outages['rms_horizontal_m']:.3g} m, max "
        f"{outages['max_horizontal_m']:.3g} m, vertical RMS {outages['rms_vertical_m']:.3g} m; "
        f"{100 * outages['within_3sigma_share']:.1f} % within 3σ "
        f"(N/E {100 * outages['within_3sigma_share_horizontal']:.1f} %), NEES/dof "
        f"{outages['nees_per_dof']:.2g}"
    )
    assert lines[2].startswith(
        f"  aided: horizontal RMS {errors['aided']['rms_horizontal_m']:.3g} m"
    )
    assert lines[3].startswith("  the truth is the filter's own GNSS input")
    assert [line.split(":")[0] for line in lines[4:]] == ["csv", "pos", "summary", "report"]
    assert cli.main(["navigate", "--config", str(tmp_path / "missing.toml")]) == 1
    assert "cannot read" in capsys.readouterr().err


def test_navigate_reports_a_cut_imu_log(tmp_path):
    shutil.copy(EX / "drive_60s.csv.tag", tmp_path / "imu.csv.tag")
    text = (EX / "drive_60s.csv").read_text()
    (tmp_path / "imu.csv").write_text(text + "0.1,0.0")
    cfg = _config(
        tmp_path,
        **{
            '"real-imu-gnss/drive_60s.csv"': f'"{tmp_path / "imu.csv"}"',
            '"real-imu-gnss/drive_60s.csv.tag"': f'"{tmp_path / "imu.csv.tag"}"',
        },
    )
    with pytest.warns(UserWarning, match=r"imu.csv:\d+: last line cut short"):
        mn.navigate(cfg, data_root=DATA, duration_s=5.0)


def test_position_only_fixes_give_the_aids_a_ground_speed():
    """Fixes without velocity: the engine takes the ground speed and course
    from consecutive positions, so a vibration-free simulated IMU cruising
    smoothly is not taken for a standstill (no ZUPT pins the velocity while
    moving) and the heading is set at the first motion."""
    trajectory = mn.Trajectory.random(300.0, seed=1, stationary_start=20.0)
    t = trajectory.time
    k = np.arange(0, len(t), 25)
    fixes = mn.fixes_from_solution(
        t[k],
        trajectory.position_geodetic()[k],
        np.full((len(k), 3), 0.02),
        velocity_ned=np.full((len(k), 3), np.nan),
    )
    run = mn.navigate_log(t, trajectory.specific_force, trajectory.angular_rate, fixes)
    sol = run.solution
    measurements = sol.measurements
    zupt = np.asarray(measurements["kind"]) == "zero_velocity"
    speed = np.linalg.norm(trajectory.velocity_ecef, axis=1)
    at = np.searchsorted(t, np.asarray(measurements["time"])[zupt])
    assert np.all(speed[np.minimum(at, len(t) - 1)] < 0.5)
    assert "heading" in [str(k) for k in sol.resets["kind"]]
    # Attitude error against the truth after the first motion: about a
    # degree at most (the heading from a course of position differences),
    # not the tenth of a radian that ZUPTs while moving caused.
    index = np.searchsorted(t, np.asarray(sol.time))
    relative = np.einsum("nij,nkj->nik", trajectory.attitude[index], np.asarray(sol.attitude))
    angle = np.arccos(np.clip((np.trace(relative, axis1=1, axis2=2) - 1) / 2, -1, 1))
    moving = np.asarray(sol.time) > t[0] + 40.0
    assert np.max(angle[moving]) < 0.03


def test_paths_in_a_configuration_are_relative_to_it(tmp_path, monkeypatch):
    """``output`` and ``[imu] calibration`` resolve against the
    configuration's folder, whatever the working directory; the recordings,
    not beside it, against the data root; ``output=`` (``--output``) against
    the working directory (docs/tutorials/first-session.md, "Paths in a
    configuration")."""
    from memsnav.calibration.file import ImuCalibration

    zero3, zero33 = np.zeros(3), np.zeros((3, 3))
    folder = tmp_path / "project"
    folder.mkdir()
    ImuCalibration(
        session="drive",
        accelerometer=mn.AccelerometerModel(zero3, zero3, zero33, zero3),
        gyroscope=mn.GyroscopeModel(zero3, zero3, zero33, zero33),
        accelerometer_std=mn.AccelerometerModel(zero3, zero3, zero33, zero3),
        gyroscope_std=mn.GyroscopeModel(zero3, zero3, zero33, zero33),
        parameter_names=["accelerometer bias_x"],
        covariance=np.zeros((1, 1)),
        nominal={
            "accel_scale": np.ones(3),
            "accel_offset": zero3,
            "gyro_scale": np.ones(3),
            "gyro_offset": zero3,
        },
        sample_rate=100.0,
    ).save(folder / "cal.json")
    text = DRIVE.format(out="results/drive").replace(
        "[imu]\n", '[imu]\ncalibration = "cal.json"\n', 1
    )
    config = folder / "run.toml"
    config.write_text(text)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    result = mn.navigate(config, data_root=DATA, duration_s=5.0)
    assert Path(result.files["summary"]).parent == folder / "results" / "drive"
    assert result.summary["imu_calibration"] == str(folder / "cal.json")
    assert list(elsewhere.iterdir()) == []
    result = mn.navigate(config, data_root=DATA, output="given", duration_s=5.0)
    assert (elsewhere / "given" / "summary.json").exists()


def test_a_configuration_beside_its_data_runs_without_a_data_root(tmp_path, monkeypatch, capsys):
    """A user's folder holding the configuration and its files: the
    relative data paths resolve there, with the data root pointing at an
    empty folder (no --data-root, a $MEMSNAV_DATA_ROOT without the files); a
    file in neither place is an error naming the key and both paths; the
    data root still serves a file not beside the configuration."""
    folder = tmp_path / "mylogger"
    folder.mkdir()
    for name in ("drive_60s.csv", "drive_60s.csv.tag", "drive_60s.pos"):
        shutil.copy(EX / name, folder / name)
    empty = tmp_path / "empty_root"
    empty.mkdir()
    monkeypatch.setenv("MEMSNAV_DATA_ROOT", str(empty))
    config = folder / "mylogger.toml"
    config.write_text(DRIVE.format(out="out").replace("real-imu-gnss/", ""))
    monkeypatch.chdir(tmp_path)
    assert cli.main(["navigate", "--config", str(config), "--duration", "5"]) == 0
    summary = json.loads((folder / "out" / "summary.json").read_text())
    assert "failure" not in summary and summary["imu_samples"] > 400
    cfg = mn.load_config(config)
    assert cfg.data_path("imu", "file") == folder / "drive_60s.csv"

    (folder / "drive_60s.pos").unlink()
    with pytest.raises(ValueError) as caught:
        mn.navigate(config, duration_s=5.0)
    message = str(caught.value)
    assert "gnss.pos: no such file 'drive_60s.pos': tried " in message
    assert f"{folder / 'drive_60s.pos'} (beside the configuration)" in message
    assert f"{empty / 'drive_60s.pos'} (under the data root" in message
    # The data root holds what the folder does not.
    shutil.copy(EX / "drive_60s.pos", empty / "drive_60s.pos")
    assert mn.load_config(config).data_path("gnss", "pos") == empty / "drive_60s.pos"
    assert mn.navigate(config, duration_s=5.0).failure is None


def test_integrity_keys_are_the_filter_solutions(tmp_path):
    """summary.json's integrity has the keys of ``FilterSolution.integrity``
    (one set of names, unit-suffixed where they carry units), with its
    times after the start; compared on a run with alerts (a gyro declared
    in rad/s, its data in °/s)."""
    cfg = _config(tmp_path, **{'gyro_unit = "deg/s"': 'gyro_unit = "rad/s"'})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError, match="gyro_unit") as caught:
            mn.navigate(cfg, data_root=DATA)
    result = caught.value.result  # type: ignore[attr-defined]
    own = result.run.solution.integrity.to_dict()
    own["alerts"] = [a.to_dict() for a in own["alerts"]]
    own["consistency"] = [c.to_dict() for c in own["consistency"]]
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())["integrity"]
    assert own["alerts"] and own["consistency"], own
    assert set(summary) == set(own) == {"diverged", "alerts", "consistency"}
    for key in ("alerts", "consistency"):
        assert [set(e) for e in summary[key]] == [set(e) for e in own[key]]
    assert set(own["alerts"][0]) == {"kind", "time_s", "message"}
    assert set(own["consistency"][0]) == {
        "kind",
        "windows",
        "windows_above_band",
        "max_band_ratio",
        "max_at_s",
    }
    t0 = result.summary["start_gps_time_s"]
    assert summary["alerts"][0]["time_s"] == pytest.approx(own["alerts"][0]["time_s"] - t0)
    assert summary["consistency"][0]["max_at_s"] == pytest.approx(
        own["consistency"][0]["max_at_s"] - t0
    )
