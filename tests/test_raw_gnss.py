"""Raw GNSS from anywhere, strictly: ``GnssMeasurements`` from
padded arrays and from long tables (CSV, dict, DataFrame), one strict
converter for every entry point (unknown keys name what was meant, NaN
refused naming the slot), the Android GnssLogger reader checked against
the same phone's RINEX file, and the pixel4-2021 table through
``solve_fix`` scored by its survey truth."""

from __future__ import annotations

import csv
from pathlib import Path

import doc_runs
import numpy as np
import pytest
from figures import figures
from shared_data import shared_data

import memsnav as mn

DATA = Path(__file__).parent / "data"
KEYS = doc_runs.GNSS_ARRAY_KEYS


@pytest.fixture(scope="module")
def sim():
    traj = mn.Trajectory.random(duration=60.0, seed=3)
    gnss = mn.simulate_gnss(
        traj.time, traj.position_ecef, traj.velocity_ecef, mn.Constellation.walker(), seed=4
    )
    return traj, gnss


def arrays(gnss) -> dict[str, np.ndarray]:
    return {k: getattr(gnss, k) for k in KEYS}


def test_constructed_from_arrays_equals_the_original(sim):
    _, gnss = sim
    built = mn.GnssMeasurements(**arrays(gnss), start_gps_time=float(gnss.gps_time[0]))
    for k in KEYS:
        np.testing.assert_array_equal(getattr(built, k), getattr(gnss, k))
    np.testing.assert_array_equal(built.gps_time, gnss.gps_time)
    # solve_fix takes the dict itself, with the same fixes.
    a, b = mn.solve_fix(gnss), mn.solve_fix(arrays(gnss))
    np.testing.assert_array_equal(a.position_ecef, b.position_ecef)


def test_misspelled_and_stray_keys_are_errors(sim, drive_300s):
    _, gnss = sim
    d = arrays(gnss)
    d["pseudorange_rates"] = d.pop("pseudorange_rate")
    with pytest.raises(
        ValueError, match=r'"pseudorange_rates" \(did you mean "pseudorange_rate"\?\)'
    ):
        mn.solve_fix(d)
    stray = {k: v for k, v in arrays(gnss).items() if k != "pseudorange_rate"}
    with pytest.raises(ValueError, match="pseudorange_rate_std given without pseudorange_rate"):
        mn.solve_fix(stray)
    # The same converter in the filters and navigate_log.
    traj, g, imu, f, w = drive_300s
    d = arrays(g)
    d["pseudorange_rates"] = d.pop("pseudorange_rate")
    with pytest.raises(ValueError, match="did you mean"):
        mn.TightlyCoupledFilter(imu).run(traj.time, f, w, d, initial_attitude=traj.attitude[0])
    with pytest.raises(ValueError, match="did you mean"):
        mn.navigate_log(traj.time, f, w, d)
    fixes = {"time": [0.0], "position_ecef": [[6.4e6, 0, 0]], "position_covarience": [np.eye(3)]}
    with pytest.raises(ValueError, match='did you mean "position_covariance"'):
        mn.LooselyCoupledFilter(imu).run(traj.time, f, w, fixes)
    start = {"position_ecef": traj.position_ecef[0], "velocity": traj.velocity_ecef[0]}
    with pytest.raises(ValueError, match='did you mean "velocity_ecef"'):
        mn.TightlyCoupledFilter(imu).run(traj.time, f, w, g, initial_state=start)


def test_the_misspelled_rate_key_used_to_cost_the_doppler(drive_300s):
    """What the strict keys prevent: without its rates the tight filter's
    position RMS on this drive rises by more than half (the record
    pseudorange_rates_value)."""
    traj, g, imu, f, w = drive_300s

    def rms(gnss) -> float:
        sol = mn.TightlyCoupledFilter(imu).run(
            traj.time, f, w, gnss, initial_attitude=traj.attitude[0]
        )
        return float(np.sqrt(np.mean(np.sum((sol.position_ecef - traj.position_ecef) ** 2, 1))))

    with_rates = rms(arrays(g))
    without = rms({k: v for k, v in arrays(g).items() if not k.startswith("pseudorange_rate")})
    assert with_rates < 2.0 < 3.0 < without
    # docs/reference/robustness.md quotes both from the record.
    recorded = figures("pseudorange_rates_value")
    assert abs(with_rates - recorded["with_rates_rms_m"]) <= 1e-9, with_rates
    assert abs(without - recorded["without_rates_rms_m"]) <= 1e-9, without


