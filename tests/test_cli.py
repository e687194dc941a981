"""The ``memsnav`` command: simulate's files, and one-line errors with a
non-zero status and no traceback for bad options."""

import json
import subprocess
import sys

import numpy as np
import pytest

import memsnav as mn


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "memsnav", *args], capture_output=True, text=True, check=False
    )


def test_simulate_writes_consistent_files(tmp_path):
    out = tmp_path / "sim"
    done = run("simulate", "--out", str(out), "--duration", "30", "--outage", "10:5", "--seed", "3")
    assert done.returncode == 0, done.stderr
    trajectory = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    imu = np.loadtxt(out / "imu.csv", delimiter=",", skiprows=1)
    imu_truth = np.loadtxt(out / "imu_truth.csv", delimiter=",", skiprows=1)
    gnss = np.loadtxt(out / "gnss.csv", delimiter=",", skiprows=1)
    meta = json.loads((out / "simulation.json").read_text())
    assert trajectory.shape == (3001, 11) and imu.shape == imu_truth.shape == (3001, 8)
    # The files hold what the API computes from the seeds derived from 3,
    # one per independent draw, recorded in simulation.json.
    seeds = meta["derived_seeds"]
    assert seeds == {
        n: mn.derive_seed(3, n) for n in ("trajectory", "imu errors", "imu noise", "gnss")
    }
    truth = mn.Trajectory.random(duration=30.0, rate=100.0, seed=seeds["trajectory"])
    np.testing.assert_allclose(trajectory[:, 1:4], truth.position_ecef, rtol=0, atol=1e-3)
    model = mn.ImuModel.preset("paper-mems", seed=seeds["imu errors"])
    accel, _ = model.measure(truth.specific_force, truth.angular_rate, seed=seeds["imu noise"])
    np.testing.assert_allclose(imu[:, 2:5], accel, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(imu_truth[:, 2:5], truth.specific_force, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(imu_truth[:, 5:8], truth.angular_rate, rtol=1e-9, atol=1e-15)
    # One GPS time in every file: the samples' (trajectory, IMU) and the
    # GNSS epochs' (gnss.csv's gps_time_s against its time_s).
    np.testing.assert_array_equal(trajectory[:, 0], imu[:, 1])
    np.testing.assert_allclose(imu[:, 1] - imu[:, 0], gnss[0, 1] - gnss[0, 0], atol=1e-9)
    np.testing.assert_allclose(
        meta["imu_errors"]["accelerometer"]["bias_m_s2"], model.accelerometer.bias
    )
    # 6 satellites per epoch at 1 Hz, none inside the outage [10, 15).
    epochs, counts = np.unique(gnss[:, 0], return_counts=True)
    assert set(counts) == {6}
    assert not np.any((epochs >= 10) & (epochs < 15))
    assert len(epochs) == 31 - 5
    # Pseudoranges are ranges to satellites plus the receiver clock: the
    # spread of (pseudorange - range) over satellites at one epoch is the
    # 3 m noise, not the 20 000 km range.
    first = gnss[gnss[:, 0] == 0]
    ranges = np.linalg.norm(first[:, 3:6] - trajectory[0, 1:4], axis=1)
    assert np.std(first[:, 9] - ranges) < 30.0


def test_simulate_with_galileo_and_beidou(tmp_path):
    out = tmp_path / "sim"
    done = run(
        "simulate", "--out", str(out), "--duration", "5", "--satellites", "30",
        "--systems", "G,E,C", "--inter-system-bias", "3,-25",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    gnss = np.loadtxt(out / "gnss.csv", delimiter=",", skiprows=1)
    meta = json.loads((out / "simulation.json").read_text())
    assert meta["systems"] == ["G", "E", "C"] and meta["inter_system_bias_m"] == [3.0, -25.0]
    # Satellite ids say the system: G 1-24, E 101-124, C 201-224.
    systems = set(gnss[:, 2].astype(int) // 100)
    assert systems == {0, 1, 2}
    back = mn.GnssMeasurements.from_table(out / "gnss.csv")
    assert back.sat_id.max() > 200


def test_simulate_with_glonass(tmp_path):
    out = tmp_path / "sim"
    done = run(
        "simulate", "--out", str(out), "--duration", "5", "--satellites", "14",
        "--systems", "G,R", "--inter-system-bias", "0,0,12",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    gnss = np.loadtxt(out / "gnss.csv", delimiter=",", skiprows=1)
    meta = json.loads((out / "simulation.json").read_text())
    assert meta["systems"] == ["G", "R"] and meta["inter_system_bias_m"] == [0.0, 0.0, 12.0]
    # GLONASS slots are numbered 301-324.
    assert set(gnss[:, 2].astype(int) // 100) == {0, 3}


def test_derived_seeds_do_not_overlap_between_user_seeds():
    # seed + 1 would make seed 0's IMU errors seed 1's trajectory.
    names = ("trajectory", "imu errors", "imu noise", "gnss")
    derived = [mn.derive_seed(seed, name) for seed in range(20) for name in names]
    assert len(set(derived)) == len(derived)
    assert not set(derived) & set(range(1000))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["reproduce", "--runs", "0"], "--runs: must be positive"),
        (["reproduce", "--bogus"], "unrecognized arguments: --bogus"),
        (["simulate", "--duration", "nan"], "--duration: must be positive"),
        (["simulate", "--outage", "5"], "expected START:LENGTH"),
        (["simulate", "--imu", "cheap"], "invalid choice: 'cheap'"),
        (["simulate", "--systems", "G,X"], "expected letters among G, E, C, R"),
        (["simulate", "--inter-system-bias", "3"], "expected GALILEO,BEIDOU"),
        (["simulate", "--cycle-slip-probability", "2"], "must be within [0, 1], got 2"),
        (["simulate", "--carrier-phase-std", "-1"], "must be zero or more and finite"),
    ],
)
def test_bad_options_fail_in_one_line(args, message):
    done = run(*args)
    assert done.returncode != 0
    assert message in done.stderr
    assert "Traceback" not in done.stderr


def test_unwritable_output_directory(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    done = run("simulate", "--out", str(blocker / "sub"), "--duration", "5")
    assert done.returncode == 1
    assert done.stderr.startswith("memsnav: error: cannot write into")
    assert "Traceback" not in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1


def test_simulate_with_carrier_phase_and_slips(tmp_path):
    out = tmp_path / "sim"
    done = run(
        "simulate", "--out", str(out), "--duration", "60", "--seed", "2",
        "--carrier-phase-std", "0.003", "--cycle-slip-probability", "0.05",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    meta = json.loads((out / "simulation.json").read_text())
    assert meta["carrier_phase_std_m"] == 0.003 and meta["cycle_slip_probability"] == 0.05
    slips = meta["cycle_slips"]
    assert 5 <= len(slips) <= 40 and all(s["cycles"] != 0 for s in slips)
    back = mn.GnssMeasurements.from_table(out / "gnss.csv")
    tracked = back.sat_id >= 0
    assert np.isfinite(back.carrier_phase[tracked]).all()
    assert (back.carrier_phase_std[tracked] == 0.003).all()
    assert back.loss_of_lock[0][tracked[0]].all() and not back.loss_of_lock[1:].any()
    # A listed slip shows in carrier minus code at its epoch (3 m code
    # noise hides a cycle or two; the big ones stand out).
    big = [s for s in slips if abs(s["cycles"]) > 200]
    assert big
    for s in big:
        k = int(np.flatnonzero(back.time == s["time_s"])[0])
        (j,) = np.flatnonzero(back.sat_id[k] == s["sat_id"])
        (i,) = np.flatnonzero(back.sat_id[k - 1] == s["sat_id"])
        before = back.carrier_phase[k - 1, i] - back.pseudorange[k - 1, i]
        after = back.carrier_phase[k, j] - back.pseudorange[k, j]
        # 5 sigma of two 3 m code noises: 21 m, 110 cycles.
        assert abs((after - before) / (299792458.0 / 1575.42e6) - s["cycles"]) < 110
    plain = run("simulate", "--out", str(tmp_path / "plain"), "--duration", "5")
    assert plain.returncode == 0, plain.stderr
    header = (tmp_path / "plain" / "gnss.csv").read_text().splitlines()[0]
    assert "carrier_phase_m" not in header
