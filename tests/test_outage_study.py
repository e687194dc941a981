"""The outage study: which IMU grade is good enough through which
GNSS outage. Physics first: errors grow with the outage, better grades
drift less, and a short free-inertial outage follows the analytic error
budget (½ b t² from an accelerometer bias, g ω t³ / 6 from a gyro bias)."""

import json
import math
import re

import doc_runs
import matplotlib
import numpy as np
import outage_study_tables
import pytest
from figures import figures
from report_checks import capture_figures, page_problems
from scipy.stats import binom, chi2

import memsnav as mn
from memsnav.cli import main
from memsnav.experiments.outage_study import look_error, looks
from memsnav.study import Requirement, run_study

matplotlib.use("Agg")

G = 9.80665


@pytest.fixture(scope="module")
def study():
    return mn.experiments.outage_study(
        grades=("consumer", "tactical"),
        outage_lengths=(10.0, 40.0),
        visible_satellites=(0, 3),
        runs=4,
        outage_start=40.0,
        seed=3,
        smooth=True,
        threads=2,
    )


def test_errors_grow_with_the_outage_and_shrink_with_the_grade(study):
    s = study.summary(n_visible=0)
    for grade in ("consumer", "tactical"):
        # Every run drifts further in 40 s than in 10 s (same trajectories:
        # the lengths are paired).
        short = study.per_run(grade, 10.0, 0, "horizontal_end")
        long = study.per_run(grade, 40.0, 0, "horizontal_end")
        assert np.all(long > short), (grade, short, long)
        assert s[grade][40.0]["p50_m"] > s[grade][10.0]["p50_m"]
    # Paired draws: the tactical IMU beats the consumer one run by run over
    # 40 s. Over 10 s both stay near the error they entered the outage with
    # (1-2 m, the GNSS noise): the tactical IMU is better in the median.
    tactical = study.per_run("tactical", 40.0, 0, "error_3d_max")
    consumer = study.per_run("consumer", 40.0, 0, "error_3d_max")
    assert np.all(tactical < consumer), (tactical, consumer)
    tactical = study.per_run("tactical", 10.0, 0, "error_3d_max")
    consumer = study.per_run("consumer", 10.0, 0, "error_3d_max")
    assert np.median(tactical) < np.median(consumer), (tactical, consumer)
    # Keeping 3 satellites holds the consumer IMU's error far below the
    # total outage's.
    three = study.summary(n_visible=3)["consumer"][40.0]["p50_m"]
    assert three < 0.3 * s["consumer"][40.0]["p50_m"]


def test_summary_meets_and_smoothed_figures(study):
    s = study.summary()
    figures = s["consumer"][10.0]
    assert set(figures) >= {"p50_m", "p95_m", "max_m", "runs", "horizontal_end", "error_3d_max"}
    values = study.per_run("consumer", 10.0, 0, "horizontal_end")
    assert figures["p50_m"] == pytest.approx(np.median(values))
    assert figures["max_m"] == values.max()
    assert figures["p50_m"] <= figures["p95_m"] <= figures["max_m"]
    # The 3D error is never below its horizontal part, the largest error
    # during the outage never below the one at its end.
    for length in (10.0, 40.0):
        h_end = study.per_run("consumer", length, 0, "horizontal_end")
        assert np.all(study.per_run("consumer", length, 0, "error_3d_end") >= h_end)
        assert np.all(study.per_run("consumer", length, 0, "horizontal_max") >= h_end)
    # A requirement between the two grades' errors separates them.
    tactical = study.per_run("tactical", 40.0, 0, "horizontal_end")
    consumer = study.per_run("consumer", 40.0, 0, "horizontal_end")
    requirement = math.sqrt(np.percentile(tactical, 95) * np.percentile(consumer, 95))
    meets = study.meets(max_error_m=requirement, percentile=95)
    assert 40.0 in meets["tactical"] and 40.0 not in meets["consumer"]
    # The smoother uses the GNSS after the outage: smaller errors inside it.
    smoothed = study.per_run("consumer", 40.0, 0, "error_3d_max", smoothed=True)
    assert np.all(smoothed < study.per_run("consumer", 40.0, 0, "error_3d_max"))
    fig = study.plot(max_error_m=requirement)
    assert len(fig.axes) == 2
    with pytest.raises(ValueError, match="n_visible"):
        study.summary(n_visible=2)
    with pytest.raises(ValueError, match="metric"):
        study.per_run("consumer", 10.0, 0, "rms")
    with pytest.raises(ValueError, match="max_error_m"):
        study.meets(max_error_m=-1.0)


