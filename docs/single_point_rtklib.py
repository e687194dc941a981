"""memsnav's single-point fixes against RTKLIB 2.4.3's single mode on public
files: horizontal and vertical RMS about the known position and the share of
epochs with a fix, per file and weighting, written to
``docs/single_point_rtklib.json`` (docs/how-to/convert-ublox.md, "Single-point weights
and the residual test").

Run: ``python docs/single_point_rtklib.py [--slac PATH]`` with ``rnx2rtkp``
on the PATH (Debian's ``rtklib`` package, 2.4.3 b34). The Skydel GPS +
GLONASS excerpt is in ``tests/data/rinex-public``; SLAC's full two hours
(gnss_lib_py ``data/unit_test/sp3/slac1180.21o``, MIT) are read from
``--slac`` when given, with the shared data's ``brdc1180.21n``. RTKLIB's
options are in ``tests/data/rinex-public/rtklib_single*.conf``: single mode,
L1, 10° mask, broadcast ionosphere and Saastamoinen (none for the
simulation, which has no atmosphere), default error model.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from marked_block import replace_block

import memsnav as mn

HERE = Path(__file__).parent
PUBLIC = HERE.parent / "tests" / "data" / "rinex-public"
SKYDEL_TRUTH = np.array([-481819.31349724, 5507219.95375401, 3170373.73538364])


def _enu(errors_ecef: np.ndarray, reference_ecef: np.ndarray) -> np.ndarray:
    lat, lon, _ = mn.ecef_to_geodetic(reference_ecef)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    rotation = np.array([[-so, co, 0.0], [-sl * co, -sl * so, cl], [cl * co, cl * so, sl]])
    return errors_ecef @ rotation.T


def _scores(position_ecef: np.ndarray, truth_ecef: np.ndarray, epochs: int) -> dict[str, float]:
    ok = np.all(np.isfinite(position_ecef), axis=1)
    enu = _enu(position_ecef[ok] - truth_ecef, truth_ecef)
    return {
        "horizontal_rms_m": round(float(np.sqrt(np.mean(enu[:, 0] ** 2 + enu[:, 1] ** 2))), 3),
        "vertical_rms_m": round(float(np.sqrt(np.mean(enu[:, 2] ** 2))), 3),
        "availability": round(float(ok.sum() / epochs), 4),
    }


def _rtklib(conf: Path, systems: str, obs: Path, nav: Path) -> np.ndarray:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.pos"
        subprocess.run(
            ["rnx2rtkp", "-k", str(conf), "-sys", systems, "-o", str(out), str(obs), str(nav)],
            check=True,
            capture_output=True,
        )
        rows = [line.split() for line in out.read_text().splitlines() if not line.startswith("%")]
    return np.array([[float(r[2]), float(r[3]), float(r[4])] for r in rows])


def _case(
    obs_path: Path,
    nav_path: Path,
    systems: list[str],
    truth: np.ndarray | None,
    atmosphere: bool,
) -> dict[str, Any]:
    obs = mn.read_rinex_obs(obs_path)
    eph = mn.read_broadcast_nav(nav_path)
    reference = obs.approx_position_ecef if truth is None else truth
    result: dict[str, Any] = {"epochs": len(obs), "systems": systems}
    for weighting in ("rtklib", "signal-strength"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            gnss = obs.measurements(
                eph,
                reference,
                systems=systems,
                ionosphere=atmosphere,
                troposphere=atmosphere,
                weighting=weighting,
            )
        fixes = mn.solve_fix(gnss)
        result[f"memsnav_{weighting}"] = _scores(fixes.position_ecef, reference, len(obs))
        result[f"memsnav_{weighting}"]["epochs_with_exclusion"] = sum(
            1 for e in fixes.excluded if e
        )
    conf = PUBLIC / ("rtklib_single.conf" if atmosphere else "rtklib_single_noatm.conf")
    result["rtklib_single"] = _scores(
        _rtklib(conf, ",".join(systems), obs_path, nav_path), reference, len(obs)
    )
    return result


#: The page whose table shows the record, and its markers.
PAGE = HERE / "how-to" / "convert-ublox.md"
BEGIN, END = "<!-- single-point-rtklib:begin -->", "<!-- single-point-rtklib:end -->"
#: Each case's row label.
LABELS = {
    "skydel_gps_glonass": "Skydel simulator, GPS + GLONASS, 4 h",
    "slac_gps": "SLAC CORS, GPS, 2 h",
}


def render_table(record: dict[str, Any]) -> str:
    """The how-to's table of ``record`` (the JSON this script writes),
    between its markers, indented as the list item it sits in."""

    def cell(s: dict[str, Any]) -> str:
        return f"{s['horizontal_rms_m']:.3f} / {s['vertical_rms_m']:.3f}"

    rows = [
        "| file | memsnav H / V RMS [m] | signal-strength weights | RTKLIB single | availability |",
        "|---|---|---|---|---|",
    ]
    for name, case in record.items():
        solvers = ("memsnav_rtklib", "memsnav_signal-strength", "rtklib_single")
        everywhere = all(case[s]["availability"] == 1.0 for s in solvers)
        rows.append(
            f"| {LABELS[name]}, {case['epochs']} epochs | {cell(case['memsnav_rtklib'])} | "
            f"{cell(case['memsnav_signal-strength'])} | {cell(case['rtklib_single'])} | "
            + ("100 % all" if everywhere else "see the record")
            + " |"
        )
    return "\n".join([BEGIN, *(f"  {row}" for row in rows), f"  {END}"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--slac", type=Path, help="SLAC's slac1180.21o (two hours)")
    args = parser.parse_args()
    if shutil.which("rnx2rtkp") is None:
        sys.exit("rnx2rtkp not found: install RTKLIB (apt-get install rtklib)")
    table = {
        "skydel_gps_glonass": _case(
            PUBLIC / "skydel_20230080000_GR_C1C.rnx",
            PUBLIC / "skydel_20230080000_GR_nav.rnx",
            ["G", "R"],
            SKYDEL_TRUTH,
            atmosphere=False,
        )
    }
    if args.slac is not None:
        from memsnav.realdata.config import resolve_data_root

        nav = resolve_data_root(HERE) / "gnss-products/2021-118/brdc1180.21n"
        table["slac_gps"] = _case(args.slac, nav, ["G"], None, atmosphere=True)
    out = HERE / "single_point_rtklib.json"
    out.write_text(json.dumps(table, indent=2) + "\n")
    replace_block(PAGE, BEGIN, END, render_table(table))
    print(json.dumps(table, indent=2))


if __name__ == "__main__":
    main()
