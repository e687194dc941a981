"""``memsnav convert``: a raw u-blox UBX log to RINEX 3.04 observation and
navigation files (:func:`memsnav.realdata.convert.convert_ubx`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

NAME = "convert"
HELP = "convert a raw u-blox UBX log to RINEX 3.04 (see docs/how-to/convert-ublox.md)"
DESCRIPTION = (
    "Read a u-blox UBX log (RXM-RAWX, RXM-SFRBX, NAV-PVT) and write its observations "
    "(every system and signal) and its decoded GPS LNAV, Galileo I/NAV and BeiDou D1 "
    "(MEO and IGSO satellites) ephemerides as RINEX 3.04 files <stem>.obs and <stem>.nav "
    "in the output folder. GPS CNAV ephemerides are decoded but not written (RINEX 3.04 "
    "has no CNAV record); BeiDou D2 (GEO satellites) is not decoded."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    command.add_argument("log", type=Path, help="the UBX log, e.g. gnss_1730.ubx")
    command.add_argument(
        "--output",
        type=Path,
        required=True,
        help="folder for <stem>.obs and <stem>.nav (made when missing)",
    )


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.realdata.convert import convert_ubx

    log, files = convert_ubx(args.log, args.output)
    print(
        f"{len(log.rawx['epoch_gps_time'])} epochs, {len(log.observations.satellites)} "
        f"satellites, {len(log.ephemerides)} GPS LNAV, {len(log.galileo_ephemerides)} Galileo and "
        f"{len(log.beidou_ephemerides)} BeiDou ephemerides, {len(log.fixes.gps_time)} NAV-PVT fixes"
    )
    # RINEX 3.04 has no CNAV record (RINEX 4 has): say what stays out.
    print(f"{len(log.gps_cnav_ephemerides)} GPS CNAV ephemerides decoded, not written to the .nav")
    for reason, count in log.skipped.items():
        print(f"skipped: {count} {reason}")
    for kind, path in files.items():
        print(f"{kind}: {path}")
    return 0