def _fixed_imu(accel_bias, gyro_bias):
    """An IMU with only these biases (and a trace of noise, so the filter's
    process noise is not zero)."""
    zero3, zero33 = np.zeros(3), np.zeros((3, 3))
    acc = mn.AccelerometerModel(accel_bias, zero3, zero33, zero3, noise_std=1e-5)
    gyr = mn.GyroscopeModel(gyro_bias, zero3, zero33, zero33, noise_std=1e-7)
    return mn.ImuModel(acc, gyr)


def _free_inertial(imu, length_s):
    """A total outage from the first second on: nothing about the biases
    was learnt, so they act in full; near-perfect initial state (1 cm,
    1 mm/s GNSS, 0.001° attitude)."""
    return mn.experiments.navigation(
        imus={"imu": imu},
        outage=(1.0, length_s, 0),
        runs=4,
        duration=length_s + 3.0,
        pseudorange_std=0.01,
        pseudorange_rate_std=0.001,
        initial_attitude_std_deg=(1e-3, 1e-3, 1e-3),
        threads=2,
    ).runs_summary["imu"]


def test_short_outage_follows_the_analytic_error_budget():
    t = 20.0  # s since the last GNSS epoch at the end of the outage
    # Accelerometer bias b along body z: a land vehicle stays within a few
    # degrees of level, so it acts on the vertical channel as ½ b t²
    # (Groves eq. 14.2; the vertical channel's instability adds a share
    # 2g/R · t²/12 ≈ 2e-4 at 20 s). Tolerance 2 %: cos of a 10° tilt.
    b = 0.05
    vertical = _free_inertial(_fixed_imu([0.0, 0.0, b], [0.0, 0.0, 0.0]), t)
    expected = 0.5 * b * t**2
    assert np.allclose(vertical["max_vertical_in_outage"], expected, rtol=0.02), (
        vertical["max_vertical_in_outage"],
        expected,
    )
    # Gyro bias ω about the horizontal body axes: the tilt grows as ω t,
    # the horizontal acceleration error as g ω t, the position error as
    # g ω t³ / 6 (Groves eq. 14.5, t well below the Schuler period). The
    # vehicle's turns rotate the tilt's direction in NED, which can only
    # lower the accumulated error: between 80 % and 102 % of the budget.
    w = 1e-3
    horizontal = _free_inertial(
        _fixed_imu([0.0, 0.0, 0.0], [w / math.sqrt(2), w / math.sqrt(2), 0.0]), t
    )
    bound = G * w * t**3 / 6.0
    ratio = horizontal["horizontal_at_outage_end"] / bound
    assert np.all((ratio > 0.8) & (ratio < 1.02)), ratio


def test_bad_arguments_name_themselves():
    with pytest.raises(ValueError, match="outage_lengths"):
        mn.experiments.outage_study(outage_lengths=(10.0, -1.0))
    with pytest.raises(ValueError, match="outage_lengths"):
        mn.experiments.outage_study(outage_lengths=(10.0, 10.0))
    with pytest.raises(ValueError, match="satellites"):
        mn.experiments.outage_study(grades=("tactical",), visible_satellites=(5,), runs=1)
    with pytest.raises(ValueError, match="unknown preset"):
        mn.experiments.outage_study(grades=("gold",), runs=1)


