import subprocess
import sys

import memsnav as mn


def test_version_is_exposed():
    assert mn.__version__.count(".") == 2


def test_error_family():
    assert issubclass(mn.UnobservableError, mn.MemsnavError)
    assert issubclass(mn.DivergenceError, mn.MemsnavError)
    assert issubclass(mn.ParseError, ValueError)


def test_command_line_version():
    out = subprocess.run(
        [sys.executable, "-m", "memsnav", "--version"], capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == f"memsnav {mn.__version__}"
