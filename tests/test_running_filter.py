"""The step API (``Filter.start`` -> ``RunningFilter``) against the batch
``run``: the same calls in the same order give the same filter bit for bit
(tight and loose); increments run the increments mechanization; the aids
(odometer, height, heading) bound an outage and their errors stay inside
the filter's covariance; and what the step API refuses.

Speed is measured in ``benches/python/bench_running_filter.py``, not here.
"""

from __future__ import annotations

import doc_runs
import numpy as np
import pytest
from figures import figures

import memsnav as mn

TOLERANCE_S = doc_runs.STEP_TOLERANCE_S
initial = doc_runs.initial_state


def step_through(running, t, f, w, epochs_time, update):
    """Drives ``running`` over the samples as ``run`` does (an epoch within
    the tolerance of a sample is applied after it); returns the position,
    velocity and covariance diagonal after every sample."""
    n = len(t)
    pos, vel, diag = np.empty((n, 3)), np.empty((n, 3)), []
    j = 0
    for k in range(n):
        if k > 0:
            running.predict(t[k], f[k], w[k])
        while j < len(epochs_time) and epochs_time[j] <= t[k] + TOLERANCE_S:
            update(j)
            j += 1
        pos[k], vel[k] = running.position_ecef, running.velocity_ecef
        diag.append(np.diag(running.covariance))
    assert j == len(epochs_time)
    return pos, vel, np.array(diag)


def test_stepping_gnss_epochs_is_the_batch_run(drive_300s):
    traj, gnss, imu, f, w = drive_300s
    n = 6001  # the first 60 s
    t, f, w = traj.time[:n], f[:n], w[:n]
    keep = np.asarray(gnss.time) <= t[-1]
    flt = mn.TightlyCoupledFilter(imu)
    sol = flt.run(t, f, w, gnss_slice(gnss, keep), initial_state=initial(traj))
    running = flt.start(t[0], f[0], w[0], initial(traj))
    assert running.state_names == sol.state_names
    applied: list[bool] = []
    pos, vel, diag = step_through(
        running,
        t,
        f,
        w,
        np.asarray(gnss.time)[keep],
        lambda j: applied.append(running.update_gnss(gnss, j)),
    )
    np.testing.assert_array_equal(pos, sol.position_ecef)
    np.testing.assert_array_equal(vel, sol.velocity_ecef)
    np.testing.assert_array_equal(diag, sol.covariance_diagonal)
    np.testing.assert_array_equal(running.attitude, sol.attitude[-1])
    records = running.take_records()
    for name in ("innovation", "nis", "time"):
        np.testing.assert_array_equal(records["measurements"][name], sol.measurements[name])
    assert records["measurements"]["status"] == sol.measurements["status"]
    assert len(records["batches"]["time"]) == len(sol.batches["time"])
    # Each call said whether its epoch was applied whole, as the batch
    # run's records say.
    assert applied == applied_whole(sol.batches, np.asarray(gnss.time)[keep])
    # Taken means handed over: the next call has only what came since.
    assert len(running.take_records()["measurements"]["time"]) == 0


def applied_whole(batches, epoch_times):
    """Per epoch, whether the batch run's records show every batch at its
    time accepted (and at least one): what the step API's update returns."""
    time, accepted = np.asarray(batches["time"]), np.asarray(batches["accepted"])
    return [bool(np.any(time == te) and np.all(accepted[time == te])) for te in epoch_times]


def gnss_slice(gnss, keep):
    names = (
        "time sat_id satellite_position_ecef satellite_velocity_ecef pseudorange "
        "pseudorange_std pseudorange_rate pseudorange_rate_std"
    ).split()
    return {n: np.asarray(getattr(gnss, n))[keep] for n in names}


def test_stepping_fixes_is_the_batch_run(drive_300s):
    traj, _, imu, f, w = drive_300s
    n = 6001
    t, f, w = traj.time[:n], f[:n], w[:n]
    rng = np.random.default_rng(8)
    k = np.arange(0, n, 100)
    cov_p, cov_v = np.diag([4.0, 4.0, 9.0]), np.eye(3) * 0.01
    fixes = {
        "time": t[k],
        "position_ecef": traj.position_ecef[k] + rng.normal(0, 2.0, (len(k), 3)),
        "position_covariance": np.repeat(cov_p[None], len(k), axis=0),
        "velocity_ecef": traj.velocity_ecef[k] + rng.normal(0, 0.1, (len(k), 3)),
        "velocity_covariance": np.repeat(cov_v[None], len(k), axis=0),
    }
    # Two positions 100 m off and a velocity 20 m/s off: those blocks fail
    # their gate, so those fixes are not applied whole.
    fixes["position_ecef"][[20, 40], 0] += 100.0
    fixes["velocity_ecef"][30, 1] += 20.0
    flt = mn.LooselyCoupledFilter(imu)
    with pytest.warns(UserWarning, match="inconsistent with its position"):
        sol = flt.run(t, f, w, fixes, initial_state=initial(traj))
    running = flt.start(t[0], f[0], w[0], initial(traj))
    applied: list[bool] = []

    def update(j):
        applied.append(
            running.update_fix(fixes["position_ecef"][j], cov_p, fixes["velocity_ecef"][j], cov_v)
        )

    pos, vel, diag = step_through(running, t, f, w, fixes["time"], update)
    np.testing.assert_array_equal(pos, sol.position_ecef)
    np.testing.assert_array_equal(vel, sol.velocity_ecef)
    np.testing.assert_array_equal(diag, sol.covariance_diagonal)
    assert all(type(a) is bool for a in applied)
    assert applied == applied_whole(sol.batches, fixes["time"])
    assert [j for j, a in enumerate(applied) if not a] == [20, 30, 40]


