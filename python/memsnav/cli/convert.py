"""``memsnav convert``: a raw u-blox UBX log to a RINEX 3.04 observation file
and a RINEX 4.00 (or 3.04) navigation file
(:func:`memsnav.realdata.convert.convert_ubx`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

NAME = "convert"
HELP = "convert a raw u-blox UBX log to RINEX (see docs/how-to/convert-ublox.md)"
DESCRIPTION = (
    "Read a u-blox UBX log (RXM-RAWX, RXM-SFRBX, NAV-PVT) and write its observations "
    "(every system and signal) as RINEX 3.04 <stem>.obs and its decoded GPS LNAV and "
    "CNAV, Galileo I/NAV, BeiDou D1 (MEO and IGSO satellites) and GLONASS (strings 1-5) "
    "ephemerides as RINEX 4.00 <stem>.nav (or RINEX 3.04, without the CNAV ones) in the "
    "output folder. BeiDou D2 (GEO satellites) is not decoded."
)


def add_arguments(command: argparse.ArgumentParser) -> None:
    command.add_argument("log", type=Path, help="the UBX log, e.g. gnss_1730.ubx")
    command.add_argument(
        "--output",
        type=Path,
        required=True,
        help="folder for <stem>.obs and <stem>.nav (made when missing)",
    )
    command.add_argument(
        "--rinex-version",
        default=None,
        metavar="VERSION",
        help="RINEX version of the navigation file: 4.00 (the default, GPS CNAV "
        "included) or 3.04 (no CNAV record: CNAV-only satellites are left out)",
    )


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.realdata.convert import convert_ubx

    log, files = convert_ubx(args.log, args.output, rinex_version=args.rinex_version)
    print(
        f"{len(log.rawx['epoch_gps_time'])} epochs, {len(log.observations.satellites)} "
        f"satellites, {len(log.ephemerides)} GPS LNAV, {len(log.galileo_ephemerides)} Galileo, "
        f"{len(log.beidou_ephemerides)} BeiDou and {len(log.glonass_ephemerides)} GLONASS "
        f"ephemerides, {len(log.fixes.gps_time)} NAV-PVT fixes"
    )
    cnav = len(log.gps_cnav_ephemerides)
    if files["navigation"].read_text()[:9].strip().startswith("3"):
        # RINEX 3.04 has no CNAV record (RINEX 4 has): say what stays out.
        print(f"{cnav} GPS CNAV ephemerides decoded, not written to the RINEX 3.04 .nav")
    else:
        print(f"{cnav} GPS CNAV ephemerides written to the RINEX 4.00 .nav")
    for reason, count in log.skipped.items():
        print(f"skipped: {count} {reason}")
    for kind, path in files.items():
        print(f"{kind}: {path}")
    return 0
