"""A fresh run's figures against a record's, within tolerances: what the
tests of docs/data/*.json records share."""

from typing import Any


def agree(fresh, recorded, tolerance, path="") -> list[str]:
    """Where ``fresh`` and ``recorded`` (nested dicts and lists of numbers;
    strings and None compared exactly)
    differ by more than ``tolerance`` (a number, or dicts of them by key: a
    key a level does not name gets its ``"*"`` entry, or without one the
    whole tolerance passed down), by path."""
    if isinstance(recorded, dict):
        assert fresh.keys() == recorded.keys(), (path, fresh.keys(), recorded.keys())
        return [
            d
            for k in recorded
            for d in agree(
                fresh[k],
                recorded[k],
                _of_key(tolerance, k),
                f"{path}.{k}",
            )
        ]
    if isinstance(recorded, list):
        assert len(fresh) == len(recorded), path
        return [
            d
            for k, (f, r) in enumerate(zip(fresh, recorded, strict=True))
            for d in agree(f, r, tolerance, f"{path}.{k}")
        ]
    if recorded is None or isinstance(recorded, str):  # a name, or nothing learnt
        return [] if fresh == recorded else [f"{path}: {fresh!r} vs {recorded!r}"]
    return [] if abs(fresh - recorded) <= tolerance + 1e-12 else [f"{path}: {fresh} vs {recorded}"]


def _of_key(tolerance: Any, key: str) -> Any:
    if not isinstance(tolerance, dict):
        return tolerance
    return tolerance.get(key, tolerance.get("*", tolerance))
