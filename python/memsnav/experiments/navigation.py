"""Navigation Monte Carlo: paper §5.3, figures 14-18 (method §5-6).

Each run draws a random 100 Hz land-vehicle trajectory (Toulouse, speeds
up to 30 m/s), simulates 1 Hz GNSS pseudoranges and rates on it (a 24-slot
Walker constellation: no ephemeris file needed, valid at any date; 6
satellites kept all along, 3 m and 0.1 m/s white noise, a TCXO receiver
clock) and runs the tightly coupled 17-state filter with every IMU of the
set on the *same* trajectory, GNSS draws and initial attitude error (a
paired comparison). The IMUs of the paper:

- ``"ins"``: a tactical-grade IMU (preset ``"tactical"``, drawn per run),
- ``"mems"``: the paper's MEMS (preset ``"paper-mems"``), raw outputs,
- ``"calibrated_mems"``: the *same* MEMS outputs passed through the
  inversion filters (method §4) with the parameters of a calibration
  (method §3, errors-in-variables) done at t = 0 on its own segment of
  ``calibration_duration`` s of land-vehicle motion with GNSS-like
  references (3 mg and 0.1 °/s per sample).

Filter tuning comes from each IMU's specification
(``FilterTuning::from_imu_spec``): noise densities and bias processes;
deterministic errors the 17 states lack (raw MEMS scale factor,
misalignment, nonlinearity, g-sensitivity) are absorbed as inflated bias
uncertainty and white noise. The calibrated MEMS is tuned from the
calibration's own parameter uncertainties. Initial position, velocity and
clock come from the least-squares fix of the first epoch; the initial
attitude is the truth rotated by a draw of 1° tilt and 5° heading (the
filter's P₀).

Every run is reproducible from ``(seed, run index)`` whatever the thread
count; each IMU draws from its own stream, so dropping an IMU from the set
does not change the others' numbers.

What our numbers show against the paper (20 runs x 600 s, seed 0; the full
study, error budget and the options behind it are in
``docs/paper-comparison.md``):

- Calibrated MEMS close to INS with GNSS (RMS 1.08 / 1.18 m after 150 s
  for INS / calibrated MEMS) and MEMS drifting far more than INS in a 30 s
  total outage at 300 s (34 m vs 3.6 m): both as in the paper.
- Calibration does *not* help visibly in the first 150 s (1.42 vs 1.43 m):
  every filter converges within ~30 s and, while aided, MEMS errors are set
  by the white noise, which calibration does not change. Pseudoranges only
  (``pseudorange_rate=False``) or larger initial attitude errors do not
  change that; only a raw-MEMS filter that ignores its misalignments
  (``absorb_unmodelled=False``) shows the paper's early gap (2.10 vs
  1.41 m), and it then diverges.
- Calibration helps *a lot* in the outage (34 -> 6.8 m; paper: "light"):
  the paper-mems 1e-2 gyro misalignment turns yaw rate into tilt (18 m
  after 30 s analytically; 32 -> 6.3 m in simulation without it), the
  accelerometer misalignment adds 6 m, white noise only ~1 m. Calibration
  removes the misalignments. The paper's "drift due to noise" needs a
  MEMS much noisier than our preset, whose density (fitted to the
  inversion MSE) is tactical-grade.
- Mean NEES per degree of freedom is 0.6-0.7 for every IMU: the tuning is
  conservative (the absorbed unmodelled terms, and the spec's one-sigma
  magnitudes as bias uncertainties for IMUs whose draws are smaller). On
  errors the filter models exactly it is consistent (NEES/dof 0.95, Rust
  test ``consistent_when_the_imu_errors_are_modelled_exactly``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from memsnav import _memsnav

PAPER_IMUS = ("ins", "mems", "calibrated_mems")
"""The paper's three IMUs (figures 14-18)."""

KEEP_RUNS_UP_TO = 50
"""Per-run curves are kept automatically for sets of at most this many runs."""

_NAMED = {"ins": "tactical", "mems": "paper-mems"}