def _order_statistic_interval(values, p, confidence):
    """The equal-tailed distribution-free interval for the p-quantile, from
    scipy's binomial (independently of memsnav's): the k-th smallest run
    lies above the quantile with probability P(Bin(n, p) <= k - 1)."""
    n, tail = len(values), (1.0 - confidence) / 2.0
    v = np.sort(values)
    lower = [r for r in range(1, n + 1) if binom.cdf(r - 1, n, p) <= tail]
    upper = [k for k in range(1, n + 1) if binom.cdf(k - 1, n, p) >= 1.0 - tail]
    return (v[max(lower) - 1] if lower else -math.inf, v[min(upper) - 1] if upper else math.inf)


def test_percentile_intervals_are_the_order_statistics(study):
    for grade in study.grades:
        for length in study.outage_lengths:
            values = study.per_run(grade, length, 0, "horizontal_end")
            # With 4 runs an 80 % interval for the median is [min, max].
            got = study.interval(grade, length, 50.0, n_visible=0, confidence=0.8)
            expected = _order_statistic_interval(values, 0.5, 0.8)
            assert (got["lower"], got["upper"]) == expected == (values.min(), values.max())
    # Four runs cannot bound a p95 at all; 72 runs are needed from above.
    wide = study.interval("consumer", 40.0, 95.0)
    assert wide["upper"] == math.inf and wide["runs_for_upper"] == 72


def _decision(values, max_error_m, error):
    """A cell's verdict from scipy's order statistics (independently of
    memsnav's): its p95's one-sided upper bound at 1 - error within the
    requirement, its lower bound beyond it, or neither."""
    lower, upper = _order_statistic_interval(values, 0.95, 1.0 - 2.0 * error)
    return "meets" if upper <= max_error_m else "fails" if lower > max_error_m else "undecided"


@pytest.mark.slow
def test_study_command_answers_first_with_the_confidence(tmp_path, capsys, monkeypatch):
    """memsnav study prints, then reports first, per grade the longest
    outage that meets the requirement, decided at the confidence, with
    the p95 there, its interval and runs; each follows its criterion (the
    interval within the requirement, every shorter outage's too); what is
    left open is said; the figure's requirement line does not stretch its
    axis."""
    figures = capture_figures(monkeypatch)
    config = tmp_path / "study.toml"
    config.write_text(
        'output = "out"\n[study]\ngrades = ["consumer", "tactical"]\noutage_lengths = [5, 15]\n'
        "visible_satellites = [0, 3]\nruns = 8\nduration = 60\noutage_start = 35\n"
        "smooth = true\n[requirement]\nmax_error_m = 2.0\n"
    )
    assert main(["study", "--config", str(config), "--quiet"]) == 0
    printed = capsys.readouterr().out.splitlines()
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert figures.keys() == {"outage_study"} and not any(figures.values())
    assert printed[0].startswith(
        "Longest outage with the horizontal error at the outage end within 2 m in 95 % of runs, "
        "decided at 95 % confidence"
    )
    assert printed[1].split() == ["0", "satellites", "kept", "3", "satellites", "kept"]
    result = mn.experiments.outage_study(
        grades=("consumer", "tactical"),
        outage_lengths=(5.0, 15.0),
        visible_satellites=(0, 3),
        runs=8,
        duration=60.0,
        outage_start=35.0,
    )
    undecided = 0
    for row, grade in zip(printed[2:4], ("consumer", "tactical"), strict=True):
        assert row.split()[0] == grade
        # Each printed p95 on the side of the requirement its value is on.
        shown_p95 = [float(v) for v in re.findall(r"p95 (\S+) m", row)]
        answers = [summary["answer"][str(n)][grade]["percentile_m"] for n in (0, 3)]
        assert [v <= 2.0 for v in shown_p95] == [v <= 2.0 for v in answers], row
        for n in (0, 3):
            entry = summary["answer"][str(n)][grade]
            verdicts = {
                length: _decision(result.per_run(grade, length, n, "horizontal_end"), 2.0, 0.05)
                for length in (5.0, 15.0)
            }
            longest = None
            for length in (5.0, 15.0):
                if verdicts[length] != "meets":
                    break
                longest = length
            assert entry["longest_met_s"] == longest, (grade, n, verdicts)
            first_open = next((v for v in verdicts.values() if v != "meets"), "fails")
            assert entry["decided"] == (first_open == "fails"), (grade, n, verdicts)
            undecided += not entry["decided"]
            shown = entry["length_s"]
            values = result.per_run(grade, shown, n, "horizontal_end")
            assert entry["percentile_m"] == pytest.approx(np.percentile(values, 95.0))
            lower, upper = _order_statistic_interval(values, 0.95, 0.90)
            assert entry["interval_m"][0] == pytest.approx(lower)
            assert (entry["interval_m"][1] is None) == (upper == math.inf)  # JSON: inf is null
            assert entry["runs"] == 8
    # 8 runs cannot bound a p95 from above: nothing meets with confidence.
    assert undecided > 0 and "give [study] max_runs" in printed[4]
    html = (tmp_path / "out" / "report.html").read_text()
    assert html.index("The answer") < html.index("Error vs outage length")
    assert "Runs a percentile may hide" in html
    assert not page_problems(html), page_problems(html)
    assert printed[5].startswith("report: ")
    config.write_text('[study]\ngrades = ["tactical"]\nrunz = 2\n')
    assert main(["study", "--config", str(config), "--quiet"]) == 1


