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

Prints the tables as Markdown; ``--write`` keeps their figures (and those
the page's sentences draw from them) in docs/data/few_satellites.json and
puts the tables into docs/explanation/few-satellites.md between its
``study`` markers, its sentences' figures through placeholders;
``--from-record`` re-renders them without a run.
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from marked_block import record_block_script
from scipy.stats import chi2

import memsnav as mn

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- study:begin -->", "<!-- study:end -->"
OCXO = (8e-20, 4e-23)


def _ned(position_ecef: np.ndarray) -> np.ndarray:
    lat, lon, _ = mn.ecef_to_geodetic(position_ecef)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def paired_figures() -> list[dict[str, float]]:
    """By satellites kept (0-3): the mean of each run's largest error in
    the window and its standard error, m; the runs flagged."""
    figures = []
    for kept in range(4):
        r = mn.experiments.navigation(
            outage=(150.0, 60.0, kept), runs=12, duration=300.0, seed=3, imus=("mems",)
        )
        s = r.summary()["mems"]
        key = "mean_max_position_error_during_outage_m"
        figures.append(
            {
                "largest_m": s[key],
                "standard_error_m": s["standard_error"][key],
                "flagged": int(r.runs_summary["mems"]["diverged"].sum()),
            }
        )
    return figures


def paired_table(figures: list[dict[str, float]]) -> str:
    rows = [
        "| satellites kept | mean of each run's largest error [m] | runs flagged |",
        "|---|---|---|",
    ]
    for kept, f in enumerate(figures):
        rows.append(
            f"| {kept} | {f['largest_m']:.0f} ± {f['standard_error_m']:.0f} | "
            f"{f['flagged']} of 12 |"
        )
    return "\n".join(rows)


#: The outage NEES runs.
NEES_RUNS = 16


def outage_nees_figures() -> dict[str, dict[str, float]]:
    """By IMU: the error at the outage's end (m), the NEES/dof there, the
    lowest and highest NEES/dof over the run."""
    figures = {}
    for name, imu in (("paper MEMS", "mems"), ("consumer", "consumer"), ("tactical", "ins")):
        r = mn.experiments.navigation(
            outage=(150.0, 60.0), runs=NEES_RUNS, duration=300.0, seed=11, imus=(imu,)
        )
        s = r.summary()[imu]
        per_epoch = r.position_nees_mean[imu] / 3.0
        figures[name] = {
            "error_at_end_m": s["position_error_at_outage_end_m"],
            "nees_per_dof_at_end": s["position_nees_per_dof_at_outage_end"],
            "nees_per_dof_least": float(per_epoch.min()),
            "nees_per_dof_most": float(per_epoch.max()),
        }
    return figures


def outage_nees_table(figures: dict[str, dict[str, float]]) -> str:
    low, high = chi2.ppf([0.0005, 0.9995], 3 * NEES_RUNS) / (3 * NEES_RUNS)
    rows = [
        "| IMU | error at the outage's end [m] | NEES/dof there | NEES/dof over the run: "
        f"lowest, highest (99.9 % band {low:.2f}-{high:.2f}) |",
        "|---|---|---|---|",
    ]
    for name, f in figures.items():
        rows.append(
            f"| {name} | {f['error_at_end_m']:.1f} | {f['nees_per_dof_at_end']:.2f} | "
            f"{f['nees_per_dof_least']:.2f}, {f['nees_per_dof_most']:.2f} |"
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


def attitude_figures() -> dict[str, dict[str, dict[str, float]]]:
    """By IMU and τ (s): the NEES/dof of position, tilt and heading."""
    figures: dict[str, dict[str, dict[str, float]]] = {}
    for name, preset in (("paper MEMS", "paper-mems"), ("consumer", "consumer")):
        for tau in (10.0, 30.0):
            figures.setdefault(name, {})[f"{tau:g}"] = _attitude_nees(preset, tau)
    figures["tactical"] = {"10": _attitude_nees("tactical", 10.0)}
    return figures


def attitude_table(figures: dict[str, dict[str, dict[str, float]]]) -> str:
    rows = [
        "| IMU | τ [s] | position | tilt | heading |",
        "|---|---|---|---|---|",
    ]
    for name, by_tau in figures.items():
        for tau, n in by_tau.items():
            rows.append(
                f"| {name} | {tau} | {n['position']:.2f} | {n['tilt']:.2f} | {n['heading']:.2f} |"
            )
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
    alerts = sol.integrity.alerts
    first = alerts[0].time_s if alerts else math.nan
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
        "kinds": {a.kind for a in alerts},
        "nis_per_dof_60s": (min(nis), max(nis)),
        "tilt_at_20s_deg": tuple(float(v) for v in tilt_deg),
        "tilt_std_at_20s_deg": tuple(float(v) for v in tilt_std_deg),
    }


#: The 900 s runs' cases: satellites kept, receiver clock, its label.
LONG_RUN_CASES = ((3, None, "TCXO"), (3, OCXO, "OCXO"), (2, None, "TCXO"), (1, None, "TCXO"))


def long_run_figures() -> list[dict[str, Any]]:
    """Per case of LONG_RUN_CASES over seeds 1-8: the share of N/E/D
    errors in 3σ (median, lowest), the same before the first alert, the
    final error and 3-D σ (medians, m), the runs flagged and why, the
    median first alert (s; NaN when none)."""
    figures = []
    for kept, clock, label in LONG_RUN_CASES:
        runs = [_long_run(kept, seed, clock) for seed in range(1, 9)]
        inside = [r["inside"] for r in runs]
        flagged = [r for r in runs if r["flagged"]]
        before = [r["inside_before_alert"] for r in runs]
        figures.append(
            {
                "satellites": kept,
                "clock": label,
                "inside": {"median": float(np.median(inside)), "least": min(inside)},
                "inside_before_alert": {"median": float(np.median(before)), "least": min(before)},
                "final_m": float(np.median([r["final_m"] for r in runs])),
                "final_sigma_m": float(np.median([r["final_sigma_m"] for r in runs])),
                "flagged": len(flagged),
                "runs": len(runs),
                "kinds": sorted({k for r in flagged for k in r["kinds"]}),
                "first_alert_s": float(np.median([r["first_alert_s"] for r in flagged]))
                if flagged
                else None,
            }
        )
    return figures


def long_run_table(figures: list[dict[str, Any]]) -> str:
    rows = [
        "| satellites | receiver clock | share of N/E/D errors in 3σ: median (lowest) | "
        "the same before the first alert | final error: median [m] | final 3-D σ: median "
        "[m] | runs flagged | first alert: median [s] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for f in figures:
        kinds = f["kinds"]
        first = f["first_alert_s"]
        rows.append(
            f"| {f['satellites']} | {f['clock']} | {f['inside']['median']:.2f} "
            f"({f['inside']['least']:.2f}) | {f['inside_before_alert']['median']:.2f} "
            f"({f['inside_before_alert']['least']:.2f}) | {f['final_m']:.3g} | "
            f"{f['final_sigma_m']:.3g} | "
            f"{f['flagged']} of {f['runs']}{' (' + ', '.join(kinds) + ')' if kinds else ''} | "
            f"{'–' if first is None else f'{first:.0f}'} |"
        )
    return "\n".join(rows)


def derived(figures: dict[str, Any]) -> dict[str, Any]:
    """What the page's sentences draw from the tables."""
    kept = [f["largest_m"] for f in figures["paired"]]
    at_end = [f["nees_per_dof_at_end"] for f in figures["outage_nees"].values()]
    raw_tilt = [figures["attitude"][imu]["10"]["tilt"] for imu in ("paper MEMS", "consumer")]
    aided_position = [
        row["position"] for rows in figures["attitude"].values() for row in rows.values()
    ]
    cases = {(f["satellites"], f["clock"]): f for f in figures["long_runs"]}
    return {
        "three_satellites_kept_percent": 100.0 * kept[3] / kept[0],
        "nees_at_end": {"least": min(at_end), "most": max(at_end)},
        "raw_tilt_nees": {"least": min(raw_tilt), "most": max(raw_tilt)},
        "aided_position_nees": {"least": min(aided_position), "most": max(aided_position)},
        "three_tcxo_final_km": cases[3, "TCXO"]["final_m"] / 1e3,
        "three_tcxo_sigma_km": cases[3, "TCXO"]["final_sigma_m"] / 1e3,
        "three_ocxo_final_m": cases[3, "OCXO"]["final_m"],
        "three_ocxo_sigma_m": cases[3, "OCXO"]["final_sigma_m"],
        "first_alert_s": {
            "two": cases[2, "TCXO"]["first_alert_s"],
            "one": cases[1, "TCXO"]["first_alert_s"],
        },
    }


def render(record: dict[str, Any]) -> str:
    """The block the page shows, from the record."""
    f = record["figures"]
    return (
        f"{BEGIN}\n\n**Paired outages** (paper MEMS, 60 s window from 150 s, 12 runs of "
        f"300 s, seed 3):\n\n{paired_table(f['paired'])}\n\n**The covariance through a 60 s "
        f"total outage** ({NEES_RUNS} runs of 300 s, seed 11, Monte Carlo position NEES per "
        f"degree of freedom):\n\n{outage_nees_table(f['outage_nees'])}\n\n**The aided "
        f"attitude** (10 runs of 600 s, 6 satellites, exact start; NEES per degree of "
        f"freedom):\n\n{attitude_table(f['attitude'])}\n\n**900 s on 1-3 satellites** "
        f"(consumer IMU, the k highest of 6 satellites from the exact start, seeds "
        f"1-8):\n\n{long_run_table(f['long_runs'])}\n\n{END}"
    )


def measure(_: argparse.Namespace) -> dict[str, Any]:
    """Every table's figures and the figures the sentences draw from them."""
    figures = {
        "paired": paired_figures(),
        "outage_nees": outage_nees_figures(),
        "attitude": attitude_figures(),
        "long_runs": long_run_figures(),
    }
    figures["derived"] = derived(figures)
    return figures


def main() -> None:
    page = ROOT / "docs" / "explanation" / "few-satellites.md"
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    record_block_script(parser, "few_satellites", page, (BEGIN, END), measure, render)


if __name__ == "__main__":
    main()