def _imu_sources(imus: Sequence[str] | Mapping[str, Any]) -> list[tuple[str, Any]]:
    """(name, source) pairs for the Rust call: a preset name,
    ``(preset name, spec dict)``, ``"calibrated:<raw>"`` or an ``ImuModel``."""
    if isinstance(imus, Mapping):
        items = list(imus.items())
    elif isinstance(imus, str):
        raise ValueError("imus: expected a sequence of names or a dict, not a single string")
    else:
        items = [(name, name) for name in imus]
    out: list[tuple[str, Any]] = []
    for name, source in items:
        if not isinstance(name, str):
            raise ValueError(f"imus: names must be strings, got {name!r}")
        if isinstance(source, tuple) and len(source) == 2 and source[0] == "calibrated":
            out.append((name, f"calibrated:{source[1]}"))
        elif isinstance(source, tuple) and len(source) == 2 and isinstance(source[1], Mapping):
            preset = _NAMED.get(source[0], source[0])
            out.append((name, (preset, dict(source[1]))))
        elif source == "calibrated_mems":
            out.append((name, "calibrated:mems"))
        elif isinstance(source, str):
            out.append((name, _NAMED.get(source, source)))
        else:
            out.append((name, source))
    return out


@dataclass(frozen=True)
class NavigationResult:
    """Result of :func:`navigation`; errors in metres, times in seconds.

    - ``time`` (T,): output epochs, s from the start (1 Hz, the GNSS epochs;
      the same grid inside an outage).
    - ``mean`` / ``std`` / ``percentiles``: per IMU name, the mean, sample
      standard deviation and 5/25/50/75/95 % percentiles ((5, T), P²
      estimates) over runs of the position error norm |r_hat - r| per epoch.
    - ``nees_mean``: per IMU, the mean over runs of the NEES per epoch
      (position, velocity, attitude: 9 degrees of freedom; 9 when the
      filter is consistent).
    - ``position_error`` / ``nees``: per IMU, ``(runs, T)`` arrays of every
      run, kept when ``keep_runs=True`` or ``runs <= 50``; otherwise
      ``None`` (the set is then folded run by run in bounded memory).
    - ``runs_summary``: per IMU, per-run scalars ``rms`` (m), ``rms_early``
      (m, first ``early_window`` s), ``final`` (m), ``max_in_outage`` (m,
      NaN without outage), ``mean_nees_per_dof``, ``rejected`` (count),
      ``accepted`` (count of scalar measurements applied).
    - ``completed_runs``; ``interrupted``: True when Ctrl-C (or a failing
      progress callback) stopped the set early — the statistics then cover
      the completed runs only.
    """

    time: npt.NDArray[np.float64]
    mean: dict[str, npt.NDArray[np.float64]]
    std: dict[str, npt.NDArray[np.float64]]
    percentiles: dict[str, npt.NDArray[np.float64]]
    nees_mean: dict[str, npt.NDArray[np.float64]]
    position_error: dict[str, npt.NDArray[np.float64]] | None
    nees: dict[str, npt.NDArray[np.float64]] | None
    runs_summary: dict[str, dict[str, npt.NDArray[Any]]]
    completed_runs: int
    interrupted: bool
    config: dict[str, Any] = field(default_factory=dict)

    @property
    def imus(self) -> list[str]:
        """IMU names, in the set's order."""
        return list(self.mean)

    def summary(self) -> dict[str, dict[str, float]]:
        """Per IMU name:

        - ``rms_position_error_m``: √(mean over runs and epochs of |δr|²);
        - ``rms_position_error_first_150s_m`` (named after ``early_window``):
          the same over the first ``early_window`` s;
        - ``final_position_error_m``: mean over runs of |δr| at the last epoch;
        - ``mean_nees_per_dof``: mean over runs and epochs of NEES / 9
          (≈ 1 for a consistent filter);
        - ``rejected_measurements_per_run``: mean count of gated/invalid
          measurements;
        - with an outage: ``max_position_error_during_outage_m`` (maximum over
          the outage of the mean-over-runs error curve, what figs 16-18 show),
          ``mean_max_position_error_during_outage_m`` (mean over runs of each
          run's maximum) and ``position_error_at_outage_end_m`` (mean curve at
          the last epoch of the outage, before GNSS returns). The outage
          covers the epochs in [start, start + length).
        """
        early = round(self.config.get("early_window", 150.0))
        out: dict[str, dict[str, float]] = {}
        outage = self.config.get("outage")
        for name, runs in self.runs_summary.items():
            s = {
                "rms_position_error_m": float(np.sqrt(np.mean(runs["rms"] ** 2))),
                f"rms_position_error_first_{early}s_m": float(
                    np.sqrt(np.mean(runs["rms_early"] ** 2))
                ),
                "final_position_error_m": float(np.mean(runs["final"])),
                "mean_nees_per_dof": float(np.mean(runs["mean_nees_per_dof"])),
                "rejected_measurements_per_run": float(np.mean(runs["rejected"])),
            }
            if outage is not None:
                start, length = outage
                inside = (self.time >= start) & (self.time < start + length)
                s["max_position_error_during_outage_m"] = float(np.max(self.mean[name][inside]))
                s["mean_max_position_error_during_outage_m"] = float(np.mean(runs["max_in_outage"]))
                s["position_error_at_outage_end_m"] = float(self.mean[name][inside][-1])
            out[name] = s
        return out

    def plot(self) -> dict[str, Any]:
        """The paper's figures as matplotlib figures: mean ± std over runs of
        the position error norm vs time, one curve per IMU.

        Without outage: ``"fig14"`` (whole run) and ``"fig15"`` (zoom on the
        first ``early_window`` s). With an outage: ``"fig16"`` (whole run),
        ``"fig17"`` (the outage's first 15 s) and ``"fig18"`` (its first 5 s),
        each zoom starting 2 s before the outage.
        """
        import matplotlib.pyplot as plt

        outage = self.config.get("outage")
        n = self.completed_runs

        def figure(title: str, window: tuple[float, float] | None) -> Any:
            fig, ax = plt.subplots(figsize=(7.0, 4.2))
            t = self.time
            sel = np.ones_like(t, dtype=bool)
            if window is not None:
                sel = (t >= window[0]) & (t <= window[1])
            for name in self.imus:
                m, s = self.mean[name][sel], self.std[name][sel]
                (line,) = ax.plot(t[sel], m, label=f"{name} (mean)")
                if np.all(np.isfinite(s)):
                    ax.fill_between(
                        t[sel],
                        m - s,
                        m + s,
                        color=line.get_color(),
                        alpha=0.2,
                        label=f"{name} ± std",
                    )
            if outage is not None:
                ax.axvspan(
                    outage[0], outage[0] + outage[1], color="grey", alpha=0.15, label="GNSS outage"
                )
            if window is not None:
                # The outage band must not widen a zoom beyond its window.
                ax.set_xlim(*window)
            ax.set_title(f"{title} ({n} runs)")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("position error norm [m]")
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize="small")
            return fig

        if outage is None:
            early = float(self.config.get("early_window", 150.0))
            return {
                "fig14": figure("Fig. 14: position error, 6 satellites", None),
                "fig15": figure(f"Fig. 15: position error, first {early:.0f} s", (0.0, early)),
            }
        start = float(outage[0])
        return {
            "fig16": figure(f"Fig. 16: position error, {outage[1]:.0f} s outage", None),
            "fig17": figure("Fig. 17: outage, first 15 s", (start - 2.0, start + 15.0)),
            "fig18": figure("Fig. 18: outage, first 5 s", (start - 2.0, start + 5.0)),
        }