ADAPTIVE = dict(
    grades=("consumer", "tactical"),
    outage_lengths=(10.0, 40.0),
    visible_satellites=(0, 3),
    outage_start=40.0,
    seed=3,
    max_error_m=3.0,
)
"""A small adaptive study: the consumer grade fails the longer outage at
once, the tactical one needs more runs to be decided."""


def _wrong_decision_probability(looks, error):
    """The probability that a cell whose p95 sits at the requirement is
    wrongly decided at some look (meets, fails), each look's bounds at
    one-sided ``error``, a decision stopping the cell: scipy's binomial law
    of the count of runs within the requirement carried look to look, each
    look's decisions read off ``_decision`` itself on runs made up to hold
    that count (independently of memsnav's recursion)."""
    open_ = np.array([1.0])
    wrong = {"meets": 0.0, "fails": 0.0}
    previous = 0
    for n in looks:
        step = binom.pmf(np.arange(n - previous + 1), n - previous, 0.95)
        open_ = np.convolve(open_, step)
        for within in range(n + 1):
            values = np.r_[np.full(within, 1.0), np.full(n - within, 5.0)]
            verdict = _decision(values, 3.0, error)
            if verdict != "undecided":
                wrong[verdict] += open_[within]
                open_[within] = 0.0
        previous = n
    return wrong["meets"], wrong["fails"]


def test_the_looks_share_the_error_exactly():
    """Each look's bounds err at the largest level that keeps a decision,
    whichever look makes it, wrong at most 5 % of the time, counted
    exactly (scipy, above): more than Bonferroni's 0.05 / 3, which the
    shared runs make conservative."""
    schedule = looks(8, 160)
    error = look_error(schedule)
    meets, fails = _wrong_decision_probability(schedule, error)
    assert max(meets, fails) <= 0.05
    assert meets == pytest.approx(mn.sequential_error(schedule, 0.95, error)[0], abs=1e-12)
    assert fails == pytest.approx(mn.sequential_error(schedule, 0.95, error)[1], abs=1e-12)
    assert max(_wrong_decision_probability(schedule, 0.05 / 3)) < 0.03
    assert error > 2 * 0.05 / 3
    # The largest such level: a little more and one side errs too often.
    assert max(_wrong_decision_probability(schedule, error * 1.001)) > 0.05


