"""A navigate run says what it did with the carrier phase it was asked to
use: the walk's UBX log on the four GPS satellites of
``examples/walk_0827.toml`` has no epoch with the five clean carrier changes
a batch needs, so none is used, the run counts them as "too-few" and warns;
with Galileo and BeiDou added the same log's changes are used. Satellite
selections name their system; a bare number is read as GPS with a
DeprecationWarning."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import pytest
from shared_data import shared_data

import memsnav as mn

ROOT = Path(__file__).parent.parent


def _walk_ubx(tmp_path: Path, example: str, gnss_lines: dict[str, str]) -> Any:
    """``examples/<example>`` on the UBX log, carrier phase on, no HTML;
    ``gnss_lines`` replace lines of the example by their start."""
    data = shared_data("real-imu-gnss/walk_0827").parent.parent
    lines = []
    for line in (ROOT / "examples" / example).read_text().splitlines():
        key = next((k for k in gnss_lines if line.startswith(k)), None)
        if key is not None:
            line = gnss_lines[key]
        if line.startswith("output ="):
            line = f'output = "{tmp_path / "out"}"'
        lines.append(line)
    path = tmp_path / example
    path.write_text("\n".join(lines) + "\n")
    config = mn.load_config(path, data)
    config.values["report"]["html"] = False
    config.engine.setdefault("gnss", {})["carrier_phase"] = True
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = mn.navigate(config, output=tmp_path / "out")
    return result, [str(w.message) for w in caught]


def test_four_gps_satellites_use_no_carrier_change_and_say_why(tmp_path):
    result, warned = _walk_ubx(
        tmp_path,
        "walk_0827.toml",
        {
            "obs =": 'ubx = "real-imu-gnss/walk_0827/gnss_1730.ubx"',
            "nav =": "",
        },
    )
    use = result.summary["carrier_phase"]
    print(use)
    assert use["used"] == 0
    # Nearly every change is clean: what stops them is their number.
    assert use["too_few"] > 0.9 * use["changes"]
    assert use["changes"] == sum(
        use[k] for k in ("used", "slips", "excluded", "too_few", "rejected")
    )
    assert "no epoch had the 5 clean changes" in use["warning"]
    assert use["warning"] in result.summary["warnings"]
    assert any("no carrier change was used" in w for w in warned)


def test_with_three_systems_the_same_log_uses_its_carrier_changes(tmp_path):
    result, warned = _walk_ubx(tmp_path, "walk_0827_multi_gnss.toml", {})
    use = result.summary["carrier_phase"]
    print(use)
    assert use["used"] > 0.5 * use["changes"]
    assert use["warning"] is None
    assert not any("no carrier change was used" in w for w in warned)


def test_a_bare_satellite_number_is_read_as_gps_with_a_deprecation_warning(tmp_path):
    data = shared_data("real-imu-gnss/walk_0827").parent.parent
    text = (ROOT / "examples" / "walk_0827.toml").read_text()
    path = tmp_path / "bare.toml"
    path.write_text(text.replace('["G10", "G23", "G27", "G32"]', '[10, "G23"]'))
    with pytest.warns(DeprecationWarning, match="the bare number 10 is read as 'G10'"):
        config = mn.load_config(path, data)
    assert config.values["gnss"]["satellites"] == ["G10", "G23"]
