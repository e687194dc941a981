"""The shared data for the tests, found by the project's one data-root
resolver (``memsnav.realdata.config.resolve_data_root``: ``$MEMSNAV_DATA_ROOT``,
else ``shared/data`` beside the checkout, where the README puts it).

A test whose data is missing is skipped, naming the path; CI sets
``MEMSNAV_REQUIRE_DATA=1`` so that a missing file fails instead, and a
green run has run every real-data test."""

import os
from pathlib import Path

import pytest

from memsnav.realdata.config import resolve_data_root

REQUIRE_DATA_ENV = "MEMSNAV_REQUIRE_DATA"


def data_root() -> Path:
    return resolve_data_root(Path(__file__))


def missing_is_an_error() -> bool:
    """Whether CI asked for every real-data test to run."""
    return os.environ.get(REQUIRE_DATA_ENV, "") not in ("", "0")


def shared_data(relative: str) -> Path:
    """``<data root>/<relative>``, or a skip (a failure under
    ``MEMSNAV_REQUIRE_DATA=1``) naming what is missing."""
    path = data_root() / relative
    if not path.exists():
        message = (
            f"{path} not found: put the shared data beside the checkout "
            "(README) or set MEMSNAV_DATA_ROOT"
        )
        if missing_is_an_error():
            pytest.fail(message)
        pytest.skip(message)
    return path
