"""Shared fixtures."""

import importlib.util
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def drive_300s():
    """A 300 s simulated drive (docs/doc_runs.py simulated_drive_300s):
    (trajectory, gnss, imu, f, w)."""
    import doc_runs

    return doc_runs.simulated_drive_300s()


@pytest.fixture(scope="session")
def reference_script():
    """Loads a stored reference's writer, ``tests/data/<folder>/make_reference.py``
    (the tests compare against its arrays): ``reference_script(folder)``."""

    def load(folder: str):
        path = Path(__file__).parent / "data" / folder / "make_reference.py"
        spec = importlib.util.spec_from_file_location(f"make_{folder}", path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load
