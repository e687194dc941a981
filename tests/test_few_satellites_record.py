"""docs/explanation/few-satellites.md is its record: the study's tables
are what docs/few_satellites_study.py renders from
docs/data/few_satellites.json, the figures its sentences draw from them
are the record's own arithmetic, the page's claims hold on the record,
and a part of the study rerun today agrees with it."""

import math

import few_satellites_study as study
import pytest
from figures import ROOT, figures, load_record

RECORD = figures("few_satellites")


def test_the_tables_are_the_records():
    text = (ROOT / "docs" / "explanation" / "few-satellites.md").read_text()
    block = text[text.index(study.BEGIN) : text.index(study.END) + len(study.END)]
    assert block == study.render(load_record("few_satellites")), (
        "docs/explanation/few-satellites.md's tables are stale: run "
        "python docs/few_satellites_study.py --from-record"
    )


def test_the_sentences_figures_are_the_tables_arithmetic():
    fresh, kept = study.derived(RECORD), RECORD["derived"]

    def close(a, b, path=""):
        if isinstance(b, dict):
            assert a.keys() == b.keys(), path
            for k in b:
                close(a[k], b[k], f"{path}.{k}")
        else:
            assert math.isclose(a, b, rel_tol=1e-12), (path, a, b)

    close(fresh, kept)


def test_the_record_says_what_the_page_claims():
    """Every satellite kept helps; the covariance covers the total outage
    for every grade; with 3 satellites every error is inside 3σ and an
    OCXO ends under 100 m; with 2 and 1 every run is flagged."""
    kept = [f["largest_m"] for f in RECORD["paired"]]
    assert kept == sorted(kept, reverse=True), kept
    nees = RECORD["derived"]["nees_at_end"]
    assert 0.3 < nees["least"] <= nees["most"] < 1.5
    cases = {(f["satellites"], f["clock"]): f for f in RECORD["long_runs"]}
    assert round(cases[3, "TCXO"]["inside"]["least"], 2) == 1.0
    assert cases[3, "OCXO"]["final_m"] < 100.0
    for n in (2, 1):
        assert cases[n, "TCXO"]["flagged"] == cases[n, "TCXO"]["runs"]
    # The raw MEMS's aided tilt is overconfident; the tactical IMU's is not.
    assert RECORD["derived"]["raw_tilt_nees"]["least"] > 1.5
    assert RECORD["attitude"]["tactical"]["10"]["tilt"] < 1.5


@pytest.mark.slow
def test_the_total_outage_covariance_is_a_fresh_run():
    """The study's covariance table rerun (16 runs of 300 s per grade):
    errors shown to 0.1 m, NEES to 0.01."""
    fresh = study.outage_nees_figures()
    for imu, recorded in RECORD["outage_nees"].items():
        assert abs(fresh[imu]["error_at_end_m"] - recorded["error_at_end_m"]) <= 0.05, imu
        for key in ("nees_per_dof_at_end", "nees_per_dof_least", "nees_per_dof_most"):
            assert abs(fresh[imu][key] - recorded[key]) <= 0.005, (imu, key)
