"""The filter classes built from a ``navigate`` configuration's tables
(``settings=``): every key that changes the filter or its aids is taken
under its navigate name, the keys that prepare a navigate run are refused
by name, the state blocks the settings ask for (installation, range
biases, a slot for every satellite) are the ones the filter runs with, and
a configuration run through the classes is navigate's solution, aids
included."""

from __future__ import annotations

import numpy as np
import pytest

import memsnav as mn

#: A value for every key of the filter's tables (the ones a filter on the
#: caller's arrays reads), each different from its default.
VALUES: dict[str, dict[str, object]] = {
    "imu": {
        "lever_arm_m": [0.1, 0.0, -0.2],
        "time_offset_std_s": 0.02,
        "mounting_std_deg": 2.0,
    },
    "gnss": {
        "antenna_lever_arm_m": [0.5, 0.1, -1.0],
        "antenna_lever_arm_std_m": 0.2,
        "velocity_latency_s": 0.1,
        "velocity_latency_std_s": 0.05,
        "use_pseudorange_rate": False,
        "carrier_phase": True,
        "receiver_clock": "ocxo",
        "range_bias_states": "every_satellite",
        "range_bias_std_m": 2.0,
        "range_bias_correlation_time_s": 600.0,
        "fix_error_states": True,
        "fix_error_std_m": 0.5,
        "fix_error_correlation_time_s": 300.0,
        "fix_correlation_time_s": 5.0,
    },
    "filter": {
        "accel_noise_density": 0.003,
        "gyro_noise_density_deg": 0.02,
        "accel_bias_std": 0.2,
        "gyro_bias_std_deg_s": 0.5,
        "accel_bias_instability": 0.001,
        "gyro_bias_instability_deg_s": 0.01,
        "bias_correlation_time_s": 300.0,
        "initial_position_std_m": 7.0,
        "initial_velocity_std_m_s": 0.7,
        "initial_attitude_std_deg": [2.0, 2.0, 8.0],
        "gate_probability": 0.99,
        "scale_factor_states": True,
        "installation_states": True,
        "accel_scale_factor_std_ppm": 5000.0,
        "gyro_scale_factor_std_ppm": 5000.0,
        "pseudorange_std_floor_m": 0.3,
        "pseudorange_rate_std_floor_m_s": 0.01,
        "position_std_floor_m": 0.02,
        "velocity_std_floor_m_s": 0.01,
        "carrier_phase_std_floor_m": 0.01,
        "pseudorange_correlation_time_s": 20.0,
        "reset_after_failed_epochs": 5,
        "reset_fading_factor": 10.0,
        "clock_jump_sigma": 50.0,
        "max_excluded_share": 0.3,
    },
    "imu_spec": {
        "accel_vrw_m_s_sqrt_h": 0.1,
        "gyro_arw_deg_sqrt_h": 0.5,
    },
    "standstill": {
        "window_s": 2.0,
        "accel_std_m_s2": 0.2,
        "gyro_std_deg_s": 2.0,
        "gnss_speed_m_s": 0.3,
        "gnss_age_s": 2.0,
        "solution_speed_m_s": 0.5,
        "solution_speed_sigmas": 2.0,
    },
    "aids": {
        "zupt": False,
        "zupt_std_m_s": 0.05,
        "zupt_interval_s": 0.5,
        "zaru": False,
        "zaru_min_std_deg_s": 0.1,
        "nhc": True,
        "nhc_std_m_s": 0.2,
        "nhc_interval_s": 1.0,
        "nhc_min_speed_m_s": 2.0,
    },
}

#: Keys that need another: a bias instability needs its correlation time.
PARTNERS = {
    ("filter", "accel_bias_instability"): {"bias_correlation_time_s": 300.0},
    ("filter", "gyro_bias_instability_deg_s"): {"bias_correlation_time_s": 300.0},
    ("aids", "nhc"): {"nhc_std_m_s": 0.2},
}

#: What a navigate run reads for itself, refused by the filter classes.
REFUSED: dict[str, dict[str, object]] = {
    "filter": {"imu_preset": "consumer", "smoother": True},
    "imu": {"time_offset_s": 0.1, "mounting_rpy_deg": [[0.0, 0.0, 90.0]]},
    "alignment": {"heading_deg": 10.0},
    "outages": {"windows_s": [[10.0, 5.0]]},
}


