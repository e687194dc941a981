"""docs/results/against-rtk.md is its record: the tables are what
docs/real_data_benchmark.py renders from docs/data/against_rtk.json, the
figures its sentences draw from the tables are the record's own
arithmetic, and the runs the other records repeat agree with it (no run
here: the benchmark takes minutes; tests/test_doc_runs.py reruns the
drive's outage windows)."""

import math

import real_data_benchmark as benchmark
from figures import ROOT, figures, load_record

RECORD = figures("against_rtk")


def test_the_tables_are_the_records():
    text = (ROOT / "docs" / "results" / "against-rtk.md").read_text()
    block = text[text.index(benchmark.BEGIN) : text.index(benchmark.END) + len(benchmark.END)]
    assert block == benchmark.render(load_record("against_rtk")), (
        "docs/results/against-rtk.md's tables are stale: run "
        "python docs/real_data_benchmark.py --from-record"
    )


def _close(a, b, path=""):
    if isinstance(b, dict):
        assert a.keys() == b.keys(), path
        for k in b:
            _close(a[k], b[k], f"{path}.{k}")
    elif isinstance(b, list):
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            _close(x, y, f"{path}.{k}")
    else:
        assert math.isclose(a, b, rel_tol=1e-12), (path, a, b)


def test_the_sentences_figures_are_the_tables_arithmetic():
    _close(benchmark.derived(RECORD), RECORD["derived"])


def test_the_drive_is_what_the_other_settings_run_repeats():
    """The example's outage runs, rerun by docs/doc_runs.py's
    drive_other_settings (and by its slow test): the same errors."""
    example = figures("drive_other_settings")["example"]
    lengths = RECORD["drive"]["lengths"].values()
    for key, column in (("forward_rms_m", "forward"), ("smoothed_rms_m", "smoothed")):
        recorded = [r[column]["rms_m"] for r in lengths]
        assert all(abs(a - b) <= 0.005 for a, b in zip(example[key], recorded, strict=True))


def test_the_record_says_what_the_page_claims():
    """The claims of the sentences, on the record: the bounds hold through
    the outages, memsnav beats the published filter at every length, the
    smoother beats the forward filter, the filter beats the single-point
    solution by precision, three satellites cost little."""
    drive, walk, derived = RECORD["drive"], RECORD["walk"], RECORD["derived"]
    assert derived["outage_share_percent"]["least"] > 99.0
    assert min(derived["peer_over_forward"] + derived["peer_over_smoothed"]) > 1.0
    for r in drive["lengths"].values():
        assert r["smoothed"]["rms_m"] < r["forward"]["rms_m"]
    forward, spp = walk["forward"], walk["single_point"]
    assert forward["precision_rms_horizontal_m"] < 0.6 * spp["precision_rms_horizontal_m"]
    withheld = RECORD["withheld"]
    assert withheld["3"]["rms_horizontal_m"] < 2 * withheld["4"]["rms_horizontal_m"]
    assert derived["outages_15s"]["standstills"] == 1
