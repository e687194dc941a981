"""The satellites of a tight-coupling run, one row each, and their totals
per system: what the report and ``summary.json`` show of them.

Every count comes from the filter's measurement records (one per scalar
measurement: its satellite, kind, epoch and status); C/N0, elevation and
signal from the measurements the run was given (``GnssMeasurements.cn0_db_hz``,
``elevation_rad``, ``signal``: the S observation of the signal each
pseudorange was taken from, and the elevation at the reference position),
averaged over the epochs whose measurements of the satellite reached the
filter. A status is counted as used ("accepted"), excluded (left out of
its batch by fault exclusion), a cycle slip ("slip", carrier phase) or
rejected (any other: its batch failed the gate, an invalid value, a batch
the filter was reset from), so a status the filter adds later lands in a
column without a change here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import memsnav._memsnav as _mn

#: The measurement kinds made per satellite.
SATELLITE_KINDS = ("pseudorange", "pseudorange_rate", "carrier_phase")

#: Systems by RINEX letter, in the order the tables list them.
SYSTEM_NAMES = {"G": "GPS", "E": "Galileo", "C": "BeiDou"}

#: The columns of the counts, by the statuses they hold (None: the rest).
COLUMNS: dict[str, tuple[str, ...] | None] = {
    "used": ("accepted",),
    "excluded": ("excluded",),
    "slips": ("slip",),
    "rejected": None,
}


def _column(status: str) -> str:
    return next(
        (name for name, held in COLUMNS.items() if held is not None and status in held),
        "rejected",
    )


def satellite_rows(records: dict[str, Any], gnss: Any) -> list[dict[str, Any]]:
    """One row per satellite with a record, in satellite-number order (GPS,
    Galileo, BeiDou): ``satellite`` (RINEX name), ``system``, ``signal``,
    ``epochs`` (with a measurement of it in the filter), ``mean_cn0_db_hz``,
    ``mean_elevation_deg`` (NaN when ``gnss`` was not built from
    observations, ``signal`` then None), the counts of the ``COLUMNS`` and
    ``measurements`` (per kind and status)."""
    kinds = np.asarray(records["kind"])
    keep = np.isin(kinds, SATELLITE_KINDS)
    kinds = kinds[keep]
    ids = np.asarray(records["id"])[keep].astype(np.int64)
    statuses = np.asarray(records["status"])[keep]
    epoch = _epoch_index(np.asarray(records["time"])[keep], np.asarray(gnss.time))
    slot = _slot(np.asarray(gnss.sat_id), epoch, ids)
    cn0, elevation, signals = gnss.cn0_db_hz, gnss.elevation_rad, gnss.signal
    rows = []
    for number in np.unique(ids):
        mine = ids == number
        # Each epoch once, whatever the kinds measured at it.
        epochs, first = np.unique(epoch[mine], return_index=True)
        slots = slot[mine][first]
        name = _mn.satellite_name(int(number))
        row: dict[str, Any] = {
            "satellite": name,
            "system": SYSTEM_NAMES.get(name[0], name[0]),
            "signal": None,
            "epochs": len(epochs),
            "mean_cn0_db_hz": float("nan"),
            "mean_elevation_deg": float("nan"),
        }
        if cn0 is not None and elevation is not None and signals is not None:
            row["mean_cn0_db_hz"] = float(np.mean(np.asarray(cn0)[epochs, slots]))
            row["mean_elevation_deg"] = float(
                np.degrees(np.mean(np.asarray(elevation)[epochs, slots]))
            )
            names = {signals[k][j] for k, j in zip(epochs.tolist(), slots.tolist(), strict=True)}
            row["signal"] = ", ".join(sorted(names))
        row.update(dict.fromkeys(COLUMNS, 0))
        measurements: dict[str, dict[str, int]] = {}
        for kind, status in zip(kinds[mine].tolist(), statuses[mine].tolist(), strict=True):
            per_kind = measurements.setdefault(str(kind), {})
            per_kind[str(status)] = per_kind.get(str(status), 0) + 1
            row[_column(str(status))] += 1
        row["measurements"] = measurements
        rows.append(row)
    return rows


def system_totals(rows: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per system, in the order of ``rows`` (of :func:`satellite_rows`: GPS,
    Galileo, BeiDou): ``satellites`` (with a measurement used),
    ``measurements`` (every record), the counts of the ``COLUMNS`` and the
    shares of the measurements excluded and rejected."""
    totals: dict[str, dict[str, Any]] = {}
    for row in rows:
        t = totals.setdefault(
            row["system"], {"satellites": 0, "measurements": 0, **dict.fromkeys(COLUMNS, 0)}
        )
        t["satellites"] += row["used"] > 0
        for column in COLUMNS:
            t[column] += row[column]
            t["measurements"] += row[column]
    for t in totals.values():
        t["excluded_share"] = t["excluded"] / t["measurements"]
        t["rejected_share"] = t["rejected"] / t["measurements"]
    return totals


def _epoch_index(record_time: np.ndarray, epoch_time: np.ndarray) -> np.ndarray:
    """The measurement epoch of each record (the filter records an epoch's
    measurements at the epoch's own time)."""
    k = np.searchsorted(epoch_time, record_time).clip(0, max(len(epoch_time) - 1, 0))
    if len(record_time) and not np.array_equal(epoch_time[k], record_time):
        raise ValueError("measurement records: a record's time is not a measurement epoch's")
    return k


def _slot(sat_id: np.ndarray, epoch: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """The column of each record's satellite in its epoch's padded arrays."""
    match = sat_id[epoch] == ids[:, None]
    if not np.all(match.any(axis=1)):
        raise ValueError("measurement records: a record's satellite is not in its epoch")
    index: np.ndarray = match.argmax(axis=1)
    return index
