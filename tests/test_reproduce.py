"""``memsnav reproduce`` end to end in a small mode: the files and their
permissions, the keys of summary.json, verdicts recomputed from it by an
independent statement of each criterion, a report whose every figure is
present and decodes as an image (parsed from the HTML, as a browser would
load it), and an interrupted run's report and summary."""

import base64
import contextlib
import csv
import html
import io
import json
import os
import re
import signal
import subprocess
import sys
import time
from html.parser import HTMLParser

import matplotlib.image
import pytest
from report_checks import capture_figures, page_problems
from test_claims import recomputed

import memsnav as mn
from memsnav.cli import main

# Every test here runs the whole study (about a minute) or interrupts one.
pytestmark = pytest.mark.slow

FIGURES = sorted([f"fig{n:02d}" for n in range(3, 19)] + ["partial_outage"])
CLAIM_IDS = [
    "accel_bias_misalignment_well_estimated",
    "gyro_bias_misalignment_well_estimated",
    "inversion_accel_mse",
    "inversion_gyro_mse",
    "calibration_helps_first_150s",
    "calibrated_mems_like_ins",
    "mems_drifts_in_outage",
    "calibration_helps_little_in_outage",
]
IMUS = {"ins", "mems", "calibrated_mems"}


class _Figures(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.figures: dict[str, str] = {}
        self._current: str | None = None

    def handle_starttag(self, tag, attrs):
        attributes = dict(attrs)
        if tag == "figure":
            self._current = attributes.get("id")
        elif tag == "img" and self._current is not None:
            self.figures[self._current] = attributes["src"]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    printed = io.StringIO()
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(printed):
        figures = capture_figures(patch)
        code = main(["reproduce", "--out", str(out), "--runs", "2", "--seed", "5", "--quiet"])
    assert code == 0
    RUN.update(figures=figures, printed=printed.getvalue())
    return out


# What the fixture's run printed and the figures its report drew.
RUN: dict = {}


def test_the_terminal_answers_first_with_every_verdict(study):
    summary = json.loads((study / "summary.json").read_text())
    lines = RUN["printed"].splitlines()
    assert lines[0] == "The paper's claims, judged (2 runs per experiment, seed 5):"
    claims = summary["claims"]
    for line, claim in zip(lines[1:], claims, strict=False):
        assert re.split(r"\s{2,}", line.strip(), maxsplit=1) == [claim["verdict"], claim["title"]]
    assert lines[len(claims) + 1].startswith(f"report: {study / 'report.html'}")
    assert len(lines) == len(claims) + 2


def test_no_figure_hides_its_data_behind_a_bound(study):
    assert sorted(RUN["figures"]) == FIGURES
    assert not any(RUN["figures"].values()), RUN["figures"]


def test_no_table_runs_past_the_page(study):
    problems = page_problems((study / "report.html").read_text())
    assert not problems, problems


def test_summary_json_has_the_documented_keys(study):
    summary = json.loads((study / "summary.json").read_text())
    assert {
        "experiments",
        "claims",
        "calibration",
        "inversion",
        "navigation",
        "partial_outage",
        "runs",
        "seed",
        "elapsed_s",
        "memsnav_version",
        "machine",
    } <= summary.keys()
    assert summary["seed"] == 5 and summary["memsnav_version"] == mn.__version__
    assert summary["runs"]["navigation"] == 2
    assert summary["machine"]["threads"] >= 1
    for name, state in summary["experiments"].items():
        assert state == {
            "planned_runs": state["completed_runs"],
            "completed_runs": state["completed_runs"],
            "state": "completed",
        }, name
    cal = summary["calibration"]
    assert cal["accelerometer"].keys() == {"bias", "scale_factor", "misalignment", "nonlinearity"}
    assert cal["gyroscope"].keys() == {"bias", "scale_factor", "misalignment", "g_sensitivity"}
    assert cal["accelerometer"]["bias"]["unit"] == "(m/s²)²"
    for sensor, axes in (("accelerometer", "uvw"), ("gyroscope", "pqr")):
        for group in cal[sensor].values():
            assert set(group["per_axis"]) == set(axes)
            for entry in [group, *group["per_axis"].values(), *group["per_parameter"].values()]:
                assert entry["mse_eiv"] > 0 and entry["mse_ls"] > 0 and entry["crb"] > 0
                assert entry["efficiency_eiv"] == pytest.approx(entry["mse_eiv"] / entry["crb"])
    assert summary["inversion"].keys() >= {"accel_mse_g2", "gyro_mse_dps2", "accel_mse_se_g2"}
    assert 0 < summary["inversion"]["accel_mse_g2"] < 1
    for scenario in ("nominal", "outage"):
        nav = summary["navigation"][scenario]
        assert nav["imus"].keys() == IMUS and nav["completed_runs"] == 2
        for values in nav["imus"].values():
            assert values.keys() >= {
                "rms_position_error_m",
                "rms_position_error_first_150s_m",
                "rms_position_error_after_150s_m",
                "final_position_error_m",
                "mean_nees_per_dof",
                "standard_error",
            }
            assert all(v >= 0 for k, v in values.items() if k != "standard_error")
    for values in summary["navigation"]["outage"]["imus"].values():
        assert values["max_position_error_during_outage_m"] > 0
    assert (
        "max_position_error_during_outage_m" not in summary["navigation"]["nominal"]["imus"]["ins"]
    )
    scenarios = summary["partial_outage"]["scenarios"]
    assert list(scenarios) == [
        "tight, 0 satellites",
        "tight, 1 satellite",
        "tight, 2 satellites",
        "tight, 3 satellites",
        "loose",
    ]
    assert [c["id"] for c in summary["claims"]] == CLAIM_IDS
    for claim in summary["claims"]:
        assert claim.keys() >= {"id", "paper", "memsnav", "criterion", "verdict"}


def test_verdicts_follow_from_summary_json(study):
    summary = json.loads((study / "summary.json").read_text())
    verdicts = {c["id"]: c["verdict"] for c in summary["claims"]}
    # Each criterion read from its printed words, independently of
    # memsnav.report.claims (test_claims.recomputed).
    assert verdicts == recomputed(summary)
    # Every verdict is stated in the report under its claim's title, and
    # the claims' answer comes before the setup.
    report = (study / "report.html").read_text()
    for claim in summary["claims"]:
        assert html.escape(claim["title"]) in report and claim["verdict"] in report
    assert report.index("The answer") < report.index("Setup")


def _prose(html_text):
    """The page's text: the body without its embedded images."""
    body = html_text[html_text.index("<body>") :]
    return re.sub(r'src="data:image/png;base64,[^"]*"', "", body)


def test_report_prose_has_no_python_reprs_or_nan(study):
    prose = _prose((study / "report.html").read_text())
    for bad in ("None", "nan", "True", "False", "(1.0, 1.0, 5.0)"):
        assert bad not in prose, bad


def test_files_have_the_permissions_of_plain_files(study):
    umask = os.umask(0)
    os.umask(umask)
    expected = 0o666 & ~umask
    for path in [study / "report.html", study / "summary.json", *study.glob("figures/*")]:
        assert path.stat().st_mode & 0o777 == expected, path


def test_report_embeds_every_figure_as_a_decodable_image(study):
    parser = _Figures()
    parser.feed((study / "report.html").read_text())
    assert sorted(parser.figures) == FIGURES
    for name, src in parser.figures.items():
        prefix = "data:image/png;base64,"
        assert src.startswith(prefix), name
        path = study / f"{name}-decoded.png"
        path.write_bytes(base64.b64decode(src[len(prefix) :]))
        image = matplotlib.image.imread(path)
        assert image.shape[0] > 100 and image.shape[1] > 100, name
        # Not a blank page: the figure has ink.
        assert image[..., :3].std() > 0.01, name


def test_figures_are_written_as_png_svg_and_csv(study):
    for name in FIGURES:
        for ext in ("png", "svg", "csv"):
            if name == "fig13" and ext == "csv":
                # A drawing, no data: no empty CSV.
                assert not (study / "figures" / "fig13.csv").exists()
                continue
            assert (study / "figures" / f"{name}.{ext}").stat().st_size > 0, (name, ext)
        assert (study / "figures" / f"{name}.svg").read_text().lstrip().startswith("<?xml")
    # The curves behind fig. 14 are there: position error vs time per IMU.
    with open(study / "figures" / "fig14.csv") as f:
        rows = list(csv.DictReader(f))
    labels = {r["label"] for r in rows}
    assert any("INS" in label or "ins" in label for label in labels), labels
    times = [float(r["x"]) for r in rows if r["curve"] == "0"]
    assert max(times) >= 590.0


def test_no_temporary_files_left_behind(study):
    assert not list(study.rglob("*.tmp"))


def test_ctrl_c_keeps_the_completed_runs_and_writes_the_report(tmp_path):
    # The test runner may run with SIGINT ignored (a background job): give the
    # child the default disposition, as a terminal would.
    # 50 sets x 400 runs: a calibration experiment of a minute or more on 2
    # cores (20 000 runs), so the signal lands in it however fast the runs are.
    child = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "memsnav",
            "reproduce",
            "--out",
            str(tmp_path),
            "--runs",
            "400",
            "--quiet",
        ],
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(6.0)  # well into the calibration experiment
    child.send_signal(signal.SIGINT)
    _, stderr = child.communicate(timeout=120)
    assert child.returncode == 130, stderr
    assert "Traceback" not in stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["interrupted"] is True
    state = summary["experiments"]["calibration"]
    assert state["state"] == "interrupted"
    assert 0 < state["completed_runs"] < state["planned_runs"] == 50 * 400
    assert summary["experiments"]["inversion"] == {
        "planned_runs": 400,
        "completed_runs": 0,
        "state": "not run",
    }
    assert summary["inversion"] is None  # never started
    # The terminal says how far each experiment got.
    assert f"calibration: {state['completed_runs']}/20000 runs, interrupted" in stderr
    assert "inversion: 0/400 runs, not run" in stderr
    # No claim is judged on an incomplete experiment.
    assert {c["verdict"] for c in summary["claims"]} == {"not evaluated"}
    # The calibration runs completed before Ctrl-C are kept and summarised.
    assert summary["calibration"]["accelerometer"]["bias"]["mse_eiv"] > 0
    report = (tmp_path / "report.html").read_text()
    assert report.count("<figure") >= 8
    assert "Interrupted after" in report and "nan" not in _prose(report)
    assert not list(tmp_path.rglob("*.tmp"))