def test_adaptive_study_decides_every_needed_cell_reproducibly():
    """Looks of 8, then from the runs that can show a p95 met at the
    schedule's exact per-look error (above), doubling to 160: every
    decision is the one scipy's order statistics give at that error; cells
    stop when decided; longer outages after a failed one are not run on;
    the runs a cell shares with a fixed 8-run study are the same numbers,
    bit for bit, and so are one and two threads."""
    study = mn.experiments.outage_study(**ADAPTIVE, runs=8, max_runs=160, threads=2)
    assert study.config["looks"] == [8, 80, 160]
    error = study.config["look_error"]
    assert 0.95**80 <= error < 0.95**59
    assert max(_wrong_decision_probability([8, 80, 160], error)) <= 0.05
    fixed = mn.experiments.outage_study(**ADAPTIVE, runs=8, threads=1)
    assert fixed.config["looks"] == [8]
    decided_early = 0
    for (grade, length, n), cell in study.cells.items():
        values = study.per_run(grade, length, n, "horizontal_end")
        assert cell.runs in (8, 80, 160), cell
        assert np.array_equal(values[:8], fixed.per_run(grade, length, n, "horizontal_end"))
        if cell.decision == "not needed":
            shorter = [study.cell(grade, s, n) for s in (10.0, 40.0) if s < length]
            assert any(c.decision == "fails" for c in shorter), cell
            continue
        assert cell.decision == _decision(values, 3.0, error), cell
        if cell.decision == "undecided":
            assert cell.runs == 160, cell
        else:
            decided_early += cell.runs < 160
    assert decided_early > 0
    # The answer: per count and grade the longest outage met with every
    # shorter one, shown at that cell when settled, else at the open one.
    from memsnav.study import Requirement, answer

    table = answer(study, Requirement(3.0, 95.0, "horizontal_end"))
    for n in (0, 3):
        for grade in ("consumer", "tactical"):
            lengths = (10.0, 40.0)
            verdicts = [study.cell(grade, length, n).decision for length in lengths]
            longest = None
            for length, verdict in zip(lengths, verdicts, strict=True):
                if verdict != "meets":
                    break
                longest = length
            first_open = next(
                ((L, v) for L, v in zip(lengths, verdicts, strict=True) if v != "meets"), None
            )
            settled = first_open is None or first_open[1] == "fails"
            entry = table[n][grade]
            assert entry["longest_met_s"] == longest, (grade, n, verdicts)
            assert entry["decided"] == settled, (grade, n, verdicts)
            shown = (longest or lengths[0]) if settled else first_open[0]
            assert entry["length_s"] == shown, (grade, n, verdicts)
    two = mn.experiments.outage_study(**ADAPTIVE, runs=8, max_runs=160, threads=1)
    for key, cell in study.cells.items():
        assert np.array_equal(
            cell.forward["horizontal_end"], two.cells[key].forward["horizontal_end"]
        )
        assert cell.decision == two.cells[key].decision
    assert "runs" in repr(study.cell("tactical", 40.0, 0))
    with pytest.raises(ValueError, match="max_runs"):
        mn.experiments.outage_study(**ADAPTIVE, runs=8, max_runs=4)
    with pytest.raises(ValueError, match="max_runs"):
        mn.experiments.outage_study(grades=("tactical",), runs=8, max_runs=16)
    with pytest.raises(ValueError, match="percentile"):
        mn.experiments.outage_study(**ADAPTIVE, runs=8, max_runs=16, percentile=100.0)
    with pytest.raises(ValueError, match="cell"):
        study.cell("tactical", 20.0, 0)


