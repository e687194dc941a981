"""The simulator reproduces its own earlier output: trajectory
generation with the exact IMU truth, IMU error synthesis and GNSS
simulation. tests/data/simulator-reference/simulator_reference.npz was
written by the code before the simulator speed-up (make_reference.py
beside it). Compared to 1e-12 relative per field; the positions relative
to the start, so the tolerance is not 1e-12 of the Earth's radius."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from shared_data import missing_is_an_error

REFERENCE_DIR = Path(__file__).parent / "data" / "simulator-reference"


def test_simulator_output_matches_the_stored_reference(reference_script) -> None:
    script = reference_script("simulator-reference")
    now = script.simulator_arrays()
    with np.load(REFERENCE_DIR / "simulator_reference.npz") as stored:
        expected = set(stored.files)
        if script.profile_path() is None:
            assert not missing_is_an_error(), "trajectories/Profile_1.csv not under the data root"
            expected = {k for k in expected if not k.startswith("profile1.")}
        assert sorted(now) == sorted(expected)
        for name in sorted(now):
            ref, new = stored[name], now[name]
            assert new.shape == ref.shape, name
            if name.endswith("sat_id"):
                np.testing.assert_array_equal(new, ref, err_msg=name)
                continue
            if name.endswith(".position_ecef"):
                ref, new = ref - ref[0], new - ref[0]
            scale = np.max(np.abs(ref))
            assert scale > 0.0, name
            # Per element, with a floor of 1e-12 of the field's scale for
            # elements that cross zero.
            np.testing.assert_allclose(new, ref, rtol=1e-12, atol=1e-12 * scale, err_msg=name)