def test_every_filter_key_is_taken_or_refused_by_name(drive_300s):
    """The keys above are every key navigate_settings() lists outside the
    refused tables and the datasheet table (whose units the datasheet
    reader's own tests cover; two of its keys are here): each is taken
    alone and all together (both classes) or refused with its table named; a misspelt key
    or an "auto" is refused with its table.key, and so is the
    non-holonomic constraint without its std (a navigate run learns it)."""
    listed = {(t, k) for t, keys in mn.navigate_settings().items() for k in keys}
    covered = {(t, k) for group in (VALUES, REFUSED) for t, keys in group.items() for k in keys}
    unlisted_tables = {"alignment", "outages", "imu_spec"}
    assert {(t, k) for t, k in listed if t not in unlisted_tables} <= covered
    assert covered <= listed
    _, _, imu, _, _ = drive_300s
    for cls in (mn.TightlyCoupledFilter, mn.LooselyCoupledFilter):
        # All at once, but the datasheet's figures and the [filter] keys
        # that override the same quantities are one or the other.
        cls(imu, settings={t: keys for t, keys in VALUES.items() if t != "imu_spec"})
        for table, keys in VALUES.items():
            for key, value in keys.items():
                cls(imu, settings={table: {key: value, **PARTNERS.get((table, key), {})}})
        for table, keys in REFUSED.items():
            for key, value in keys.items():
                with pytest.raises(ValueError, match=table):
                    cls(imu, settings={table: {key: value}})
        with pytest.raises(ValueError, match=r"filter\.gate_probabilty"):
            cls(imu, settings={"filter": {"gate_probabilty": 0.99}})
        with pytest.raises(ValueError, match=r"gnss\.fix_error_states"):
            cls(imu, settings={"gnss": {"fix_error_states": "auto"}})
        with pytest.raises(ValueError, match=r"aids\.nhc_std_m_s"):
            cls(imu, settings={"aids": {"nhc": True}})
        with pytest.raises(ValueError, match="not both"):
            cls(imu, settings={}, gate_probability=0.99)


def test_settings_set_the_tuning_under_their_navigate_names(drive_300s):
    """The values land where navigate puts them (the tuning in effect)."""
    _, _, imu, _, _ = drive_300s
    filter_keys = VALUES["filter"]
    flt = mn.TightlyCoupledFilter(
        imu,
        settings={
            "filter": {
                k: filter_keys[k]
                for k in (
                    "gate_probability",
                    "initial_position_std_m",
                    "initial_velocity_std_m_s",
                    "initial_attitude_std_deg",
                    "pseudorange_correlation_time_s",
                )
            },
            "gnss": {"use_pseudorange_rate": False, "carrier_phase": True},
        },
    )
    t = flt.tuning
    assert t["gate_probability"] == 0.99
    assert t["initial_position_std"] == 7.0
    assert t["initial_velocity_std"] == 0.7
    assert t["initial_tilt_std"] == pytest.approx(np.radians(2.0), rel=1e-12)
    assert t["initial_heading_std"] == pytest.approx(np.radians(8.0), rel=1e-12)
    assert t["pseudorange_correlation_time"] == 20.0
    assert t["use_pseudorange_rate"] is False and t["use_carrier_phase"] is True
    # navigate's defaults hold for what is not given: 12 shared range-bias
    # slots for pseudoranges, none for fixes.
    assert t["range_bias_states"] is True and t["installation_states"] is False
    assert mn.LooselyCoupledFilter(imu, settings={}).tuning["range_bias_states"] is False
    assert mn.TightlyCoupledFilter(imu).tuning["range_bias_states"] is False