def test_nan_is_refused_naming_the_slot(sim):
    _, gnss = sim
    d = arrays(gnss)
    d["pseudorange"] = d["pseudorange"].copy()
    d["pseudorange"][2, 1] = np.nan
    with pytest.raises(ValueError, match=r"gnss: \[2, 1\] .*pseudorange = NaN"):
        mn.GnssMeasurements(**d)
    d = arrays(gnss)
    d["satellite_position_ecef"] = d["satellite_position_ecef"].copy()
    d["satellite_position_ecef"][0, 0, 2] = np.inf
    with pytest.raises(ValueError, match=r"\[0, 0\].*satellite position"):
        mn.solve_fix(d)
    d = arrays(gnss)
    d["pseudorange_rate_std"] = d["pseudorange_rate_std"].copy()
    d["pseudorange_rate_std"][1, 0] = np.nan
    with pytest.raises(ValueError, match=r"\[1, 0\].*pseudorange_rate_std = NaN"):
        mn.solve_fix(d)
    # A NaN rate is "no rate there", its σ dropped with it.
    d = arrays(gnss)
    d["pseudorange_rate"] = d["pseudorange_rate"].copy()
    d["pseudorange_rate"][1, 0] = np.nan
    built = mn.GnssMeasurements(**d)
    assert np.isnan(built.pseudorange_rate_std[1, 0])
    d["sat_id"] = d["sat_id"].astype(float)
    d["sat_id"][0, 0] = np.nan
    with pytest.raises(ValueError, match=r"\[0, 0\].*not a satellite number"):
        mn.GnssMeasurements(**d)


def long_table(gnss) -> dict[str, np.ndarray]:
    k, j = np.nonzero(gnss.sat_id >= 0)
    xyz = "xyz"
    return {
        "time_s": gnss.time[k],
        "gps_time_s": gnss.gps_time[k],
        "sat_id": gnss.sat_id[k, j],
        **{
            f"sat_position_ecef_{a}_m": gnss.satellite_position_ecef[k, j, i]
            for i, a in enumerate(xyz)
        },
        **{
            f"sat_velocity_ecef_{a}_m_s": gnss.satellite_velocity_ecef[k, j, i]
            for i, a in enumerate(xyz)
        },
        "pseudorange_m": gnss.pseudorange[k, j],
        "pseudorange_rate_m_s": gnss.pseudorange_rate[k, j],
        "pseudorange_std_m": gnss.pseudorange_std[k, j],
        "pseudorange_rate_std_m_s": gnss.pseudorange_rate_std[k, j],
    }


