"""Figures the README and the user guide quote that no benchmark script
writes (the scripts write theirs between markers: docs/*.py --write),
each compared with a fresh run within the rounding it is quoted with.
The drive calibration's figures are checked where its session runs
(test_drive_calibration)."""

import re
import warnings
from pathlib import Path

import pytest
from shared_data import shared_data

import memsnav as mn

ROOT = Path(__file__).resolve().parent.parent


def _quoted(page: str, pattern: str) -> tuple[float, ...]:
    text = " ".join((ROOT / page).read_text().split())
    found = re.search(pattern, text)
    assert found, f"{page} no longer quotes {pattern!r}"
    return tuple(float(v) for v in found.groups())


def test_getting_started_quotes_what_its_session_prints(tmp_path, monkeypatch, capsys):
    """The first session's INS fed the truth stays within millimetres; the
    raw MEMS drifts by the distance the page quotes."""
    (drift_km,) = _quoted("docs/getting-started.md", r"drifts by about ([\d.]+) km")
    page = (ROOT / "docs" / "getting-started.md").read_text()
    session = re.search(r"## A first session in Python\n\n```python\n(.*?)```", page, re.S)
    monkeypatch.chdir(tmp_path)
    exec(compile(session.group(1), "getting-started.md", "exec"), {})
    truth_error, drift = (float(v) for v in capsys.readouterr().out.split())
    assert truth_error < 0.01  # "mm over 120 s"
    assert abs(drift / 1000.0 - drift_km) <= 0.05


@pytest.mark.slow
def test_readme_quotes_the_walk_by_precision(tmp_path):
    """ "the walk's truth sits ~9 m off, so the walk is also scored by
    precision: 0.50 m horizontal against single-point's 1.03 m"."""
    offset_m, forward_m, spp_m = _quoted(
        "README.md",
        r"truth sits ~([\d.]+) m off, so the walk is also scored by precision: ([\d.]+) m "
        r"horizontal against single-point's ([\d.]+) m",
    )
    data = shared_data("real-imu-gnss/walk_0827").parent.parent
    config = mn.load_config(ROOT / "examples" / "walk_0827.toml", data)
    config.values["report"]["html"] = False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the log's last line is cut short
        s = mn.navigate(config, output=tmp_path / "walk").summary
    precise = s["errors_vs_truth_precision"]
    north, east, _ = precise["offset_removed_ned_m"]
    assert abs((north**2 + east**2) ** 0.5 - offset_m) <= 0.5
    assert abs(precise["aided"]["rms_horizontal_m"] - forward_m) <= 0.005
    assert abs(s["spp_errors_vs_truth_precision"]["rms_horizontal_m"] - spp_m) <= 0.005