def test_study_on_galileo_and_beidou_from_the_configuration(tmp_path):
    """[study] systems, n_satellites and inter_system_bias reach the runs:
    the summary records them, and its numbers are those of the API with
    the same keywords (which differ from GPS alone's)."""
    config = tmp_path / "study.toml"
    config.write_text(
        'output = "out"\n[study]\ngrades = ["tactical"]\noutage_lengths = [10]\n'
        "visible_satellites = [3]\nruns = 3\nduration = 50\noutage_start = 35\n"
        'systems = ["G", "E", "C"]\nn_satellites = 20\ninter_system_bias = [3.0, -25.0]\n'
        "[requirement]\nmax_error_m = 100.0\n"
    )
    assert main(["study", "--config", str(config), "--quiet"]) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["config"]["systems"] == ["G", "E", "C"]
    assert summary["config"]["inter_system_bias"] == [3.0, -25.0]
    kw = dict(
        grades=("tactical",),
        outage_lengths=(10.0,),
        visible_satellites=(3,),
        runs=3,
        duration=50.0,
        outage_start=35.0,
    )
    several = mn.experiments.outage_study(
        **kw, systems=("G", "E", "C"), n_satellites=20, inter_system_bias=(3.0, -25.0)
    )
    gps = mn.experiments.outage_study(**kw)
    end = several.per_run("tactical", 10.0, 3, "horizontal_end")
    assert summary["answer"]["3"]["tactical"]["percentile_m"] == pytest.approx(
        np.percentile(end, 95.0)
    )
    assert not np.array_equal(end, gps.per_run("tactical", 10.0, 3, "horizontal_end"))
    bad = tmp_path / "bad.toml"
    bad.write_text('output = "out2"\n[study]\nsystems = ["G", "X"]\n')
    assert main(["study", "--config", str(bad), "--quiet"]) != 0


CARRIER_STUDY = doc_runs.CARRIER_STUDY
_aided, _end = doc_runs.carrier_aided, doc_runs.carrier_end


@pytest.fixture(scope="module")
def carrier_studies():
    return doc_runs.carrier_study_sets()


def test_carrier_phase_sharpens_the_aided_solution_and_the_outage_start(carrier_studies):
    """Time-differenced carrier phase (3 mm) pins the velocity between
    epochs: the aided position error shrinks, the filter stays consistent
    (NEES of 9 dof per run inside the chi-square band of the runs), and the
    better velocity at the outage's start shrinks the error at its end,
    with 3 satellites kept too, where too few carrier changes are left
    for the filter to use them (5 needed)."""
    code, carrier = carrier_studies["code"], carrier_studies["carrier"]
    assert code["config"]["carrier_phase_std"] == 0.0
    assert carrier["config"]["carrier_phase_std"] == 0.003
    assert carrier["config"]["cycle_slip_probability"] == 0.0
    band = chi2.ppf([0.005, 0.995], 9 * CARRIER_STUDY["runs"]) / (9 * CARRIER_STUDY["runs"])
    code_error, _ = _aided(code)
    for name in ("carrier", "slips"):
        error, nees = _aided(carrier_studies[name])
        assert error < 0.9 * code_error, (name, error, code_error)
        assert band[0] < nees.mean() < band[1], (name, nees.mean(), band)
        # Silent slips of one satellite in a hundred per epoch: found or
        # excluded, never a divergence.
        for n in (0, 3):
            runs = carrier_studies[name][n].runs_summary["tactical"]
            assert not np.any(runs["diverged"]), (name, n)
    for n in (0, 3):
        with_carrier = np.median(_end(carrier, "tactical", n))
        without = np.median(_end(code, "tactical", n))
        assert with_carrier < 0.8 * without, (n, with_carrier, without)
    # The slips cost the carrier's changes where they are found, which the
    # filter records as rejected.
    rejected = {
        name: carrier_studies[name][0].runs_summary["tactical"]["rejected"].sum()
        for name in ("code", "carrier", "slips")
    }
    assert rejected["code"] < rejected["carrier"] < rejected["slips"], rejected


