"""The foreign drive (VN-100, F9T fixes, INS-D truth; another team's car)
run with the engine's defaults: the bounds the log's own model gives hold,
the coast beats a plain EKF's published figures on the same drive, and
the smoother gets within a tenth of the straight line between the fixes
that bound each outage (computed here from the run's own fixes and truth).
The same run with nothing learnt (the consumer preset, white fixes) does
not hold its bounds: the learning is what makes the difference.
docs/results/foreign-drive.md shows the figures (docs/foreign_drive_study.py)."""

from __future__ import annotations

import foreign_drive_study as study
import pytest
from figures import figures
from record_agreement import agree
from shared_data import data_root, shared_data

import memsnav as mn

#: A plain 15-state EKF (navtk) on the same drive with 30 s outages:
#: horizontal RMS and max over the outages, m.
PLAIN_EKF_30_S = (4.4, 12.1)


@pytest.fixture(scope="module")
def base():
    shared_data("foreign-drive/vn100_imu.csv")
    return mn.load_config(study.ROOT / "examples" / "foreign_drive.toml", data_root())


#: What the page shows of a configuration to its digits: errors 0.01 m
#: (RMS) and 0.1 m (max), shares, NIS band ratios and the installation to
#: 0.01; counts
#: and what was learnt exactly (its std 0.01 m, τ 1 s); the run time is the
#: machine's, not checked.
ROW_TOLERANCE = {
    "forward_aided": {"max_m": 0.05, "*": 0.005},
    "forward_outages": {"max_m": 0.05, "*": 0.005},
    "smoothed_aided": {"max_m": 0.05, "*": 0.005},
    "smoothed_outages": {"max_m": 0.05, "*": 0.005},
    "resets": 0,
    "diverged": 0,
    "nis_band_ratio_most": 0.005,
    "learnt": {"fix_error_std_m": 0.005, "fix_error_correlation_time_s": 0.5, "*": 0},
    "installation": 0.005,
    "run_s": float("inf"),
}


def _agrees_with_the_record(result, name: str, length_s: float) -> None:
    """``result``'s row of the study equals the record's within the digits
    docs/results/foreign-drive.md shows."""
    fresh = {"name": name} | study.configuration_figures(result, length_s, 0.0)
    recorded = figures("foreign_drive_study")[f"{length_s:g}"]["configurations"]
    differ = agree(fresh, recorded[study.slug(name)], {"name": 0} | ROW_TOLERANCE)
    assert not differ, f"{differ}: rerun python docs/doc_runs.py foreign_drive_study if meant"


@pytest.mark.slow
def test_the_defaults_hold_their_bounds_and_coast_on_a_foreign_drive(base):
    result, _ = study.run(study.configured(base, "defaults", 30.0))
    _agrees_with_the_record(result, "defaults", 30.0)
    s = result.summary
    assert not s["integrity"]["diverged"] and "failure" not in s
    assert s["adaptation"]["imu_preset"] == "industrial"
    learnt = s["adaptation"]
    assert learnt["fix_correlation"]["correlation_time_s"] > 30.0
    # The F9T's errors exceed the σ it reports: the states carry more.
    assert learnt["fix_error_std_m"] > 0.5
    forward, smoothed = s["errors_vs_truth"], s["errors_vs_truth_smoothed"]
    for errors in (forward, smoothed):
        assert errors["aided"]["within_3sigma_share_horizontal"] >= 0.9
        assert errors["by_outage_length_s"]["30"]["within_3sigma_share_horizontal"] >= 0.9
    coast = forward["by_outage_length_s"]["30"]
    assert coast["rms_horizontal_m"] < PLAIN_EKF_30_S[0]
    assert coast["max_horizontal_m"] < PLAIN_EKF_30_S[1]
    line_rms, _ = study.straight_line(result, 30.0)
    assert smoothed["by_outage_length_s"]["30"]["rms_horizontal_m"] <= line_rms / 10.0


@pytest.mark.slow
def test_with_nothing_learnt_the_aided_bounds_fail(base):
    result, _ = study.run(study.configured(base, "fixed consumer, white fixes", 30.0))
    _agrees_with_the_record(result, "fixed consumer, white fixes", 30.0)
    s = result.summary
    assert s["adaptation"]["imu_candidates"] == [] and s["adaptation"]["fix_correlation"] is None
    assert s["errors_vs_truth"]["aided"]["within_3sigma_share_horizontal"] < 0.8
    assert s["errors_vs_truth_smoothed"]["aided"]["within_3sigma_share_horizontal"] < 0.5
