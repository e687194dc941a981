"""``memsnav reproduce`` end to end in a small mode: the files, the keys of
summary.json, and a report whose every figure is present and decodes as an
image (parsed from the HTML, as a browser would load it)."""

import base64
import csv
import json
import signal
import subprocess
import sys
import time
from html.parser import HTMLParser

import matplotlib.image
import numpy as np
import pytest

import memsnav as mn

FIGURES = [f"fig{n:02d}" for n in range(3, 19)]
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
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "memsnav",
            "reproduce",
            "--out",
            str(out),
            "--runs",
            "2",
            "--seed",
            "5",
            "--quiet",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    return out


def test_summary_json_has_the_documented_keys(study):
    summary = json.loads((study / "summary.json").read_text())
    assert {
        "calibration",
        "inversion",
        "navigation",
        "runs",
        "seed",
        "elapsed_s",
        "memsnav_version",
    } <= summary.keys()
    assert summary["seed"] == 5 and summary["memsnav_version"] == mn.__version__
    assert summary["runs"]["navigation"] == 2
    assert summary["calibration"]["accelerometer"].keys() >= {
        "bias",
        "scale_factor",
        "misalignment",
        "nonlinearity",
    }
    assert summary["calibration"]["gyroscope"].keys() >= {
        "bias",
        "scale_factor",
        "misalignment",
        "g_sensitivity",
    }
    assert summary["inversion"].keys() >= {"accel_mse_g2", "gyro_mse_dps2"}
    for scenario in ("nominal", "outage"):
        per_imu = summary["navigation"][scenario]
        assert per_imu.keys() == IMUS
        for values in per_imu.values():
            assert values.keys() >= {
                "rms_position_error_m",
                "final_position_error_m",
                "mean_nees_per_dof",
            }
            assert all(np.isfinite(v) and v >= 0 for v in values.values())
    for values in summary["navigation"]["outage"].values():
        assert values["max_position_error_during_outage_m"] > 0
    # MSEs are positive numbers in SI units.
    assert 0 < summary["inversion"]["accel_mse_g2"] < 1
    assert all(
        v > 0 for v in summary["calibration"]["accelerometer"].values() if isinstance(v, float)
    )


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
    assert summary["inversion"] is None  # never started
    # The calibration runs completed before Ctrl-C are kept and summarised.
    assert summary["calibration"]["accelerometer"]["bias"] > 0
    assert (tmp_path / "report.html").read_text().count("<figure") >= 8
    assert not list(tmp_path.rglob("*.tmp"))
