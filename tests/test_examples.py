"""Every shipped example (examples/*.toml) runs to the end through the
command its kind takes (``navigate``, ``calibrate`` or ``study``) and
warns about nothing but the data it reads: no warning, raised or written
into its result, asks the user to fix the example."""

import contextlib
import io
import json
import tomllib
import warnings
from pathlib import Path

import pytest
from shared_data import shared_data

from memsnav.cli import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _command(config: Path) -> str:
    """The command an example is for: a calibration session, a study or a
    log to navigate."""
    tables = tomllib.loads(config.read_text())
    if "session" in tables:
        return "calibrate"
    return "study" if "study" in tables else "navigate"


def test_every_example_is_covered():
    """A new example gets run here without a change to this file; the kinds
    are the three commands."""
    kinds = {_command(c) for c in EXAMPLES.glob("*.toml")}
    assert kinds == {"navigate", "calibrate", "study"}, kinds


def test_a_warning_about_the_example_fails_it(tmp_path):
    """The check itself: the static example with the nominal gyro scale of
    the datasheet instead of the fitted one warns that the example should
    pass the fitted scale, and that fails the test."""
    text = (EXAMPLES / "xsens_static.toml").read_text()
    text = text.replace("gyro_scale = [2.091310e-4", "gyro_scale = [1.6e-4")
    config = tmp_path / "xsens_static.toml"
    # Relative data paths resolve against the data root, not the file.
    config.write_text(text)
    with pytest.raises(AssertionError, match="pass the fitted scale"):
        test_the_example_runs_without_warning_about_itself(config, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("config", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_the_example_runs_without_warning_about_itself(config, tmp_path):
    command = _command(config)
    argv = [command, "--config", str(config), "--output", str(tmp_path / "out")]
    if command != "study":  # a study simulates its data
        data_root = shared_data("real-imu-gnss").parent
        argv += ["--data-root", str(data_root)]
    printed = io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(printed):
        warnings.simplefilter("always")
        code = main(argv)
    assert code == 0, printed.getvalue()[-2000:]
    written = {"navigate": "summary.json", "calibrate": "calibration.json"}.get(command)
    result = json.loads((tmp_path / "out" / written).read_text()) if written else {}
    messages = [str(w.message) for w in caught] + list(result.get("warnings", []))
    about_the_example = [m for m in messages if command == "study" or str(data_root) not in m]
    assert not about_the_example, about_the_example
