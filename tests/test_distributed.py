"""Monte Carlo on Dask: chunks of runs on the workers of a
process LocalCluster fold to the numbers of local threads bit for bit,
whatever the chunk size; Ctrl-C keeps the completed chunks; a worker
killed mid-run is replaced and its chunks recomputed, with the same
result."""

import os
import signal
import subprocess
import sys

import numpy as np
import pytest

import memsnav as mn

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as c:
        yield c


def _bits(a):
    """Arrays compared bit for bit (NaN included), not within a tolerance."""
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.uint64)


def _same(a, b):
    assert np.array_equal(_bits(a), _bits(b))


NAVIGATION = {
    "outage": (20.0, 10.0, 2),
    "runs": 5,
    "duration": 40.0,
    "imus": ("ins", "mems", "calibrated_mems"),
    "calibration_duration": 30.0,
    "smooth": True,
    "seed": 4,
}


@pytest.fixture(scope="module")
def navigation_local():
    return mn.experiments.navigation(**NAVIGATION, threads=2)


@pytest.mark.parametrize("chunk_runs", [1, 2, 5])
def test_navigation_is_bit_identical_whatever_the_chunks(client, navigation_local, chunk_runs):
    remote = mn.experiments.navigation(**NAVIGATION, client=client, chunk_runs=chunk_runs)
    local = navigation_local
    assert remote.completed_runs == 5 and not remote.interrupted
    for name in local.imus:
        for result, other in ((local, remote), (local.smoothed, remote.smoothed)):
            _same(result.mean[name], other.mean[name])
            _same(result.percentiles[name], other.percentiles[name])
            _same(result.position_error[name], other.position_error[name])
            for key, values in result.runs_summary[name].items():
                _same(values, other.runs_summary[name][key])


def test_calibration_inversion_and_partial_outage_are_bit_identical(client):
    cal = {"parameter_sets": 2, "runs": 3, "duration": 20.0, "seed": 1}
    local, remote = (
        mn.experiments.calibration(**cal, threads=2),
        mn.experiments.calibration(**cal, client=client, chunk_runs=2),
    )
    assert remote.completed_runs == 6
    for sensor in ("accelerometer", "gyroscope"):
        a, b = getattr(local, sensor), getattr(remote, sensor)
        _same(a.mse_eiv, b.mse_eiv)
        _same(a.crb, b.crb)
    inv = {"runs": 3, "duration": 10.0, "calibration_duration": 30.0, "seed": 2}
    local, remote = (
        mn.experiments.inversion(**inv, threads=2),
        mn.experiments.inversion(**inv, client=client, chunk_runs=2),
    )
    _same(local.accel_mse, remote.accel_mse)
    _same(local.gyro_squared_error_vs_time, remote.gyro_squared_error_vs_time)
    po = {
        "imus": ("mems",),
        "runs": 3,
        "duration": 40.0,
        "outage_start": 20.0,
        "outage_length": 10.0,
        "satellites": (0, 3),
    }
    local, remote = (
        mn.experiments.partial_outage(**po, threads=2),
        mn.experiments.partial_outage(**po, client=client, chunk_runs=1),
    )
    for label, result in local.scenarios.items():
        _same(result.mean["mems"], remote.scenarios[label].mean["mems"])


def test_the_adaptive_outage_study_is_bit_identical_and_decides_alike(client):
    """Looks computed in chunks on the workers hold the local runs, so
    every cell stops at the same look with the same decision."""
    study = {
        "grades": ("consumer", "tactical"),
        "outage_lengths": (10.0, 30.0),
        "visible_satellites": (0, 3),
        "outage_start": 30.0,
        "runs": 4,
        "max_runs": 16,
        "max_error_m": 3.0,
        "smooth": True,
        "seed": 2,
    }
    local = mn.experiments.outage_study(**study, threads=2)
    remote = mn.experiments.outage_study(**study, client=client, chunk_runs=3)
    assert remote.config["looks"] == local.config["looks"]
    for key, cell in local.cells.items():
        other = remote.cells[key]
        assert (cell.decision, cell.runs) == (other.decision, other.runs), key
        for field, values in cell.forward.items():
            _same(values, other.forward[field])
        for field, values in (cell.smoothed or {}).items():
            _same(values, other.smoothed[field])


def test_progress_and_interruption_keep_completed_chunks(client, navigation_local):
    calls = []

    def progress(done, total):
        calls.append((done, total))

    mn.experiments.navigation(**NAVIGATION, client=client, chunk_runs=2, progress=progress)
    assert calls[-1] == (5, 5) and [d for d, _ in calls] == sorted(d for d, _ in calls)

    def interrupt(done, total):
        raise KeyboardInterrupt

    cut = mn.experiments.navigation(**NAVIGATION, client=client, chunk_runs=1, progress=interrupt)
    assert cut.interrupted and 1 <= cut.completed_runs < 5
    # The completed runs are some of the set's runs, folded in run order.
    local_runs = navigation_local.position_error["mems"]
    kept = [
        next(i for i, row in enumerate(local_runs) if np.array_equal(_bits(row), _bits(r)))
        for r in cut.position_error["mems"]
    ]
    assert kept == sorted(kept)

    def failing(done, total):
        raise RuntimeError("callback failed")

    with pytest.raises(RuntimeError, match="callback failed"):
        mn.experiments.navigation(**NAVIGATION, client=client, chunk_runs=1, progress=failing)


def test_a_worker_killed_mid_run_changes_nothing(client):
    config = {**NAVIGATION, "duration": 120.0, "runs": 6, "smooth": False}
    local = mn.experiments.navigation(**config, threads=2)
    killed = []

    def kill_a_busy_worker(done, total):
        if killed:
            return
        busy = [w for w, keys in client.processing().items() if keys]
        if busy:
            pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    remote = mn.experiments.navigation(
        **config, client=client, chunk_runs=1, progress=kill_a_busy_worker
    )
    assert killed, "no worker was busy when the first chunk completed"
    assert remote.completed_runs == 6 and not remote.interrupted
    _same(local.mean["mems"], remote.mean["mems"])
    _same(local.position_error["ins"], remote.position_error["ins"])
    client.wait_for_workers(2, timeout=60)


def test_bad_chunking_and_threads_with_a_client(client):
    with pytest.raises(ValueError, match="chunk_runs"):
        mn.experiments.navigation(**NAVIGATION, client=client, chunk_runs=0)
    with pytest.raises(ValueError, match="threads"):
        mn.experiments.navigation(**NAVIGATION, client=client, threads=2)
    # A bad configuration is refused here, before any chunk is shipped.
    with pytest.raises(ValueError, match="n_satellites"):
        mn.experiments.navigation(runs=2, n_satellites=3, client=client)


def test_local_runs_do_not_import_dask():
    code = (
        "import sys, memsnav as mn\n"
        "mn.experiments.navigation(runs=1, duration=5.0, imus=('ins',))\n"
        "assert 'distributed' not in sys.modules and 'dask' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
