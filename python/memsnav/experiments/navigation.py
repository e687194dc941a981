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
uncertainty and process noise shaped by the sensed motion. The
calibrated MEMS is tuned from the calibration's own parameter
uncertainties. Initial position, velocity and
clock come from the least-squares fix of the first epoch; the initial
attitude is the truth rotated by a draw of 1° tilt and 5° heading (the
filter's P₀).

Every run is reproducible from ``(seed, run index)`` whatever the thread
count; each IMU draws from its own stream, so dropping an IMU from the set
does not change the others' numbers.

What our numbers show against the paper: the report of ``memsnav
reproduce`` (each claim's verdict computed from its numbers by a criterion
fixed in ``memsnav.report.claims``) and ``docs/results/paper-comparison.md`` (the
study behind the differences and the options it uses).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from memsnav import _memsnav as _mn
from memsnav._distributed import run_set
from memsnav.experiments._plotting import legend_below

_STYLES: list[dict[str, Any]] = [
    {"ls": "-", "lw": 1.6},
    {"ls": "--", "lw": 2.4},
    {"ls": "-.", "lw": 1.2},
    {"ls": ":", "lw": 2.0},
]
"""Line styles of the IMUs, in the set's order."""

PAPER_IMUS = ("ins", "mems", "calibrated_mems")
"""The paper's three IMUs (figures 14-18)."""

IMU_LABELS = {"ins": "INS", "mems": "MEMS", "calibrated_mems": "calibrated MEMS"}
"""The paper's IMUs as the figures and reports name them."""


def imu_label(name: str) -> str:
    """An IMU's name for a reader: the paper's words for its three, a
    user's own name as given."""
    return IMU_LABELS.get(name, name)


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
      filter is consistent); ``position_nees_mean``: the same for the
      position alone (3 degrees of freedom).
    - ``position_error`` / ``nees``: per IMU, ``(runs, T)`` arrays of every
      run, kept when ``keep_runs=True`` or ``runs <= 50``; otherwise
      ``None`` (the set is then folded run by run in bounded memory).
    - ``runs_summary``: per IMU, per-run scalars ``rms`` (m), ``rms_early``
      (m, t ≤ ``early_window`` s), ``rms_late`` (m, after it), ``final``
      (m), ``max_in_outage``, ``max_horizontal_in_outage`` and
      ``max_vertical_in_outage`` (m, the error norm and its NED parts,
      NaN without outage), ``at_outage_end`` and
      ``horizontal_at_outage_end`` (m, the error norm and its horizontal
      part at the last epoch of the outage, NaN without outage),
      ``mean_nees_per_dof``, ``position_nees_per_dof_at_outage_end``
      (position NEES / 3 at the last epoch of the outage, NaN without
      outage), ``diverged`` (bool: the run raised an integrity alert, its
      solution flagged as not trustworthy; see ``FilterSolution.integrity``),
      ``rejected`` (count), ``accepted`` (count of scalar measurements
      applied).
    - ``smoothed``: with ``smooth=True``, the same result for the
      fixed-interval smoothed solution of every filter (its NEES is NaN:
      the smoother keeps the diagonal blocks of the covariance only);
      otherwise ``None``.
    - ``completed_runs``; ``interrupted``: True when Ctrl-C (or a failing
      progress callback) stopped the set early — the statistics then cover
      the completed runs only.
    """

    time: npt.NDArray[np.float64]
    mean: dict[str, npt.NDArray[np.float64]]
    std: dict[str, npt.NDArray[np.float64]]
    percentiles: dict[str, npt.NDArray[np.float64]]
    nees_mean: dict[str, npt.NDArray[np.float64]]
    position_nees_mean: dict[str, npt.NDArray[np.float64]]
    position_error: dict[str, npt.NDArray[np.float64]] | None
    nees: dict[str, npt.NDArray[np.float64]] | None
    runs_summary: dict[str, dict[str, npt.NDArray[Any]]]
    completed_runs: int
    interrupted: bool
    config: dict[str, Any] = field(default_factory=dict)
    smoothed: NavigationResult | None = None

    def __repr__(self) -> str:
        outage = self.config.get("outage")
        return (
            f"NavigationResult({', '.join(self.imus)}: {self.completed_runs} runs of "
            f"{self.time[-1]:g} s"
            + (f", outage {tuple(outage)}" if outage else "")
            + (", smoothed" if self.smoothed is not None else "")
            + (", interrupted" if self.interrupted else "")
            + ")"
        )

    @property
    def imus(self) -> list[str]:
        """IMU names, in the set's order."""
        return list(self.mean)

    @property
    def early_key(self) -> str:
        """The name of the early-window keys: ``first_150s`` for 150 s."""
        return f"first_{round(self.config.get('early_window', 150.0))}s"

    @property
    def late_key(self) -> str:
        """The name of the keys after the early window: ``after_150s``."""
        return f"after_{round(self.config.get('early_window', 150.0))}s"

    def _outage_window(self) -> npt.NDArray[np.bool_]:
        outage = self.config.get("outage")
        if outage is None:
            return np.zeros_like(self.time, dtype=bool)
        start, length = outage[0], outage[1]
        inside: np.ndarray = (self.time >= start) & (self.time < start + length)
        return inside

    def _per_run(self, name: str) -> dict[str, npt.NDArray[np.float64]]:
        """Per-run values whose mean over runs is each summary figure (the
        RMS figures are means of per-run mean squares)."""
        runs = self.runs_summary[name]
        out = {
            "rms_position_error_m": runs["rms"] ** 2,
            f"rms_position_error_{self.early_key}_m": runs["rms_early"] ** 2,
            f"rms_position_error_{self.late_key}_m": runs["rms_late"] ** 2,
            "final_position_error_m": runs["final"],
            "mean_nees_per_dof": runs["mean_nees_per_dof"],
            "rejected_measurements_per_run": runs["rejected"].astype(float),
            "diverged_share": runs["diverged"].astype(float),
        }
        if self.config.get("outage") is not None:
            out["position_nees_per_dof_at_outage_end"] = runs["position_nees_per_dof_at_outage_end"]
            out["mean_max_position_error_during_outage_m"] = runs["max_in_outage"]
            out["mean_max_horizontal_error_during_outage_m"] = runs["max_horizontal_in_outage"]
            out["mean_max_vertical_error_during_outage_m"] = runs["max_vertical_in_outage"]
        return out

    def summary(self) -> dict[str, dict[str, Any]]:
        """Per IMU name, means over the completed runs (m unless stated),
        each with its Monte Carlo standard error in ``standard_error``:

        - ``rms_position_error_m``: √(mean over runs and epochs of |δr|²);
          ``rms_position_error_first_150s_m`` (named after ``early_window``)
          and ``rms_position_error_after_150s_m``: the same over the epochs
          t ≤ 150 s and after;
        - ``final_position_error_m``: mean over runs of |δr| at the last epoch;
        - ``mean_nees_per_dof``: mean over runs and epochs of NEES / 9
          (≈ 1 for a consistent filter);
        - ``rejected_measurements_per_run``: mean count of gated/invalid
          measurements;
        - ``diverged_share``: the share of runs that raised an integrity
          alert (their solution flagged as not trustworthy);
        - with an outage: ``max_position_error_during_outage_m`` (maximum over
          the outage of the mean-over-runs error curve, what figs 16-18 show;
          its standard error is the runs' spread at that epoch over √runs),
          ``mean_max_position_error_during_outage_m`` (mean over runs of each
          run's maximum; ``mean_max_horizontal_error_during_outage_m`` and
          ``mean_max_vertical_error_during_outage_m`` the same for the
          horizontal and vertical parts of the error in local NED) and
          ``position_error_at_outage_end_m`` (mean curve at
          the last epoch of the outage, before GNSS returns) and
          ``position_nees_per_dof_at_outage_end`` (the Monte Carlo position
          NEES / 3 there: 1 for a covariance that matches the errors). The outage
          covers the epochs in [start, start + length).

        Standard errors of RMS figures follow from those of the mean squares
        (δ method); all are NaN for a single run.
        """
        n = self.completed_runs
        inside = self._outage_window()
        out: dict[str, dict[str, Any]] = {}
        for name in self.runs_summary:
            s: dict[str, Any] = {}
            se: dict[str, float] = {}
            for key, values in self._per_run(name).items():
                mean = float(np.mean(values)) if n else math.nan
                error = float(np.std(values, ddof=1) / math.sqrt(n)) if n > 1 else math.nan
                if key.startswith("rms_"):
                    mean = math.sqrt(mean)
                    error = error / (2.0 * mean) if mean > 0 else math.nan
                s[key] = mean
                se[key] = error
            if inside.any():
                curve = self.mean[name][inside]
                peak = int(np.argmax(curve))
                s["max_position_error_during_outage_m"] = float(curve[peak])
                se["max_position_error_during_outage_m"] = (
                    float(self.std[name][inside][peak] / math.sqrt(n)) if n > 1 else math.nan
                )
                s["position_error_at_outage_end_m"] = float(curve[-1])
                se["position_error_at_outage_end_m"] = (
                    float(self.std[name][inside][-1] / math.sqrt(n)) if n > 1 else math.nan
                )
            s["standard_error"] = se
            out[name] = s
        return out

    def paired_difference(self, first: str, second: str) -> dict[str, dict[str, float]]:
        """``first`` minus ``second`` (IMU names) run by run, for the per-run
        figures of :meth:`summary` (RMS figures as differences of per-run
        RMS): ``{key: {"difference", "standard_error"}}`` — the paired
        comparison's own uncertainty, smaller than the two standard errors
        combined because both IMUs fly the same trajectories."""
        n = self.completed_runs
        a, b = self.runs_summary[first], self.runs_summary[second]
        pairs = {
            "rms_position_error_m": ("rms",),
            f"rms_position_error_{self.early_key}_m": ("rms_early",),
            f"rms_position_error_{self.late_key}_m": ("rms_late",),
            "final_position_error_m": ("final",),
        }
        if self.config.get("outage") is not None:
            pairs["mean_max_position_error_during_outage_m"] = ("max_in_outage",)
        out = {}
        for key, (field_name,) in pairs.items():
            d = np.asarray(a[field_name], dtype=float) - np.asarray(b[field_name], dtype=float)
            out[key] = {
                "difference": float(d.mean()) if n else math.nan,
                "standard_error": float(d.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan,
            }
        return out

    def plot(self) -> dict[str, Any]:
        """The paper's figures as matplotlib figures: mean ± std over runs of
        the position error norm vs time, one curve per IMU.

        Without outage: ``"fig14"`` (whole run) and ``"fig15"`` (zoom on the
        first ``early_window`` s), each with a panel below of every other
        IMU's mean error less the first IMU's (the curves lie within a few
        per cent of each other while aided). With an outage: ``"fig16"`` (whole run),
        ``"fig17"`` (the outage's first 15 s) and ``"fig18"`` (its first 5 s),
        each zoom starting 2 s before the outage.
        """
        import matplotlib.pyplot as plt

        outage = self.config.get("outage")
        n = self.completed_runs

        def figure(title: str, window: tuple[float, float] | None, against: str | None) -> Any:
            # Against an IMU: a second panel with each other IMU's mean error
            # less that IMU's, the differences the top panel cannot show
            # where the curves lie on each other (1 % apart while aided).
            if against is None:
                fig, ax = plt.subplots(figsize=(7.0, 4.2))
            else:
                fig, (ax, below) = plt.subplots(
                    2, 1, figsize=(7.0, 6.0), sharex=True, height_ratios=(3, 2)
                )
            t = self.time
            sel = np.ones_like(t, dtype=bool)
            if window is not None:
                sel = (t >= window[0]) & (t <= window[1])
            for k, name in enumerate(self.imus):
                m, s = self.mean[name][sel], self.std[name][sel]
                # Distinct dashes and widths: curves that coincide (raw and
                # calibrated MEMS while aided) stay visible over each other.
                style = _STYLES[k % len(_STYLES)]
                (line,) = ax.plot(t[sel], m, label=f"{imu_label(name)} (mean)", **style)
                if np.all(np.isfinite(s)):
                    ax.fill_between(
                        t[sel],
                        m - s,
                        m + s,
                        color=line.get_color(),
                        alpha=0.12,
                        label=f"{imu_label(name)} ± std",
                    )
                if against is not None and name != against:
                    below.plot(
                        t[sel],
                        m - self.mean[against][sel],
                        color=line.get_color(),
                        label=f"{imu_label(name)} − {imu_label(against)}",
                        **style,
                    )
            if outage is not None:
                ax.axvspan(
                    outage[0], outage[0] + outage[1], color="grey", alpha=0.15, label="GNSS outage"
                )
            if window is not None:
                # The outage band must not widen a zoom beyond its window.
                ax.set_xlim(*window)
            ax.set_title(f"{title} ({n} runs)")
            ax.set_ylabel("position error norm [m]")
            ax.grid(True, alpha=0.3)
            if against is None:
                ax.set_xlabel("time [s]")
            else:
                below.axhline(0.0, color="k", lw=0.6)
                below.set_ylabel(f"mean error less the\n{imu_label(against)}'s [m]")
                below.set_xlabel("time [s]")
                below.grid(True, alpha=0.3)
                below.legend(fontsize="small", loc="upper right")
            legend_below(fig, ax, ncol=3)
            return fig

        # The first IMU (the INS of the paper's set) is what the others are
        # compared with while aided, where their curves coincide.
        reference = self.imus[0] if len(self.imus) > 1 else None
        if outage is None:
            early = float(self.config.get("early_window", 150.0))
            return {
                "fig14": figure("Fig. 14: position error, 6 satellites", None, reference),
                "fig15": figure(
                    f"Fig. 15: position error, first {early:.0f} s", (0.0, early), reference
                ),
            }
        start = float(outage[0])
        kept = "no satellite" if len(outage) < 3 or outage[2] == 0 else f"{outage[2]} satellites"
        return {
            "fig16": figure(f"Fig. 16: position error, {outage[1]:.0f} s with {kept}", None, None),
            "fig17": figure("Fig. 17: outage, first 15 s", (start - 2.0, start + 15.0), None),
            "fig18": figure("Fig. 18: outage, first 5 s", (start - 2.0, start + 5.0), None),
        }


def navigation(
    outage: tuple[float, float] | tuple[float, float, int] | None = None,
    runs: int | None = None,
    duration: float | None = None,
    seed: int | None = None,
    imus: Sequence[str] | Mapping[str, Any] = PAPER_IMUS,
    n_satellites: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    keep_runs: bool = False,
    *,
    calibration_duration: float | None = None,
    early_window: float | None = None,
    pseudorange_rate: bool | None = None,
    pseudorange_std: float | None = None,
    pseudorange_rate_std: float | None = None,
    initial_attitude_std_deg: tuple[float, float, float] | None = None,
    scale_factor_states: bool = False,
    absorb_unmodelled: bool | None = None,
    smooth: bool = False,
    systems: Sequence[str] = ("G",),
    inter_system_bias: Sequence[float] = (0.0, 0.0),
    carrier_phase_std: float | None = None,
    cycle_slip_probability: float | None = None,
    client: Any = None,
    chunk_runs: int | None = None,
) -> NavigationResult:
    """Runs the navigation Monte Carlo (paper §5.3) in Rust, GIL released.

    ``outage``: ``(start_s, length_s)``, a total GNSS outage (paper: 30 s),
    or ``(start_s, length_s, n_visible)`` keeping ``n_visible`` satellites
    (0-3) through the window: the highest of those tracked — an urban
    canyon's view, and the worst horizontal geometry of the set (high
    satellites constrain mostly the height and the clock); start ≥ 1 s.
    ``None``: 6 satellites all along (figs 14-15). The window's satellites
    carry the same noise as without the outage (outages are applied after
    every draw), so runs with different outages are paired.
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

    Study options (``docs/results/paper-comparison.md``; defaults unchanged):
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
    tuned from the spec's biases and noise only). ``smooth``: also run the
    fixed-interval (RTS) smoother after every filter and report its error
    in ``result.smoothed`` (``docs/explanation/smoother.md``; about twice the time and
    the memory of a forward solution per run in flight).
    ``systems``: the simulated satellite systems, RINEX letters among "G"
    (GPS), "E" (Galileo), "C" (BeiDou MEO), "R" (GLONASS), each a nominal
    Walker constellation (:meth:`memsnav.Constellation.nominal`); with
    another system than GPS every filter carries three inter-system-bias
    states, and the pseudoranges ``inter_system_bias`` (Galileo, BeiDou[,
    GLONASS] against GPS, m).
    ``n_satellites`` counts every system's satellites.
    ``carrier_phase_std``: white noise of the simulated carrier range, one
    sigma, m, as in :func:`memsnav.simulate_gnss` (default 0: no carrier
    phase, the results as without it); above 0 the tightly coupled filters
    also use the carrier's change between epochs (time-differenced carrier
    phase, 5 changes or more per epoch; the loosely coupled filter is
    unaffected), and the carrier slips silently by whole cycles with
    ``cycle_slip_probability`` per satellite and epoch (default 0).

    ``client``: a ``dask.distributed.Client``: the runs go to its cluster
    in chunks of ``chunk_runs`` (default: about 4 chunks per worker
    thread), folded here in run order, so the numbers are bit for bit
    those of local threads (``docs/how-to/run-on-dask.md``); ``threads`` must
    then be None.

    Every argument left None takes the core's default, listed by
    ``memsnav.defaults()["navigation_experiment"]``.

    Raises ValueError naming the argument for bad input.
    """
    default = _mn.defaults()["navigation_experiment"]

    def given(value: Any, key: str) -> Any:
        return default[key] if value is None else value

    runs = given(runs, "runs")
    duration = given(duration, "duration")
    seed = given(seed, "seed")
    n_satellites = given(n_satellites, "n_satellites")
    calibration_duration = given(calibration_duration, "calibration_duration")
    early_window = given(early_window, "early_window")
    pseudorange_rate = given(pseudorange_rate, "pseudorange_rate")
    pseudorange_std = given(pseudorange_std, "pseudorange_std")
    pseudorange_rate_std = given(pseudorange_rate_std, "pseudorange_rate_std")
    initial_attitude_std_deg = given(initial_attitude_std_deg, "initial_attitude_std_deg")
    absorb_unmodelled = given(absorb_unmodelled, "absorb_unmodelled")
    carrier_phase_std = real_number(
        given(carrier_phase_std, "carrier_phase_std"), "carrier_phase_std"
    )
    cycle_slip_probability = real_number(
        given(cycle_slip_probability, "cycle_slip_probability"), "cycle_slip_probability"
    )
    if not isinstance(runs, int) or isinstance(runs, bool) or runs < 1:
        raise ValueError(f"runs: must be a positive integer, got {runs!r}")
    window: tuple[float, float, int] | None = None
    if outage is not None:
        try:
            values = [float(v) for v in outage]
            if len(values) not in (2, 3) or (len(values) == 3 and not values[2].is_integer()):
                raise ValueError
        except (TypeError, ValueError):
            raise ValueError(
                "outage: expected (start_s, length_s) or (start_s, length_s, n_visible) "
                f"or None, got {outage!r}"
            ) from None
        window = (values[0], values[1], int(values[2]) if len(values) == 3 else 0)
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
    raw = run_set(
        "navigation_experiment",
        dict(
            imus=_imu_sources(imus),
            runs=runs,
            duration=float(duration),
            seed=seed,
            n_satellites=n_satellites,
            outage=window,
            calibration_duration=float(calibration_duration),
            early_window=float(early_window),
            pseudorange_rate=bool(pseudorange_rate),
            pseudorange_std=float(pseudorange_std),
            pseudorange_rate_std=float(pseudorange_rate_std),
            initial_attitude_std_deg=attitude_std,
            scale_factor_states=bool(scale_factor_states),
            absorb_unmodelled=bool(absorb_unmodelled),
            smooth=bool(smooth),
            keep_runs=keep,
            systems=list(systems),
            inter_system_bias=tuple(float(b) for b in inter_system_bias),
            carrier_phase_std=carrier_phase_std,
            cycle_slip_probability=cycle_slip_probability,
        ),
        runs,
        client=client,
        threads=threads,
        progress=progress,
        chunk_runs=chunk_runs,
    )
    return result_from_raw(
        raw,
        {
            "outage": window,
            "runs": runs,
            "duration": float(duration),
            "seed": seed,
            "imus": [name for name, _ in _imu_sources(imus)],
            "n_satellites": n_satellites,
            "calibration_duration": float(calibration_duration),
            "early_window": float(early_window),
            "pseudorange_rate": bool(pseudorange_rate),
            "pseudorange_std": float(pseudorange_std),
            "pseudorange_rate_std": float(pseudorange_rate_std),
            "initial_attitude_std_deg": attitude_std,
            "scale_factor_states": bool(scale_factor_states),
            "absorb_unmodelled": bool(absorb_unmodelled),
            "smooth": bool(smooth),
            "systems": list(systems),
            "inter_system_bias": [float(b) for b in inter_system_bias],
            "carrier_phase_std": carrier_phase_std,
            "cycle_slip_probability": cycle_slip_probability,
        },
    )


def real_number(value: Any, argument: str) -> float:
    """``value`` as a float if it is a real number (not a bool); the core
    checks its range. Raises ValueError naming ``argument``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{argument}: must be a number, got {value!r}")
    return float(value)


def result_from_raw(raw: Mapping[str, Any], config: dict[str, Any]) -> NavigationResult:
    """A :class:`NavigationResult` from the binding's dict (``time``,
    ``imus``, ``completed_runs``, ``interrupted``) and its ``config``."""
    entries = raw["imus"]
    names = [e["name"] for e in entries]
    kept = entries[0]["position_error_runs"] is not None
    smoothed = None
    if entries[0].get("smoothed") is not None:
        smoothed = result_from_raw(
            {**raw, "imus": [e["smoothed"] for e in entries]}, {**config, "smoothed": True}
        )
    return NavigationResult(
        time=raw["time"],
        mean={n: e["position_error_mean"] for n, e in zip(names, entries, strict=True)},
        std={n: e["position_error_std"] for n, e in zip(names, entries, strict=True)},
        percentiles={
            n: e["position_error_percentiles"] for n, e in zip(names, entries, strict=True)
        },
        nees_mean={n: e["nees_mean"] for n, e in zip(names, entries, strict=True)},
        position_nees_mean={
            n: e["position_nees_mean"] for n, e in zip(names, entries, strict=True)
        },
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
                "rms_late": e["run_rms_late"],
                "final": e["run_final"],
                "max_in_outage": e["run_max_in_outage"],
                "max_horizontal_in_outage": e["run_max_horizontal_in_outage"],
                "max_vertical_in_outage": e["run_max_vertical_in_outage"],
                "at_outage_end": e["run_at_outage_end"],
                "horizontal_at_outage_end": e["run_horizontal_at_outage_end"],
                "mean_nees_per_dof": e["run_mean_nees_per_dof"],
                "position_nees_per_dof_at_outage_end": e["run_position_nees_per_dof_at_outage_end"],
                "diverged": e["run_diverged"],
                "rejected": e["run_rejected"],
                "accepted": e["run_accepted"],
            }
            for n, e in zip(names, entries, strict=True)
        },
        completed_runs=int(raw["completed_runs"]),
        interrupted=bool(raw["interrupted"]),
        config=config,
        smoothed=smoothed,
    )
