"""The paper comparison's figures, still read from its page: its prose
against its study tables, and the tables against a fresh run within the
rounding they are quoted with. docs/paper_comparison_study.py keeps no
record yet (docs/figures.py); the other figures these tests used to read
from sentences now come from records (tests/test_doc_runs.py and the
tests named in docs/decisions/0013-figures-from-records.md)."""

import re
from pathlib import Path

import numpy as np
import paper_comparison_study
import pytest
from quoted import quoted_figures, rounds_to

ROOT = Path(__file__).resolve().parent.parent


def _paper_study_rows() -> dict[tuple[str, str], tuple[float, ...]]:
    """docs/results/paper-comparison.md's study table (`python
    docs/paper_comparison_study.py 20`): RMS 0-150 s, RMS 150-600 s,
    outage max, NEES/dof by (setting, IMU); a blank setting cell repeats
    the one above."""
    text = (ROOT / "docs" / "results" / "paper-comparison.md").read_text()
    table = text[text.index("| setting | IMU |") :].split("\n\n", 1)[0]
    rows, setting = {}, ""
    for line in table.splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        setting = cells[0] or setting
        rows[(setting, cells[1])] = tuple(float(c) for c in cells[2:])
    return rows


def _paper_budget_rows(header: str) -> dict[str, str]:
    """The paper-comparison table that starts with ``header``: first cell →
    second."""
    text = (ROOT / "docs" / "results" / "paper-comparison.md").read_text()
    table = text[text.index(header) :].split("\n\n", 1)[0]
    cells = [[c.strip() for c in line.strip().strip("|").split("|")] for line in table.splitlines()]
    return {row[0]: row[1] for row in cells[2:]}


def test_paper_comparison_prose_reads_its_study_tables():
    """The defaults table, the claims' bullets and the "which configuration"
    table of docs/results/paper-comparison.md quote its study tables (no run: the
    slow test below reruns the tables); each quote agrees."""
    rows = _paper_study_rows()
    defaults = "defaults (ranges + rates, 1°/1°/5°)"
    text = (ROOT / "docs" / "results" / "paper-comparison.md").read_text()
    for imu in ("ins", "mems", "calibrated_mems"):
        numbers = r" \| ([\d.]+)" * 4
        row = re.search(rf"^\| {imu}{numbers} \|$", text, re.M)
        assert tuple(float(v) for v in row.groups()) == rows[(defaults, imu)], imu

    def study(setting: str, imu: str, column: int) -> float:
        return rows[(setting, imu)][column]

    (nees,) = quoted_figures(
        "docs/results/paper-comparison.md", r"raw MEMS's NEES/dof of ([\d.]+) is its tilt"
    )
    assert rounds_to(nees, study(defaults, "mems", 3))
    only = "pseudoranges only"
    quoted = quoted_figures(
        "docs/results/paper-comparison.md",
        r"calibration then helps all along, ([\d.]+) → ([\d.]+) m in the first 150 s \((\d+) %\) "
        r"and ([\d.]+) → ([\d.]+) m after \((\d+) %\)",
    )
    early = (study(only, "mems", 0), study(only, "calibrated_mems", 0))
    late = (study(only, "mems", 1), study(only, "calibrated_mems", 1))
    assert quoted[:2] == early and quoted[3:5] == late
    assert rounds_to(quoted[2], 100 * (1 - early[1] / early[0]))
    assert rounds_to(quoted[5], 100 * (1 - late[1] / late[0]))
    above = quoted_figures(
        "docs/results/paper-comparison.md",
        r"stays above the INS \(([\d.]+) vs ([\d.]+) m after 150 s\)",
    )
    assert above == (study(only, "calibrated_mems", 1), study(only, "ins", 1))
    noisy = "rate noise 1 m/s"
    quoted = quoted_figures(
        "docs/results/paper-comparison.md",
        r"\(([\d.]+) → ([\d.]+) m early, ([\d.]+) → ([\d.]+) m after\)",
    )
    assert quoted == (
        study(noisy, "mems", 0),
        study(noisy, "calibrated_mems", 0),
        study(noisy, "mems", 1),
        study(noisy, "calibrated_mems", 1),
    )
    plain = "no absorption of unmodelled errors"
    quoted = quoted_figures(
        "docs/results/paper-comparison.md",
        r"first 150 s ([\d.]+) m raw vs ([\d.]+) m calibrated vs ([\d.]+) m INS",
    )
    assert quoted == tuple(study(plain, imu, 0) for imu in ("mems", "calibrated_mems", "ins"))
    late_rms, late_nees = quoted_figures(
        "docs/results/paper-comparison.md", r"diverges \(RMS (\d+) m after 150 s, NEES/dof (\d+)\)"
    )
    assert rounds_to(late_rms, study(plain, "mems", 1)) and rounds_to(
        late_nees, study(plain, "mems", 3)
    )
    # The "which configuration reproduces which claim" table.
    claims = " ".join(text[text.index("| claim | defaults |") :].split("\n\n", 1)[0].split())
    for setting, aided in ((defaults, "yes"), (only, "yes, narrowly")):
        pair = (study(setting, "calibrated_mems", 1), study(setting, "ins", 1))
        assert f"{aided} ({pair[0]:.2f} vs {pair[1]:.2f} m)" in claims, setting
        drift = (study(setting, "mems", 2), study(setting, "ins", 2))
        assert f"yes ({drift[0]:.1f} vs {drift[1]:.1f} m)" in claims, setting
        helped = (study(setting, "mems", 2), study(setting, "calibrated_mems", 2))
        assert f"no ({helped[0]:.1f} → {helped[1]:.1f} m)" in claims, setting
    gain = [100 * (1 - study(only, "calibrated_mems", k) / study(only, "mems", k)) for k in (0, 1)]
    assert f"partly: {gain[0]:.0f} % early, {gain[1]:.0f} % after" in claims
    first = (study(plain, "mems", 0), study(plain, "calibrated_mems", 0))
    assert f"yes ({first[0]:.2f} vs {first[1]:.2f} m)" in claims
    # The outage budget: the simulation against the analytic sum.
    simulated = _paper_budget_rows("| raw MEMS variant | outage max [m] |")
    analytic = _paper_budget_rows("| raw MEMS error term (paper-mems sigma) |")
    measured, budget = quoted_figures(
        "docs/results/paper-comparison.md", r"The measured (\d+) m is the analytic (\d+) m"
    )
    assert rounds_to(measured, float(simulated["raw MEMS (all terms)"]))
    assert rounds_to(budget, float(analytic["all, in quadrature"]))
    calibrated, plain_calibrated = quoted_figures(
        "docs/results/paper-comparison.md",
        r"hence ([\d.]+) m for the calibrated MEMS, and ([\d.]+) m when its filter is tuned",
    )
    assert calibrated == study(defaults, "calibrated_mems", 2)
    assert plain_calibrated == study(plain, "calibrated_mems", 2)
    noise_only, ins = quoted_figures(
        "docs/results/paper-comparison.md",
        r"noise-only drift \(([\d.]+) m\) is the INS's \(([\d.]+) m\)",
    )
    assert noise_only == float(simulated["noise only"]) and ins == study(defaults, "ins", 2)