def test_long_tables_from_dict_csv_and_dataframes(sim, tmp_path):
    _, gnss = sim
    table = long_table(gnss)
    for built in [mn.GnssMeasurements.from_table(table)]:
        for k in KEYS:
            np.testing.assert_array_equal(getattr(built, k), getattr(gnss, k))
        np.testing.assert_array_equal(built.gps_time, gnss.gps_time)
    path = tmp_path / "gnss.csv"
    names = list(table)
    rows = np.column_stack([table[n] for n in names])
    np.savetxt(path, rows, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    from_csv = mn.GnssMeasurements.from_table(path)
    np.testing.assert_array_equal(from_csv.pseudorange, gnss.pseudorange)
    for module in ("pandas", "polars"):
        try:
            lib = __import__(module)
        except ImportError:
            continue
        frame = lib.DataFrame(table)
        np.testing.assert_array_equal(
            mn.GnssMeasurements.from_table(frame).pseudorange, gnss.pseudorange
        )
    bad = dict(table)
    bad["pseudorange_rates_m_s"] = bad.pop("pseudorange_rate_m_s")
    with pytest.raises(ValueError, match='did you mean "pseudorange_rate_m_s"'):
        mn.GnssMeasurements.from_table(bad)
    bad = dict(table, pseudorange_m=table["pseudorange_m"].copy())
    bad["pseudorange_m"][5] = np.nan
    with pytest.raises(ValueError, match="table: row 5: pseudorange = NaN"):
        mn.GnssMeasurements.from_table(bad)


def test_the_simulate_gnss_csv_reads_back(tmp_path):
    from memsnav.simulate import simulate

    files = simulate(tmp_path, duration=20.0, seed=1)
    g = mn.GnssMeasurements.from_table(files.gnss, pseudorange_std=2.0)
    tracked = g.sat_id >= 0
    assert len(g) > 0 and np.all(np.isfinite(g.pseudorange_rate[tracked]))
    assert np.all(g.pseudorange_std[tracked] == 2.0)
    assert mn.solve_fix(g).valid.all()


def test_pixel4_table_through_solve_fix_scored_by_its_survey_truth():
    folder = shared_data("gnss-products/pixel4-2021")
    with open(folder / "Pixel4_derived.csv") as f:
        rows = list(csv.DictReader(f))

    def col(name: str) -> np.ndarray:
        return np.array([float(r[name]) for r in rows])

    signals = sorted({r["signalType"] for r in rows})
    # One id per satellite and signal (a satellite's L1 and L5 are two rows).
    sat = np.array([100 * signals.index(r["signalType"]) for r in rows]) + col("svid")
    time = col("millisSinceGpsEpoch") / 1000.0
    rho = col("rawPrM") + col("satClkBiasM") - col("isrbM") - col("ionoDelayM") - col("tropoDelayM")
    table = {
        "time_s": time,
        "sat_id": sat,
        "pseudorange_m": rho,
        "pseudorange_std_m": col("rawPrUncM"),
        **{f"sat_position_ecef_{a}_m": col(f"{a}SatPosM") for a in "xyz"},
        **{f"sat_velocity_ecef_{a}_m_s": col(f"{a}SatVelMps") for a in "xyz"},
    }
    order = np.lexsort((sat, time))
    gnss = mn.GnssMeasurements.from_table({k: v[order] for k, v in table.items()})
    fix = mn.solve_fix(gnss)
    assert fix.valid.all()
    with open(folder / "Pixel4_ground_truth.csv") as f:
        truth = list(csv.DictReader(f))
    t_truth = np.array([float(r["millisSinceGpsEpoch"]) / 1000.0 for r in truth])
    errors = []
    for k, t in enumerate(fix.time):
        r = truth[int(np.argmin(abs(t_truth - t)))]
        lla = [
            np.radians(float(r["latDeg"])),
            np.radians(float(r["lngDeg"])),
            float(r["heightAboveWgs84EllipsoidM"]),
        ]
        errors.append(mn.ecef_to_ned(fix.position_ecef[k], mn.geodetic_to_ecef(lla)))
    e = np.array(errors)
    horizontal = np.sqrt(np.mean(np.sum(e[:, :2] ** 2, 1)))
    assert horizontal < 4.0, horizontal  # measured 2.09 m: a phone
    # The truth's heights sit 65.6 m above every fix (the fixes put the
    # phone at -32 m, the geoid's height there: at sea level); the vertical
    # scatter about that offset is a phone's.
    assert 60.0 < np.mean(e[:, 2]) < 70.0 and np.std(e[:, 2]) < 5.0


def test_gnsslogger_excerpt():
    log = mn.read_gnsslogger(DATA / "android-gnsslogger" / "pixel6_excerpt.txt")
    obs = log.observations
    assert len(obs) == 2
    assert obs.observation_types["G"] == ["C1C", "L1C", "D1C", "S1C", "C5Q", "L5Q", "D5Q", "S5Q"]
    # TimeNanos − (FullBiasNanos + BiasNanos) of the first epoch, GPS s.
    assert obs.time[0] == pytest.approx(1383435812.000273353, abs=1e-6)
    # G04's first L1 record by hand: tRx mod week − ReceivedSvTimeNanos.
    c = 299792458.0
    rx = (61090000000 + 1383435750910273353) % (604800 * 10**9)
    expected = (rx - 258211922049091) * 1e-9 * c
    g04 = obs.satellites.index("G04")
    assert obs.observation("C1C")[0, g04] == pytest.approx(expected, abs=1e-6)
    # Doppler: −rate/λ; C/N0 as logged.
    assert obs.observation("D1C")[0, g04] == pytest.approx(-673.7922380838304 / (c / 1575420030))
    assert obs.observation("S1C")[0, g04] == pytest.approx(28.924739837646484)
    # Records without code lock (State lacks bits 1 and 1024, e.g. 16384:
    # TOW known only; their L5 pseudoranges sit 190 m off L1) are skipped.
    text = (DATA / "android-gnsslogger" / "pixel6_excerpt.txt").read_text().splitlines()
    header = next(line[2:].split(",") for line in text if line.startswith("# Raw,"))
    states = [
        int(dict(zip(header, line.split(","), strict=True))["State"])
        for line in text
        if line.startswith("Raw,")
    ]
    unlocked = sum(1 for s in states if s & (1 | 1024) == 0)
    assert unlocked > 0 and log.skipped == {"no code lock (State)": unlocked}
    assert log.imu is not None and len(log.imu) >= 1


def test_gnsslogger_pseudoranges_and_doppler_agree_with_its_rinex():
    """The phone's GnssLogger file and its RINEX twin share no epoch (Raw
    every 18 s at GPS seconds = 2 mod 6, RINEX every 12 s at 3 mod 6): the
    RINEX values are interpolated (cubic through the four nearest epochs) to
    each Raw epoch and the epoch's common offset (the receiver clock) is
    removed. A wrong time scale, week or ms is off by kilometres; what is
    left is the phone's code noise over 12 s."""
    folder = shared_data("android-gnsslogger")
    log = mn.read_gnsslogger(folder / "pixel6_gnsslogger.txt")
    obs = log.observations
    rinex = mn.read_rinex_obs(folder / "pixel6.23o")
    assert obs.satellites == rinex.satellites
    assert obs.observation_types == rinex.observation_types
    columns = [rinex.satellites.index(s) for s in obs.satellites]
    figures = {}
    for code in ("C1C", "C5Q", "D1C", "D5Q"):
        ours, theirs = obs.observation(code), rinex.observation(code)[:, columns]
        residuals = []
        for k, t in enumerate(obs.time):
            i = int(np.searchsorted(rinex.time, t))
            near = np.arange(i - 2, i + 2)
            if near[0] < 0 or near[-1] >= len(rinex.time):
                continue
            x = rinex.time[near] - t
            d = np.array(
                [
                    ours[k, j] - np.polyval(np.polyfit(x, theirs[near, j], 3), 0.0)
                    if np.all(np.isfinite(theirs[near, j]))
                    else np.nan
                    for j in range(len(columns))
                ]
            )
            d = d[np.isfinite(d)]
            if len(d) >= 3:
                residuals.extend(np.abs(d - np.median(d)))
        figures[code] = (np.median(residuals), np.percentile(residuals, 95))
    # Measured: C1C 3.1 / 17 m, C5Q 0.55 / 2.3 m, D1C 1.0 / 4.7 Hz, D5Q 0.54 / 2.3 Hz.
    assert figures["C1C"][0] < 5.0 and figures["C1C"][1] < 30.0, figures
    assert figures["C5Q"][0] < 1.0 and figures["C5Q"][1] < 4.0, figures
    assert figures["D1C"][0] < 2.0 and figures["D5Q"][0] < 1.0, figures
