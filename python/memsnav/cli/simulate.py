"""``memsnav simulate``: a trajectory, its IMU outputs and GNSS measurements
as CSV files (:func:`memsnav.simulate.simulate`)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

import memsnav
from memsnav.cli.arguments import (
    non_negative_float,
    non_negative_int,
    positive_float,
    positive_int,
    probability,
)

NAME = "simulate"
HELP = "write a random trajectory, its IMU outputs and GNSS measurements as CSV"
DESCRIPTION = (
    "Simulate a random land-vehicle trajectory, the outputs of an IMU preset along it "
    "and GNSS pseudoranges and rates, and write trajectory.csv (the truth, readable as "
    "[truth] pos), imu.csv, imu_truth.csv (the IMU without errors), gnss.csv and "
    "simulation.json into DIR."
)


def _outage(text: str) -> tuple[float, float]:
    start, sep, length = text.partition(":")
    try:
        if not sep:
            raise ValueError
        window = (float(start), float(length))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected START:LENGTH in seconds, got {text!r}"
        ) from None
    if window[0] < 0 or not window[1] > 0:
        raise argparse.ArgumentTypeError(f"start must be >= 0 and length > 0, got {text!r}")
    return window


def _systems(text: str) -> tuple[str, ...]:
    letters = tuple(part.strip().upper() for part in text.split(","))
    if not letters or any(letter not in ("G", "E", "C", "R") for letter in letters):
        raise argparse.ArgumentTypeError(f"expected letters among G, E, C, R, got {text!r}")
    return letters


def _biases(text: str) -> tuple[float, ...]:
    parts = text.split(",")
    try:
        if len(parts) not in (2, 3):
            raise ValueError
        return tuple(float(part) for part in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected GALILEO,BEIDOU[,GLONASS] in metres, got {text!r}"
        ) from None


def add_arguments(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--out", default="simulation", metavar="DIR", help="output directory (default: simulation)"
    )
    command.add_argument(
        "--duration",
        type=positive_float,
        default=600.0,
        metavar="S",
        help="seconds (default: 600)",
    )
    command.add_argument(
        "--rate", type=positive_float, default=100.0, metavar="HZ", help="IMU rate (default: 100)"
    )
    command.add_argument(
        "--imu",
        default="paper-mems",
        choices=memsnav.ImuModel.presets(),
        help="IMU preset (default: paper-mems)",
    )
    command.add_argument(
        "--satellites", type=positive_int, default=6, metavar="N", help="tracked (default: 6)"
    )
    command.add_argument(
        "--gnss-rate", type=positive_float, default=1.0, metavar="HZ", help="(default: 1)"
    )
    command.add_argument(
        "--constellation",
        default="walker",
        metavar="NAV",
        help="'walker' (the nominal constellations of --systems; default) or a RINEX "
        "navigation file (GPS)",
    )
    command.add_argument(
        "--systems",
        type=_systems,
        default=("G",),
        metavar="G,E,C,R",
        help="systems of the Walker constellation: G GPS, E Galileo, C BeiDou, R GLONASS "
        "(default: G)",
    )
    command.add_argument(
        "--inter-system-bias",
        type=_biases,
        default=(0.0, 0.0),
        metavar="E,C[,R]",
        help="Galileo, BeiDou and GLONASS pseudorange biases against GPS, m (default: 0,0,0; "
        "GLONASS 0 when left out)",
    )
    command.add_argument(
        "--carrier-phase-std",
        type=non_negative_float,
        default=0.0,
        metavar="M",
        help="carrier-range noise one-sigma, m (default: 0, no carrier phase)",
    )
    command.add_argument(
        "--cycle-slip-probability",
        type=probability,
        default=0.0,
        metavar="P",
        help="chance of a silent cycle slip per satellite and epoch (default: 0)",
    )
    command.add_argument(
        "--outage",
        action="append",
        type=_outage,
        default=[],
        metavar="START:LENGTH",
        help="a total GNSS outage, seconds (repeatable)",
    )
    command.add_argument(
        "--seed", type=non_negative_int, default=0, metavar="S", help="base seed (default: 0)"
    )


def run(args: argparse.Namespace, client: Any) -> int:
    from memsnav.simulate import simulate

    files = simulate(
        out=args.out,
        duration=args.duration,
        rate=args.rate,
        imu=args.imu,
        seed=args.seed,
        n_satellites=args.satellites,
        gnss_rate=args.gnss_rate,
        constellation=args.constellation,
        outages=args.outage,
        systems=args.systems,
        inter_system_bias=args.inter_system_bias,
        carrier_phase_std=args.carrier_phase_std,
        cycle_slip_probability=args.cycle_slip_probability,
    )
    print(f"memsnav: wrote {files.trajectory.parent}", file=sys.stderr)
    return 0