def test_increments_follow_the_increments_mechanization(drive_300s):
    """Error-free increments through the step API reproduce the INS's own
    increments run (``strapdown_increments``) and the trajectory."""
    traj, _, imu, _, _ = drive_300s
    n = 3001
    t = traj.time[:n]
    dv, dtheta = mn.imu_increments(t, traj.specific_force[:n], traj.angular_rate[:n])
    ins = mn.strapdown_increments(
        t, dv, dtheta, traj.position_ecef[0], traj.velocity_ecef[0], traj.attitude[0]
    )
    running = mn.TightlyCoupledFilter(imu).start(
        t[0], traj.specific_force[0], traj.angular_rate[0], initial(traj)
    )
    for k in range(1, n):
        running.predict_increments(t[k], dv[k - 1], dtheta[k - 1])
    np.testing.assert_allclose(running.position_ecef, ins.position_ecef[-1], rtol=0, atol=1e-6)
    error = np.linalg.norm(running.position_ecef - traj.position_ecef[n - 1])
    assert error < 0.05, error


def test_aids_bound_an_outage_inside_the_covariance():
    """A 60 s GNSS outage bridged by an odometer (forward speed), a
    barometer (height) and a heading at 10 Hz: the horizontal error stays
    a fraction of the unaided one, and every aided error is inside 3σ of
    the filter's own covariance (docs/doc_runs.py aided_outage_runs)."""
    results, accepted, kinds = doc_runs.aided_outage_runs()
    # The gate (0.999) rejects about one in a thousand good ones.
    assert np.mean(accepted[True]) > 0.99, np.mean(accepted[True])
    assert not accepted[False]
    assert {"speed", "height", "heading"} <= kinds[True]
    assert not {"speed", "height", "heading"} & kinds[False]
    coast, aided = results[False][0], results[True][0]
    assert aided[-1] < 0.25 * coast[-1], (aided[-1], coast[-1])
    assert np.all(results[True][1] < 3.0), results[True][1].max()
    # docs/how-to/step-api.md shows both ends from the record.
    recorded = figures("aided_outage")
    assert abs(coast[-1] - recorded["coast_end_m"]) <= 1e-9, coast[-1]
    assert abs(aided[-1] - recorded["aided_end_m"]) <= 1e-9, aided[-1]


def test_bad_calls_name_the_argument_and_change_nothing(drive_300s):
    traj, gnss, imu, f, w = drive_300s
    tight = mn.TightlyCoupledFilter(imu)
    running = tight.start(traj.time[0], f[0], w[0], initial(traj))
    before = running.position_ecef.copy()
    cases = [
        (lambda: running.predict(traj.time[0], f[1], w[1]), "time"),
        (lambda: running.predict(5.0, f[1], w[1]), "longer than"),
        (lambda: running.predict(0.01, [np.nan, 0, 0], w[1]), "specific_force"),
        (lambda: running.predict(0.01, f[1], [1.0, 2.0]), "angular_rate"),
        (lambda: running.predict_increments(0.01, f[1], [1e9, 0, 0]), "delta_theta"),
        (lambda: running.update_gnss(gnss, 5), "predict to the epoch's time"),
        (lambda: running.update_gnss(gnss, 10_000), "epoch"),
        (lambda: running.update_fix([1.0, 2.0, 3.0], np.eye(3), [0, 0, 0]), "velocity_covariance"),
        # One call's error names its argument, not a fix of a batch.
        (lambda: running.update_fix(before, -np.eye(3)), "^position_covariance: covariance"),
        (
            lambda: running.update_fix(before, np.eye(3), [0, 0, 0], -np.eye(3)),
            "^velocity_covariance: covariance",
        ),
        (lambda: running.update_height(np.nan, 1.0), "height"),
        (lambda: running.update_heading(0.1, 0.0), "std"),
        (lambda: running.update_speed(3.0, -1.0), "std"),
        (lambda: running.update_zaru([0, 0, 0], [1e-3, 0, 1e-3]), "std"),
        (lambda: tight.start(0.0, f[0], w[0], {"position_ecef": [0, 0, 0]}), "initial_state"),
    ]
    for call, word in cases:
        with pytest.raises(ValueError, match=word):
            call()
    np.testing.assert_array_equal(running.position_ecef, before)
    assert running.time == traj.time[0]
    loose = mn.LooselyCoupledFilter(imu).start(traj.time[0], f[0], w[0], initial(traj))
    with pytest.raises(ValueError, match="LooselyCoupledFilter"):
        loose.update_gnss(gnss, 0)
    assert "RunningFilter(TightlyCoupledFilter, 17 states" in repr(running)


