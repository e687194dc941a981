"""The tightly coupled filter reproduces its own earlier output:
tests/data/tight-reference/tight_reference.npz was written by an earlier
commit (make_reference.py beside it says which, and why it was rewritten);
a fused multiply-add rounds once instead of twice, so a reference from the
portable kernels and a run on AVX2/FMA ones compare to 1e-9 relative, not
bitwise."""

from __future__ import annotations

from pathlib import Path

import numpy as np

REFERENCE_DIR = Path(__file__).parent / "data" / "tight-reference"


def test_forward_and_smoothed_solutions_match_the_stored_reference(reference_script) -> None:
    script = reference_script("tight-reference")
    now = script.solution_arrays()
    with np.load(REFERENCE_DIR / "tight_reference.npz") as stored:
        assert sorted(stored.files) == sorted(now)
        for name in stored.files:
            ref, new = stored[name], now[name]
            assert new.shape == ref.shape, name
            if name.endswith("position_ecef"):
                # Relative to the distance travelled, not to the Earth's
                # radius (1e-9 of 6.4e6 m would allow 6 mm).
                ref, new = ref - ref[0], new - ref[0]
            # Per element, with a floor of 1e-9 of the field's scale for
            # elements that cross zero (biases, clock offset).
            scale = np.max(np.abs(ref))
            assert scale > 0.0, name
            np.testing.assert_allclose(new, ref, rtol=1e-9, atol=1e-9 * scale, err_msg=name)