def test_the_blocks_asked_for_are_the_filters_states(drive_300s):
    """Installation states and a range-bias slot for every satellite appear
    in the solution's state names; the running filter started from the same
    class has the same states (it applies no aids by itself, so it is
    refused while the settings' aids are on)."""
    traj, gnss, imu, f, w = drive_300s
    settings = {
        "filter": {"installation_states": True},
        "gnss": {"range_bias_states": "every_satellite"},
        "aids": {"zupt": False, "zaru": False},
    }
    flt = mn.TightlyCoupledFilter(imu, settings=settings)
    assert "installation" in repr(flt) and "range biases" in repr(flt)
    initial = {
        "position_ecef": traj.position_ecef[0],
        "velocity_ecef": traj.velocity_ecef[0],
        "attitude": traj.attitude[0],
    }
    sol = flt.run(traj.time, f, w, gnss, initial_state=initial)
    names = sol.state_names
    assert names[-1] == "range_bias_39" and "range_bias_40" not in names
    assert "lever_arm_x" in names and "mounting_yaw" in names
    running = flt.start(traj.time[0], f[0], w[0], initial)
    assert running.state_names == names
    aided = mn.TightlyCoupledFilter(imu, settings={**settings, "aids": {}})
    with pytest.raises(ValueError, match=r"\[aids\].*update_zupt"):
        aided.start(traj.time[0], f[0], w[0], initial)
    assert running.covariance.shape == (len(names), len(names))


def test_a_slot_for_every_satellite_changes_nothing_with_few_satellites(drive_300s):
    """With no more satellites than the 12 shared slots, every satellite
    holds a slot either way and the slots beyond stay uncoupled: the
    solutions agree to 1e-9 m, and both hold the same satellites' biases."""
    traj, gnss, imu, f, w = drive_300s
    initial = {
        "position_ecef": traj.position_ecef[0],
        "velocity_ecef": traj.velocity_ecef[0],
        "attitude": traj.attitude[0],
    }
    runs = {}
    for slots in (True, "every_satellite"):
        flt = mn.TightlyCoupledFilter(imu, settings={"gnss": {"range_bias_states": slots}})
        runs[slots] = flt.run(traj.time, f, w, gnss, initial_state=initial)
    shared, every = runs[True], runs["every_satellite"]
    assert len(shared.state_names) + 28 == len(every.state_names)
    np.testing.assert_allclose(every.position_ecef, shared.position_ecef, rtol=0, atol=1e-9)
    np.testing.assert_allclose(every.velocity_ecef, shared.velocity_ecef, rtol=0, atol=1e-9)


def test_a_navigate_configuration_through_the_classes_is_navigates_solution(drive_300s):
    """navigate_log with a configuration, and TightlyCoupledFilter with the
    same configuration's filter tables on the same arrays from navigate's
    start (its first sample, state and one-sigmas), give the same solution
    to 1e-9 m: one filter behind both doors. The aids are off and the start
    is a moving one (the start is what a navigate run adds around the
    filter); another setting moves the solution by more than a
    centimetre."""
    traj, gnss, _, f, w = drive_300s
    filter_tables = {
        "filter": {
            "scale_factor_states": True,
            "gate_probability": 0.9999,
            "pseudorange_std_floor_m": 0.5,
        },
        "gnss": {"range_bias_std_m": 2.0, "range_bias_correlation_time_s": 900.0},
    }
    navigate_settings = {
        "filter": {**filter_tables["filter"], "imu_preset": "consumer"},
        "gnss": filter_tables["gnss"],
        "alignment": {"method": "gnss_velocity"},
        "aids": {"zupt": False, "zaru": False, "nhc": False},
    }
    run = mn.navigate_log(traj.time, f, w, gnss, settings=navigate_settings)
    assert run.failure is None
    start = run.start
    k0 = start.first_sample
    rate = (len(traj.time) - 1) / (traj.time[-1] - traj.time[0])
    imu = mn.ImuModel.preset("consumer", sample_rate=rate)
    stds = np.degrees([start.tilt_std, start.tilt_std, start.heading_std])
    settings = {
        "filter": {
            **filter_tables["filter"],
            "initial_position_std_m": start.position_std,
            "initial_velocity_std_m_s": start.velocity_std,
            "initial_attitude_std_deg": list(stds),
        },
        "gnss": filter_tables["gnss"],
        "aids": navigate_settings["aids"],
    }
    flt = mn.TightlyCoupledFilter(imu, settings=settings)
    # The epochs navigate gave the filter: those from its start on.
    after = np.asarray(gnss.time) >= traj.time[k0]
    names = (
        "time sat_id satellite_position_ecef satellite_velocity_ecef pseudorange "
        "pseudorange_std pseudorange_rate pseudorange_rate_std"
    ).split()
    used = {n: np.asarray(getattr(gnss, n))[after] for n in names}
    sol = flt.run(traj.time[k0:], f[k0:], w[k0:], used, initial_state=start.initial_state)
    navigated = run.solution
    assert navigated.state_names == sol.state_names
    np.testing.assert_array_equal(navigated.time, sol.time)
    np.testing.assert_allclose(sol.position_ecef, navigated.position_ecef, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sol.velocity_ecef, navigated.velocity_ecef, rtol=0, atol=1e-9)
    # The comparison can tell filters apart: another gate moves the solution.
    settings["filter"]["gate_probability"] = 0.99
    other = mn.TightlyCoupledFilter(imu, settings=settings).run(
        traj.time[k0:], f[k0:], w[k0:], used, initial_state=start.initial_state
    )
    assert np.abs(other.position_ecef - navigated.position_ecef).max() > 0.01