def test_carrier_phase_helps_the_consumer_grade_too(carrier_studies):
    """The consumer IMU's tilt errors make the acceleration error's part of
    a carrier change (½ δa Δt², coupling/carrier.rs) several times the
    phase's noise: modelled, its filter with carrier phase stays consistent
    (NEES per dof in the band; without the term it was above 5) and its
    aided error shrinks as the tactical grade's does, slips or not."""
    band = chi2.ppf([0.005, 0.995], 9 * CARRIER_STUDY["runs"]) / (9 * CARRIER_STUDY["runs"])
    code_error, _ = _aided(carrier_studies["code"], "consumer")
    for name in ("carrier", "slips"):
        error, nees = _aided(carrier_studies[name], "consumer")
        assert band[0] < nees.mean() < band[1], (name, nees.mean(), band)
        assert error < 0.9 * code_error, (name, error, code_error)


def test_the_carrier_phase_figures_are_the_record(carrier_studies):
    """docs/results/outage-study.md shows the carrier comparison per grade
    from its record: recomputed here on the same sets."""
    fresh = doc_runs.carrier_phase_figures(carrier_studies)
    recorded = figures("carrier_phase_comparison")
    assert fresh.keys() == recorded.keys()
    for grade, values in fresh.items():
        for key, value in values.items():
            assert abs(value - recorded[grade][key]) <= 1e-9 * max(1.0, value), (grade, key)


def test_carrier_settings_are_checked_and_reach_the_study_configuration(tmp_path):
    with pytest.raises(ValueError, match="carrier_phase_std"):
        mn.experiments.outage_study(grades=("tactical",), runs=1, carrier_phase_std=-0.003)
    with pytest.raises(ValueError, match="carrier_phase_std"):
        mn.experiments.navigation(runs=1, duration=5.0, carrier_phase_std="3 mm")
    with pytest.raises(ValueError, match="cycle_slip_probability"):
        mn.experiments.partial_outage(runs=1, carrier_phase_std=0.003, cycle_slip_probability=1.5)
    from memsnav.study import read_config

    config = tmp_path / "study.toml"
    config.write_text("[study]\ncarrier_phase_std = 0.003\ncycle_slip_probability = 0.01\n")
    study = read_config(config)["study"]
    assert study == {"carrier_phase_std": 0.003, "cycle_slip_probability": 0.01}
    config.write_text("[study]\ncycle_slip_probability = 2\n")
    with pytest.raises(ValueError, match="cycle_slip_probability"):
        read_config(config)


def test_carrier_phase_leaves_the_loose_filter_alone():
    """The carrier is drawn on a side stream and only the tight filter
    reads it: the loosely coupled scenario is the same bit for bit, the
    tight ones are not."""
    kw = dict(
        imus=("tactical",),
        runs=3,
        duration=80.0,
        outage_start=40.0,
        outage_length=20.0,
        satellites=[3],
        keep_runs=True,
    )
    code = mn.experiments.partial_outage(**kw)
    carrier = mn.experiments.partial_outage(**kw, carrier_phase_std=0.003)
    assert carrier.config["carrier_phase_std"] == 0.003
    for label in code.scenarios:
        same = np.array_equal(
            code.scenarios[label].position_error["tactical"],
            carrier.scenarios[label].position_error["tactical"],
        )
        assert same == (code.coupling[label] == "loose"), label


@pytest.mark.slow
def test_the_land_vehicle_study_today_is_its_record(tmp_path):
    """examples/study_land_vehicle.toml run again (~50 s on 2 cores): every
    cell's runs, decision, interval and percentiles are the record's
    (docs/data/outage_study.json, which docs/results/outage-study.md's
    sentences show) exactly: the draws are seeded per (seed, cell, run)."""
    study = run_study(outage_study_tables.CONFIG, output=tmp_path, progress=False)
    requirement = Requirement.of(study.summary["requirement"])
    fresh = outage_study_tables.cell_figures(study.result, requirement)
    assert fresh == figures("outage_study")["cells"], (
        "rerun python docs/outage_study_tables.py --write if this is meant"
    )
