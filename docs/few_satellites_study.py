"""The numbers of docs/explanation/few-satellites.md, rerunnable by anyone:
``python docs/few_satellites_study.py [--write]`` (about half a minute).

- Paired Monte Carlo: the paper's MEMS through a 60 s window keeping 0-3
  of its 6 satellites (12 runs of 300 s, seed 3).
- The covariance through a 60 s total outage: Monte Carlo position NEES
  per degree of freedom at its end and over the run, three grades (16 runs).
- The aided attitude: NEES per degree of freedom of tilt and heading for
  the manoeuvre correlation time of the input-shaped noise (10 runs of
  600 s, 6 satellites, exact start).
- 900 s on 1-3 satellites: a consumer IMU on the k highest of 6 satellites
  from the exact start (the first k kept), eight
  seeds; with 3, also with an oven-controlled receiver clock.

Prints the tables as Markdown; ``--write`` puts them into
docs/explanation/few-satellites.md between its ``study`` markers.
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np
from marked_block import replace_block
from scipy.stats import chi2

import memsnav as mn

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- study:begin -->", "<!-- study:end -->"
OCXO = (8e-20, 4e-23)


def _ned(position_ecef: np.ndarray) -> np.ndarray:
    lat, lon, _ = mn.ecef_to_geodetic(position_ecef)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def paired_table() -> str:
    rows = [
        "| satellites kept | mean of each run's largest error [m] | runs flagged |",
        "|---|---|---|",
    ]
    for kept in range(4):
        r = mn.experiments.navigation(
            outage=(150.0, 60.0, kept), runs=12, duration=300.0, seed=3, imus=("mems",)
        )
        s = r.summary()["mems"]
        key = "mean_max_position_error_during_outage_m"
        rows.append(
            f"| {kept} | {s[key]:.0f} ± {s['standard_error'][key]:.0f} | "
            f"{int(r.runs_summary['mems']['diverged'].sum())} of 12 |"
        )
    return "\n".join(rows)


def outage_nees_table() -> str:
    runs = 16
    low, high = chi2.ppf([0.0005, 0.9995], 3 * runs) / (3 * runs)
    rows = [
        "| IMU | error at the outage's end [m] | NEES/dof there | NEES/dof over the run: "
        f"lowest, highest (99.9 % band {low:.2f}-{high:.2f}) |",
        "|---|---|---|---|",
    ]
    for name, imu in (("paper MEMS", "mems"), ("consumer", "consumer"), ("tactical", "ins")):
        r = mn.experiments.navigation(
            outage=(150.0, 60.0), runs=runs, duration=300.0, seed=11, imus=(imu,)
        )
        s = r.summary()[imu]
        per_epoch = r.position_nees_mean[imu] / 3.0
        rows.append(
            f"| {name} | {s['position_error_at_outage_end_m']:.1f} | "
            f"{s['position_nees_per_dof_at_outage_end']:.2f} | "
            f"{per_epoch.min():.2f}, {per_epoch.max():.2f} |"
        )
    return "\n".join(rows)


def _attitude_nees(preset: str, tau: float, runs: int = 10) -> dict[str, float]:
    z2: dict[str, list[float]] = {"position": [], "tilt": [], "heading": []}
    for r in range(runs):
        rng = np.random.default_rng([7, r])
        truth = mn.Trajectory.random(duration=600.0, seed=int(rng.integers(1 << 31)))
        imu = mn.ImuModel.preset(preset, seed=int(rng.integers(1 << 31)))
        accel, gyro = imu.measure(
            truth.specific_force, truth.angular_rate, seed=int(rng.integers(1 << 31))
        )
        gnss = mn.simulate_gnss(
            truth.time,
            truth.position_ecef,
            truth.velocity_ecef,
            mn.Constellation.walker(),
            seed=int(rng.integers(1 << 31)),
        )
        start = {
            "position_ecef": truth.position_ecef[0],
            "velocity_ecef": truth.velocity_ecef[0],
            "attitude": truth.attitude[0],
        }
        sol = mn.TightlyCoupledFilter(imu, manoeuvre_correlation_time=tau).run(
            truth.time, accel, gyro, gnss, initial_state=start
        )
        every = slice(0, None, 100)
        e = (sol.position_ecef - truth.position_ecef)[every]
        p = sol.position_covariance_ecef[every]
        z2["position"].append(
            float(np.mean(np.einsum("ni,ni->n", e, np.linalg.solve(p, e[..., None])[..., 0]) / 3))
        )
        c = np.einsum("nij,nkj->nik", sol.attitude[every], truth.attitude[every])
        psi = np.stack([c[:, 2, 1] - c[:, 1, 2], c[:, 0, 2] - c[:, 2, 0], c[:, 1, 0] - c[:, 0, 1]])
        psi_ned = (0.5 * psi.T) @ _ned(truth.position_ecef[0]).T
        z = psi_ned / sol.attitude_std_ned[every]
        z2["tilt"].append(float(np.mean(z[:, :2] ** 2)))
        z2["heading"].append(float(np.mean(z[:, 2] ** 2)))
    return {k: float(np.mean(v)) for k, v in z2.items()}


def attitude_table() -> str:
    rows = [
        "| IMU | τ [s] | position | tilt | heading |",
        "|---|---|---|---|---|",
    ]
    for name, preset in (("paper MEMS", "paper-mems"), ("consumer", "consumer")):
        for tau in (10.0, 30.0):
            n = _attitude_nees(preset, tau)
            rows.append(
                f"| {name} | {tau:g} | {n['position']:.2f} | {n['tilt']:.2f} | {n['heading']:.2f} |"
            )
    n = _attitude_nees("tactical", 10.0)
    rows.append(f"| tactical | 10 | {n['position']:.2f} | {n['tilt']:.2f} | {n['heading']:.2f} |")
    return "\n".join(rows)


def _long_run(
    kept: int, seed: int, clock: tuple[float, float] | None = None, grade: str = "consumer"
):
    truth = mn.Trajectory.random(duration=900.0, seed=seed)
    imu = mn.ImuModel.preset(grade, seed=seed)
    accel, gyro = imu.measure(truth.specific_force, truth.angular_rate, seed=seed)
    clock_kw = {} if clock is None else {"clock_h0": clock[0], "clock_h_minus2": clock[1]}
    # The k highest of the 6 satellites from the first epoch on.
    gnss = mn.simulate_gnss(
        truth.time,
        truth.position_ecef,
        truth.velocity_ecef,
        mn.Constellation.walker(),
        seed=seed,
        outages=[(0.5, truth.time[-1], kept)],
        **clock_kw,
    )
    start = {
        "position_ecef": truth.position_ecef[0],
        "velocity_ecef": truth.velocity_ecef[0],
        "attitude": truth.attitude[0],
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the integrity alerts are counted below
        sol = mn.TightlyCoupledFilter(imu, **clock_kw).run(
            truth.time, accel, gyro, gnss, initial_state=start
        )
    ned = _ned(truth.position_ecef[0])
    error = (sol.position_ecef - truth.position_ecef) @ ned.T
    # The tilt error 20 s in (north and east of ψ: C_est C_trueᵀ ≈ I + [ψ×],
    # ECEF, into NED) and its σ, degrees.
    k20 = int(np.searchsorted(truth.time, truth.time[0] + 20.0))
    skew = sol.attitude[k20] @ truth.attitude[k20].T
    psi = ned @ np.array(
        [skew[2, 1] - skew[1, 2], skew[0, 2] - skew[2, 0], skew[1, 0] - skew[0, 1]]
    )
    tilt_deg = np.degrees(0.5 * psi[:2])
    tilt_std_deg = np.degrees(sol.attitude_std_ned[k20, :2])
    within = np.abs(error) <= 3.0 * sol.position_std_ned
    alerts = sol.integrity["alerts"]
    first = alerts[0]["time_s"] if alerts else math.nan
    # NIS per degree of freedom over 60 s windows: the mean z² of the
    # accepted scalar innovations (pseudoranges and rates) in each.
    records = sol.measurements
    since = np.asarray(records["time"]) - truth.time[0]
    z = np.asarray(records["innovation"]) / np.asarray(records["innovation_std"])
    used = (np.asarray(records["status"]) == "accepted") & np.isfinite(z)
    windows = [used & (since >= a) & (since < a + 60.0) for a in np.arange(0.0, since.max(), 60.0)]
    nis = [float(np.mean(z[w] ** 2)) for w in windows if w.any()]
    before = truth.time < first if alerts else np.ones(len(truth.time), dtype=bool)
    return {
        "inside": float(np.mean(within)),
        "inside_before_alert": float(np.mean(within[before])) if before.any() else math.nan,
        "final_m": float(np.linalg.norm(error[-1])),
        "final_sigma_m": float(np.linalg.norm(sol.position_std_ned[-1])),
        "final_vertical_sigma_m": float(sol.position_std_ned[-1, 2]),
        "flagged": bool(sol.diverged),
        "first_alert_s": first,
        "kinds": {a["kind"] for a in alerts},
        "nis_per_dof_60s": (min(nis), max(nis)),
        "tilt_at_20s_deg": tuple(float(v) for v in tilt_deg),
        "tilt_std_at_20s_deg": tuple(float(v) for v in tilt_std_deg),
    }


def long_run_table() -> str:
    rows = [
        "| satellites | receiver clock | share of N/E/D errors in 3σ: median (lowest) | "
        "the same before the first alert | final error: median [m] | final 3-D σ: median "
        "[m] | runs flagged | first alert: median [s] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    seeds = range(1, 9)
    for kept, clock, label in (
        (3, None, "TCXO"),
        (3, OCXO, "OCXO"),
        (2, None, "TCXO"),
        (1, None, "TCXO"),
    ):
        runs = [_long_run(kept, seed, clock) for seed in seeds]
        inside = [r["inside"] for r in runs]
        flagged = [r for r in runs if r["flagged"]]
        first = np.median([r["first_alert_s"] for r in flagged]) if flagged else math.nan
        kinds = sorted({k for r in flagged for k in r["kinds"]})
        before = [r["inside_before_alert"] for r in runs]
        rows.append(
            f"| {kept} | {label} | {np.median(inside):.2f} ({min(inside):.2f}) | "
            f"{np.median(before):.2f} ({min(before):.2f}) | "
            f"{np.median([r['final_m'] for r in runs]):.3g} | "
            f"{np.median([r['final_sigma_m'] for r in runs]):.3g} | "
            f"{len(flagged)} of {len(runs)}{' (' + ', '.join(kinds) + ')' if kinds else ''} | "
            f"{'–' if math.isnan(first) else f'{first:.0f}'} |"
        )
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--write", action="store_true", help="update docs/explanation/few-satellites.md"
    )
    args = parser.parse_args()
    text = (
        f"{BEGIN}\n\n**Paired outages** (paper MEMS, 60 s window from 150 s, 12 runs of "
        f"300 s, seed 3):\n\n{paired_table()}\n\n**The covariance through a 60 s total "
        f"outage** (16 runs of 300 s, seed 11, Monte Carlo position NEES per degree of "
        f"freedom):\n\n{outage_nees_table()}\n\n**The aided attitude** (10 runs of 600 s, "
        f"6 satellites, exact start; NEES per degree of freedom):\n\n{attitude_table()}\n\n"
        f"**900 s on 1-3 satellites** (consumer IMU, the k highest of 6 satellites from the "
        f"exact start, seeds 1-8):\n\n{long_run_table()}\n\n{END}"
    )
    print(text)
    if args.write:
        page = ROOT / "docs" / "explanation" / "few-satellites.md"
        replace_block(page, BEGIN, END, text)


if __name__ == "__main__":
    main()