#: A scripted drive with standstills (s, m/s, rad): a rest, a drive with a
#: turn, a stop, and on again, for the aids at standstills and while moving.
DRIVE_WITH_STOPS = [
    ("stop", 20.0),
    ("accelerate", 15.0, 12.0),
    ("cruise", 30.0),
    ("turn", 10.0, 1.2),
    ("accelerate", 12.0, 0.0),
    ("stop", 25.0),
    ("accelerate", 15.0, 10.0),
    ("cruise", 20.0),
]


def test_a_configuration_with_aids_through_the_classes_is_navigates_solution():
    """navigate_log and TightlyCoupledFilter with the same [aids] (the
    zero-velocity and zero-rate updates at the standstills they detect, by
    default, and the non-holonomic constraint) on a scripted drive with two
    standstills, from navigate's static start with a known heading: the
    same solution to 1e-9 m and the same count of each kind of update. The
    aids do apply (hundreds of each), and another ZUPT std moves the
    solution."""
    heading_rad = 0.3
    traj = mn.Trajectory.from_segments(DRIVE_WITH_STOPS, heading=heading_rad)
    gnss = mn.simulate_gnss(
        traj.time, traj.position_ecef, traj.velocity_ecef, mn.Constellation.walker(), seed=4
    )
    imu = mn.ImuModel.preset("consumer", sample_rate=100.0)
    f, w = imu.measure(traj.specific_force, traj.angular_rate, seed=6)
    aids = {"nhc": True, "nhc_std_m_s": 0.1}
    run = mn.navigate_log(
        traj.time,
        f,
        w,
        gnss,
        settings={
            "filter": {"imu_preset": "consumer"},
            "alignment": {"method": "static", "heading_deg": float(np.degrees(heading_rad))},
            "aids": aids,
        },
    )
    assert run.failure is None
    start = run.start
    k0 = start.first_sample
    stds = np.degrees([start.tilt_std, start.tilt_std, start.heading_std])
    settings = {
        "filter": {
            "initial_position_std_m": start.position_std,
            "initial_velocity_std_m_s": start.velocity_std,
            "initial_attitude_std_deg": list(stds),
        },
        "aids": aids,
    }
    after = np.asarray(gnss.time) >= traj.time[k0]
    names = (
        "time sat_id satellite_position_ecef satellite_velocity_ecef pseudorange "
        "pseudorange_std pseudorange_rate pseudorange_rate_std"
    ).split()
    used = {n: np.asarray(getattr(gnss, n))[after] for n in names}

    flt = mn.TightlyCoupledFilter(imu, settings=settings)
    assert repr(flt).endswith("aids zupt+zaru+nhc)") and flt.tuning["aids"] == "zupt, zaru, nhc"

    def through_class(settings):
        return mn.TightlyCoupledFilter(imu, settings=settings).run(
            traj.time[k0:], f[k0:], w[k0:], used, initial_state=start.initial_state
        )

    sol = through_class(settings)
    navigated = run.solution
    np.testing.assert_allclose(sol.position_ecef, navigated.position_ecef, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sol.velocity_ecef, navigated.velocity_ecef, rtol=0, atol=1e-9)

    def updates(solution):
        kinds, counts = np.unique(solution.measurements["kind"], return_counts=True)
        return dict(zip(kinds.tolist(), counts.tolist(), strict=True))

    assert updates(sol) == updates(navigated)
    for aid in ("zero_velocity", "zero_rate", "non_holonomic"):
        assert updates(sol).get(aid, 0) > 100, aid
    other = through_class({**settings, "aids": {**aids, "zupt_std_m_s": 0.2}})
    assert np.abs(other.position_ecef - navigated.position_ecef).max() > 0.01
