"""Carrier phase from Python: simulated carriers with silent cycle slips
through the tight filter's time-differenced carrier phase, and the slips'
truth found among its records."""

import numpy as np

import memsnav as mn


def test_the_tight_filter_finds_the_simulated_slips(drive_300s):
    traj, _, imu, f, w = drive_300s
    sky = mn.Constellation.walker()
    gnss = mn.simulate_gnss(
        traj.time, traj.position_ecef, traj.velocity_ecef, sky,
        n_satellites=10, carrier_phase_std=0.003, cycle_slip_probability=0.02, seed=4,
    )  # fmt: skip
    slips = gnss.cycle_slips
    assert len(slips["time"]) > 20 and not gnss.loss_of_lock[1:].any()
    start = {
        "position_ecef": traj.position_ecef[0],
        "velocity_ecef": traj.velocity_ecef[0],
        "attitude": traj.attitude[0],
    }
    solutions = {
        use: mn.TightlyCoupledFilter(imu, use_carrier_phase=use).run(
            traj.time, f, w, gnss, initial_state=start
        )
        for use in (False, True)
    }
    records = solutions[True].measurements
    carrier = np.asarray(records["kind"]) == "carrier_phase"
    assert carrier.sum() > 1000
    assert not (np.asarray(solutions[False].measurements["kind"]) == "carrier_phase").any()
    not_applied = carrier & np.isin(np.asarray(records["status"]), ["slip", "excluded", "gate"])
    flagged = set(
        zip(
            np.asarray(records["time"])[not_applied],
            np.asarray(records["id"])[not_applied],
            strict=True,
        )
    )
    injected = list(zip(slips["time"], slips["sat_id"], strict=True))
    found = sum((t, s) in flagged for t, s in injected)
    assert found >= 0.95 * len(injected), (found, len(injected))
    error = {
        use: np.sqrt(np.mean(np.sum((s.position_ecef - traj.position_ecef) ** 2, axis=1)))
        for use, s in solutions.items()
    }
    assert error[True] < error[False], error


def test_the_smoother_takes_the_carrier_changes(drive_300s):
    """The carrier changes reach the fixed-interval smoother as the forward
    filter applied them: the smoothed solution is finite and closer to the
    truth than the forward one, with carrier phase as without."""
    traj, _, imu, f, w = drive_300s
    gnss = mn.simulate_gnss(
        traj.time, traj.position_ecef, traj.velocity_ecef, mn.Constellation.walker(),
        n_satellites=10, carrier_phase_std=0.003, cycle_slip_probability=0.01, seed=5,
    )  # fmt: skip
    start = {
        "position_ecef": traj.position_ecef[0],
        "velocity_ecef": traj.velocity_ecef[0],
        "attitude": traj.attitude[0],
    }
    run = mn.TightlyCoupledFilter(imu, use_carrier_phase=True).run(
        traj.time, f, w, gnss, initial_state=start, smooth=True
    )

    def rms(solution):
        return np.sqrt(np.mean(np.sum((solution.position_ecef - traj.position_ecef) ** 2, axis=1)))

    assert np.isfinite(run.smoothed.position_ecef).all()
    assert rms(run.smoothed) < rms(run)