def navigation(
    outage: tuple[float, float] | None = None,
    runs: int = 20,
    duration: float = 600.0,
    seed: int = 0,
    imus: Sequence[str] | Mapping[str, Any] = PAPER_IMUS,
    n_satellites: int = 6,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    keep_runs: bool = False,
    *,
    calibration_duration: float = 300.0,
    early_window: float = 150.0,
    pseudorange_rate: bool = True,
    pseudorange_std: float = 3.0,
    pseudorange_rate_std: float = 0.1,
    initial_attitude_std_deg: tuple[float, float, float] = (1.0, 1.0, 5.0),
    scale_factor_states: bool = False,
    absorb_unmodelled: bool = True,
) -> NavigationResult:
    """Runs the navigation Monte Carlo (paper §5.3) in Rust, GIL released.

    ``outage``: ``(start_s, length_s)`` total GNSS outage (no satellites;
    paper: 30 s), start ≥ 1 s; ``None``: 6 satellites all along (figs 14-15).
    ``runs`` (paper: 200) of ``duration`` s each (paper: 600). ``imus``: names
    among ``"ins"``, ``"mems"``, ``"calibrated_mems"`` (needs ``"mems"``
    earlier in the set) or any preset name of ``ImuModel.presets()``; or a
    dict name → ``ImuModel`` (that very sensor in every run, noise drawn per
    run; its sample rate must be 100 Hz), preset name, or
    ``("calibrated", raw_name)``. ``n_satellites`` ≥ 4 tracked all along.
    ``threads``: worker threads (None: all cores); the numbers do not
    depend on it. ``progress(done, total)`` is called from the calling
    thread as runs complete. Ctrl-C stops the set after the runs under way
    and returns the completed ones with ``interrupted=True``.
    ``keep_runs``: keep every run's curves (always for ``runs <= 50``).
    ``calibration_duration``: calibration segment of calibrated IMUs, s.
    ``early_window``: window of the early RMS summary and of fig. 15, s.

    Study options (``docs/paper-comparison.md``; defaults unchanged):
    ``pseudorange_rate``: the filters also use the pseudorange rates (True)
    or pseudoranges only (False, the paper's wording of its tight
    coupling). ``pseudorange_std`` (m) and ``pseudorange_rate_std`` (m/s):
    the simulated GNSS white noise, one sigma, also the filters' measurement
    std. ``initial_attitude_std_deg``: (north tilt, east tilt, heading) one
    sigma, degrees, of the initial attitude error drawn per run (shared by
    the IMUs of a run) and of every filter's initial attitude uncertainty.
    ``scale_factor_states``: every filter carries accelerometer and gyro
    scale-factor states (23 instead of 17). ``absorb_unmodelled``: every
    filter's tuning covers the deterministic errors its state lacks
    (scale factor, misalignment, nonlinearity, g-sensitivity) by inflated
    initial bias uncertainty and white noise (True), or ignores them (False:
    tuned from the spec's biases and noise only).

    Raises ValueError naming the argument for bad input.
    """
    if not isinstance(runs, int) or isinstance(runs, bool) or runs < 1:
        raise ValueError(f"runs: must be a positive integer, got {runs!r}")
    if outage is not None:
        try:
            start, length = (float(v) for v in outage)
        except (TypeError, ValueError):
            raise ValueError(
                f"outage: expected (start_s, length_s) or None, got {outage!r}"
            ) from None
        outage = (start, length)
    try:
        attitude_std = tuple(float(v) for v in initial_attitude_std_deg)
    except (TypeError, ValueError):
        attitude_std = ()
    if len(attitude_std) != 3:
        raise ValueError(
            "initial_attitude_std_deg: expected three numbers (north tilt, east tilt, "
            f"heading), got {initial_attitude_std_deg!r}"
        )
    keep = bool(keep_runs) or runs <= KEEP_RUNS_UP_TO
    raw = _memsnav.navigation_experiment(
        _imu_sources(imus),
        runs=runs,
        duration=float(duration),
        seed=seed,
        n_satellites=n_satellites,
        outage=outage,
        calibration_duration=float(calibration_duration),
        early_window=float(early_window),
        pseudorange_rate=bool(pseudorange_rate),
        pseudorange_std=float(pseudorange_std),
        pseudorange_rate_std=float(pseudorange_rate_std),
        initial_attitude_std_deg=attitude_std,
        scale_factor_states=bool(scale_factor_states),
        absorb_unmodelled=bool(absorb_unmodelled),
        keep_runs=keep,
        threads=threads,
        progress=progress,
    )
    entries = raw["imus"]
    names = [e["name"] for e in entries]
    kept = entries[0]["position_error_runs"] is not None
    return NavigationResult(
        time=raw["time"],
        mean={n: e["position_error_mean"] for n, e in zip(names, entries, strict=True)},
        std={n: e["position_error_std"] for n, e in zip(names, entries, strict=True)},
        percentiles={
            n: e["position_error_percentiles"] for n, e in zip(names, entries, strict=True)
        },
        nees_mean={n: e["nees_mean"] for n, e in zip(names, entries, strict=True)},
        position_error=(
            {n: e["position_error_runs"] for n, e in zip(names, entries, strict=True)}
            if kept
            else None
        ),
        nees={n: e["nees_runs"] for n, e in zip(names, entries, strict=True)} if kept else None,
        runs_summary={
            n: {
                "rms": e["run_rms"],
                "rms_early": e["run_rms_early"],
                "final": e["run_final"],
                "max_in_outage": e["run_max_in_outage"],
                "mean_nees_per_dof": e["run_mean_nees_per_dof"],
                "rejected": e["run_rejected"],
                "accepted": e["run_accepted"],
            }
            for n, e in zip(names, entries, strict=True)
        },
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
        config={
            "outage": outage,
            "runs": runs,
            "duration": float(duration),
            "seed": seed,
            "imus": names,
            "n_satellites": n_satellites,
            "calibration_duration": float(calibration_duration),
            "early_window": float(early_window),
            "pseudorange_rate": bool(pseudorange_rate),
            "pseudorange_std": float(pseudorange_std),
            "pseudorange_rate_std": float(pseudorange_rate_std),
            "initial_attitude_std_deg": attitude_std,
            "scale_factor_states": bool(scale_factor_states),
            "absorb_unmodelled": bool(absorb_unmodelled),
        },
    )