def test_run_increments_is_the_stepped_increments_run(drive_300s):
    """``run_increments`` integrates the increments natively, the way
    ``predict_increments`` does: the same calls, the same numbers."""
    traj, gnss, imu, _, _ = drive_300s
    n = 3001
    t = traj.time[:n]
    dv, dtheta = mn.imu_increments(t, traj.specific_force[:n], traj.angular_rate[:n])
    keep = np.asarray(gnss.time) <= t[-1]
    flt = mn.TightlyCoupledFilter(imu)
    sol = flt.run_increments(t, dv, dtheta, gnss_slice(gnss, keep), initial_state=initial(traj))
    # The first interval's means stand for the first sample.
    running = flt.start(t[0], dv[0] / (t[1] - t[0]), dtheta[0] / (t[1] - t[0]), initial(traj))
    epochs_time = np.asarray(gnss.time)[keep]
    j, pos = 0, np.empty((n, 3))
    for k in range(n):
        if k > 0:
            running.predict_increments(t[k], dv[k - 1], dtheta[k - 1])
        while j < len(epochs_time) and epochs_time[j] <= t[k] + TOLERANCE_S:
            running.update_gnss(gnss, j)
            j += 1
        pos[k] = running.position_ecef
    np.testing.assert_array_equal(pos, sol.position_ecef)
    assert np.linalg.norm(pos[-1] - traj.position_ecef[n - 1]) < 5.0
    with pytest.raises(ValueError, match="delta_v"):
        flt.run_increments(t, dv[:-1], dtheta[:-1], gnss_slice(gnss, keep))


@pytest.mark.slow
def test_the_increments_gain_is_the_record():
    """600 s of unaided propagation from error-free data ends closer to the
    truth by increments (coning and sculling) than by instantaneous
    samples, much closer at 20 Hz; the figures docs/how-to/step-api.md and
    docs/how-to/your-own-imu-log.md show are this run's record."""
    fresh, recorded = doc_runs.increments_gain(None), figures("increments_gain")
    for rate in ("100", "20"):
        assert fresh[rate]["increments_m"] < fresh[rate]["samples_m"], fresh
        for key, value in fresh[rate].items():
            assert abs(value - recorded[rate][key]) <= 1e-9, (rate, key, value)
    assert fresh["20"]["samples_m"] > 5 * fresh["20"]["increments_m"], fresh


def test_updates_are_transactions_and_starts_plausible(drive_300s):
    """Arguments no sensor gives (a std that squares to zero, a lever arm
    of 1e30 m, a fix 1e30 m from the Earth's centre) are refused before the
    filter is touched: its state, covariance and records are the ones
    before, array for array; a start no receiver can have names its key."""
    traj, _, imu, f, w = drive_300s
    rate = np.array([1e-4, -2e-4, 3e-5])
    cases = [
        (lambda r: r.update_non_holonomic(1e-300), r"std: 1e-300 is outside"),
        (lambda r: r.update_non_holonomic(0.1, [1e30, 0, 0]), r"lever_arm: .*100 m"),
        (lambda r: r.update_zaru(rate, 1e-300), r"std: 1e-300 is outside"),
        (lambda r: r.update_speed(1.0, 0.1, [0, 1e30, 0]), r"lever_arm"),
    ]
    cases += [
        (
            lambda r: r.update_fix([1e30, 0, 0], 4 * np.eye(3)),
            r"position_ecef: 1e30 m from the Earth's centre is no receiver's position",
        )
    ] * 3
    for cls in (mn.TightlyCoupledFilter, mn.LooselyCoupledFilter):
        running = cls(imu).start(traj.time[0], f[0], w[0], initial(traj))
        running.predict(traj.time[1], f[1], w[1])
        running.update_zupt(0.05)
        before = (running.state, running.covariance.copy(), running.position_ecef.copy())
        for call, message in cases:
            with pytest.raises(ValueError, match=message):
                call(running)
            state, covariance, position = before
            for name, value in running.state.to_dict().items():
                np.testing.assert_array_equal(value, getattr(state, name))
            np.testing.assert_array_equal(running.covariance, covariance)
            np.testing.assert_array_equal(running.position_ecef, position)
        # One ZUPT's batch and its rows, nothing from the refused calls.
        records = running.take_records()
        assert len(records["batches"]["time"]) == 1
        start = initial(traj) | {"clock_drift": 1.797e308, "clock_offset": 0.0}
        with pytest.raises(ValueError, match=r"initial\.clock_drift: 1\.797e308 is beyond"):
            cls(imu).start(traj.time[0], f[0], w[0], start)
    tight = mn.TightlyCoupledFilter(imu)
    with pytest.raises(ValueError, match=r"initial\.clock_offset"):
        tight.start(traj.time[0], f[0], w[0], initial(traj) | {"clock_offset": 1e9})
    far = initial(traj) | {"position_ecef": [1e30, 0.0, 0.0]}
    with pytest.raises(ValueError, match="position"):
        tight.start(traj.time[0], f[0], w[0], far)
