"""The ``memsnav`` command."""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

import memsnav

T = TypeVar("T", int, float)


def _checked(
    parse: Callable[[str], T], kind: str, ok: Callable[[T], bool], rule: str
) -> Callable[[str], T]:
    """An argparse type: ``parse`` the text (else "expected <kind>"), then
    require ``ok`` of the value (else "must be <rule>")."""

    def convert(text: str) -> T:
        try:
            value = parse(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}") from None
        if not ok(value):
            raise argparse.ArgumentTypeError(f"must be {rule}, got {text}")
        return value

    return convert


_positive_int = _checked(int, "a positive integer", lambda v: v > 0, "positive")
_non_negative_int = _checked(int, "an integer", lambda v: v >= 0, "zero or more")
_positive_float = _checked(float, "a number", lambda v: 0 < v < math.inf, "positive and finite")


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


def _print_study(summary: dict[str, Any]) -> None:
    """What ran and what it found, on stderr: each experiment's completed
    runs and state, then each claim's verdict."""
    for name, state in summary["experiments"].items():
        print(
            f"memsnav: {name}: {state['completed_runs']}/{state['planned_runs']} runs, "
            f"{state['state']}",
            file=sys.stderr,
        )
    for claim in summary["claims"]:
        print(f"memsnav: {claim['id']}: {claim['verdict']}", file=sys.stderr)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="memsnav",
        description=(
            "MEMS inertial sensors aided by GNSS: the study of de Boer et al. (ION GNSS 2008)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"memsnav {memsnav.__version__}")
    parser.add_argument(
        "--debug",
        action="store_true",
        help="show the full traceback of an error (default: one line)",
    )
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    reproduce = commands.add_parser(
        "reproduce",
        help="reproduce the paper's experiments (figures 3-18) and write the report",
        description=(
            "Run the calibration, inversion and navigation experiments (nominal, with a "
            "30 s outage, and with partial outages of 0-3 satellites) and write report.html, "
            "summary.json (every number, each experiment's completed runs, and each paper "
            "claim's verdict), the figures (PNG, SVG) and their curves (CSV) into DIR."
        ),
    )
    reproduce.add_argument(
        "--out", default="results", metavar="DIR", help="output directory (default: results)"
    )
    reproduce.add_argument(
        "--full",
        action="store_true",
        help="the paper's Monte Carlo sizes (1000 x 50 calibration, 300 inversion, "
        "200 navigation runs; 100 partial-outage runs) instead of the quick defaults",
    )
    reproduce.add_argument(
        "--runs",
        type=_positive_int,
        metavar="N",
        help="Monte Carlo runs of every experiment (calibration: runs per parameter set)",
    )
    reproduce.add_argument(
        "--seed", type=_non_negative_int, default=0, metavar="S", help="base seed (default: 0)"
    )
    reproduce.add_argument(
        "--threads", type=_positive_int, metavar="T", help="worker threads (default: all cores)"
    )
    reproduce.add_argument("--quiet", action="store_true", help="no progress bars")
    _scheduler_argument(reproduce)

    study = commands.add_parser(
        "study",
        help="which IMU grade is good enough through which GNSS outages (Monte Carlo sweep)",
        description=(
            "Run the outage study of a TOML configuration (IMU grades x outage lengths x "
            "satellites kept; see examples/study_land_vehicle.toml) and write report.html, "
            "summary.json and the figures into the output folder."
        ),
    )
    study.add_argument(
        "--config",
        required=True,
        help="study configuration (TOML), e.g. examples/study_land_vehicle.toml",
    )
    study.add_argument(
        "--output", default=None, help="output folder (default: the configuration's 'output')"
    )
    study.add_argument(
        "--threads", type=_positive_int, metavar="T", help="worker threads (default: all cores)"
    )
    study.add_argument("--quiet", action="store_true", help="no progress bar")
    _scheduler_argument(study)

    simulate = commands.add_parser(
        "simulate",
        help="write a random trajectory, its IMU outputs and GNSS measurements as CSV",
        description=(
            "Simulate a random land-vehicle trajectory, the outputs of an IMU preset along it "
            "and GNSS pseudoranges and rates, and write trajectory.csv, imu.csv, gnss.csv and "
            "simulation.json into DIR."
        ),
    )
    simulate.add_argument(
        "--out", default="simulation", metavar="DIR", help="output directory (default: simulation)"
    )
    simulate.add_argument(
        "--duration",
        type=_positive_float,
        default=600.0,
        metavar="S",
        help="seconds (default: 600)",
    )
    simulate.add_argument(
        "--rate", type=_positive_float, default=100.0, metavar="HZ", help="IMU rate (default: 100)"
    )
    simulate.add_argument(
        "--imu",
        default="paper-mems",
        choices=memsnav.ImuModel.presets(),
        help="IMU preset (default: paper-mems)",
    )
    simulate.add_argument(
        "--satellites", type=_positive_int, default=6, metavar="N", help="tracked (default: 6)"
    )
    simulate.add_argument(
        "--gnss-rate", type=_positive_float, default=1.0, metavar="HZ", help="(default: 1)"
    )
    simulate.add_argument(
        "--constellation",
        default="walker",
        metavar="NAV",
        help="'walker' (GPS-like, 24 satellites; default) or a RINEX navigation file",
    )
    simulate.add_argument(
        "--outage",
        action="append",
        type=_outage,
        default=[],
        metavar="START:LENGTH",
        help="a total GNSS outage, seconds (repeatable)",
    )
    simulate.add_argument(
        "--seed", type=_non_negative_int, default=0, metavar="S", help="base seed (default: 0)"
    )

    nav = commands.add_parser(
        "navigate",
        help="run real IMU/GNSS logs through a coupled filter (see docs/real-data.md)",
        description="Read the logs of a TOML run configuration, align, run the loosely or tightly "
        "coupled filter, write the solution (CSV, RTKLIB .pos), summary.json and report.html.",
    )
    _configured_run(nav, "run configuration (TOML), e.g. examples/drive_0708.toml")
    nav.add_argument(
        "--duration",
        type=_positive_float,
        default=None,
        help="stop this many seconds after alignment",
    )
    cal = commands.add_parser(
        "calibrate",
        help="calibrate an IMU from a recorded session (see docs/calibration.md)",
        description="Read a calibration session described by a TOML configuration (a "
        "multi-position static-pose session, or a drive calibrated against its GNSS), fit the "
        "accelerometer and gyroscope models and write calibration.json (the calibration file) "
        "and report.html.",
    )
    _configured_run(
        cal,
        "configuration (TOML), e.g. examples/xsens_static.toml or "
        "examples/drive_0708_calibration.toml",
    )
    return parser


def _scheduler_argument(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        default=None,
        help="run the Monte Carlo runs on the Dask cluster of this scheduler "
        "(e.g. tcp://10.0.0.5:8786; needs pip install 'memsnav[dask]'); the numbers "
        "do not change (docs/distributed.md)",
    )


def _configured_run(command: argparse.ArgumentParser, config_help: str) -> None:
    """The arguments of a command driven by a TOML configuration."""
    command.add_argument("--config", required=True, help=config_help)
    command.add_argument(
        "--data-root",
        default=None,
        help=(
            "folder relative data paths point into (default: "
            "$MEMSNAV_DATA_ROOT, else ../shared/data next to the repository)"
        ),
    )
    command.add_argument(
        "--output", default=None, help="output folder (default: the configuration's 'output')"
    )


def _calibrate(args: argparse.Namespace) -> int:
    from memsnav.calibration.command import run_calibration

    run = run_calibration(args.config, data_root=args.data_root, output=args.output)
    for kind, path in run.files.items():
        print(f"{kind}: {path}")
    s = run.summary
    if run.config["session"]["kind"] == "drive":
        for view in ("forward", "smoothed"):
            for label in ("raw", "calibrated"):
                st = s.get("navigation", {}).get(label, {}).get(view, {}).get("after_fit", {})
                if st.get("outages"):
                    print(
                        f"{view}, {label}: outages after the calibration span: horizontal RMS "
                        f"{st['rms_horizontal_m']:.2f} m, max {st['max_horizontal_m']:.2f} m"
                    )
            draws = s.get("navigation", {}).get("draws") or []
            rms = [d[view]["after_fit"].get("rms_horizontal_m") for d in draws]
            finite = [r for r in rms if r is not None]
            if finite:
                print(
                    f"{view}, {len(finite)} calibrations drawn from its covariance: RMS "
                    f"{min(finite):.2f}-{max(finite):.2f} m"
                )
    for subset in ("fit", "held_out"):
        if f"magnitude_rms_after_{subset}_m_s2" not in s:
            continue
        magnitude = s[f"magnitude_rms_after_{subset}_m_s2"]
        turn = s[f"turn_rms_after_{subset}_deg"]
        if magnitude is not None:
            print(
                f"{subset.replace('_', ' ')}: |f| - g RMS {1e3 * magnitude:.2f} mm/s^2 "
                f"(nominal {1e3 * s[f'magnitude_rms_before_{subset}_m_s2']:.0f}), gravity "
                f"direction after a turn RMS {turn:.3f} deg "
                f"(nominal {s[f'turn_rms_before_{subset}_deg']:.1f})"
            )
    for warning in run.calibration.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return 0


def main(argv: list[str] | None = None) -> int:
    """Runs a command; any error is one line ``memsnav: error: ...`` on
    stderr and exit status 1 (the traceback with ``--debug``), an interrupt
    exit status 130."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    format_warning = warnings.formatwarning
    if not args.debug:
        warnings.formatwarning = _one_line_warning
    client = None
    try:
        if getattr(args, "scheduler", None) is not None:
            from memsnav._distributed import connect

            client = connect(args.scheduler)
        return _run(args, client)
    except KeyboardInterrupt:
        print("memsnav: interrupted", file=sys.stderr)
        return 130
    except Exception as e:
        if args.debug:
            raise
        message = " ".join(str(e).split()) or type(e).__name__
        print(f"memsnav: error: {message}", file=sys.stderr)
        return 1
    finally:
        warnings.formatwarning = format_warning
        if client is not None:
            client.close()


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    line: str | None = None,
) -> str:
    """A warning as ``memsnav: warning: ...`` (no source line)."""
    return f"memsnav: warning: {message}\n"


def _run(args: argparse.Namespace, client: Any) -> int:
    if args.command == "calibrate":
        return _calibrate(args)
    if args.command == "navigate":
        return _navigate(args)
    if args.command == "study":
        from memsnav.study_command import run_study

        run = run_study(
            args.config,
            output=args.output,
            threads=args.threads,
            progress=not args.quiet,
            client=client,
        )
        for kind, written in run.files.items():
            print(f"{kind}: {written}")
        return 130 if run.interrupted else 0
    if args.command == "reproduce":
        from memsnav.reproduce import reproduce

        study = reproduce(
            out=args.out,
            full=args.full,
            runs=args.runs,
            seed=args.seed,
            threads=args.threads,
            progress=not args.quiet,
            client=client,
        )
        _print_study(study.summary)
        print(f"memsnav: report written to {study.report}", file=sys.stderr)
        return 130 if study.interrupted else 0
    if args.command == "simulate":
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
        )
        print(f"memsnav: wrote {files.trajectory.parent}", file=sys.stderr)
        return 0
    raise AssertionError(f"unknown command {args.command}")


def _navigate(args: argparse.Namespace) -> int:
    from memsnav.realdata.pipeline import navigate

    result = navigate(
        args.config, data_root=args.data_root, output=args.output, duration_s=args.duration
    )
    for kind, path in result.files.items():
        print(f"{kind}: {path}")
    stats = result.summary.get("errors_vs_truth", {}).get("aided")
    if stats and stats.get("epochs"):
        print(
            f"aided: RMS horizontal {stats['rms_horizontal_m']:.2f} "
            f"m, vertical {stats['rms_vertical_m']:.2f} m, "
            f"{100 * stats['within_3sigma_share']:.1f} % within 3 sigma"
        )
    return 0
