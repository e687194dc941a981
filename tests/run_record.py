"""Runs one of docs/doc_runs.py's records again and compares it with the
record the pages show, docs/data/<name>.json."""

import doc_runs
from figures import figures
from record_agreement import agree
from shared_data import data_root as data_root_of_tests
from shared_data import shared_data


def check_run(name: str, tolerance, needs_data: bool = False) -> dict:
    """Runs ``name`` and compares it with its record within ``tolerance``
    (a number, or a dict of figure paths with ``"*"`` for the rest); the
    fresh figures, for the caller's own checks against theory."""
    data_root = shared_data("real-imu-gnss").parent if needs_data else data_root_of_tests()
    fresh = doc_runs.RUNS[name](data_root)
    differ = agree(fresh, figures(name), tolerance, name)
    assert not differ, f"{differ}: rerun python docs/doc_runs.py {name} if this is meant"
    return fresh