#: The study's settings rerun by the test below: all but the 23-state
#: filters (the costliest, 25 s; the page says only that they change
#: nothing), to keep the added test time small.
RERUN_SETTINGS = [s for s in paper_comparison_study.SETTINGS if not s.startswith("23 states")]


@pytest.mark.slow
@pytest.mark.parametrize("setting", RERUN_SETTINGS)
def test_paper_comparison_study_table_is_a_fresh_run(setting):
    """Each setting's rows of docs/results/paper-comparison.md's study table
    (20 runs, seed 0: deterministic) are what the study script computes
    today, within the rounding they are quoted with (~5-10 s a setting)."""
    rows, nominal = paper_comparison_study.setting_rows(
        paper_comparison_study.SETTINGS[setting], runs=20, threads=None
    )
    quoted = _paper_study_rows()
    for imu, fresh in rows.items():
        page = quoted[(setting, imu)]
        assert all(rounds_to(q, v) for q, v in zip(page, fresh, strict=True)), (imu, page, fresh)
    if setting.startswith("defaults"):
        # "window RMS 0-10 s / 10-30 s / 30-60 s: 3.0 / 1.7 / 1.3 m for all
        # three IMUs" (1 Hz errors: index = second).
        windows = quoted_figures(
            "docs/results/paper-comparison.md", r"30-60 s: ([\d.]+) / ([\d.]+) / ([\d.]+) m"
        )
        for imu in nominal.imus:
            error = nominal.position_error[imu]
            fresh = [np.sqrt(np.mean(error[:, a:b] ** 2)) for a, b in ((0, 10), (10, 30), (30, 60))]
            assert all(rounds_to(q, v) for q, v in zip(windows, fresh, strict=True)), (imu, fresh)


@pytest.mark.slow
def test_paper_comparison_outage_budget_is_a_fresh_run():
    """The outage budget of docs/results/paper-comparison.md, analytic (20
    trajectories) and by simulation (20 runs), from the study script."""
    analytic = paper_comparison_study.budget_analytic_rows(20)
    page = _paper_budget_rows("| raw MEMS error term (paper-mems sigma) |")
    for label, text in page.items():
        if label == "all, in quadrature":
            assert rounds_to(float(text), np.sqrt(sum(v**2 for v in analytic.values())))
        elif text.startswith("<"):  # "accel scale factor 1e-5, nonlinearity 1e-5 /g"
            assert analytic["accel scale factor"] < 0.01 and analytic["accel nonlinearity"] < 0.01
        else:
            (term,) = [k for k in analytic if label.startswith(k)]
            assert rounds_to(float(text), analytic[term]), (label, analytic[term])
    simulated = paper_comparison_study.budget_by_simulation_rows(20, None)
    page = _paper_budget_rows("| raw MEMS variant | outage max [m] |")
    assert page.keys() == simulated.keys()
    for variant, (largest, _) in simulated.items():
        assert rounds_to(float(page[variant]), largest), (variant, largest)
