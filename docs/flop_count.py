"""The reference workload and the floating-point count of
docs/results/performance.md, written from their sources:
``python docs/flop_count.py [--write]``.

The workload is the Python benchmark's constants (benches/python/
bench_tight.py, which the Rust suites share: tests/test_performance_doc.py
checks); the count is design arithmetic on the number of non-zeros of Φ
for 17 states that crates/memsnav-core/tests/phi_structure.rs counts from
the code (docs/data/phi_structure.json) and on the per-part estimates
below."""

from __future__ import annotations

import re
import sys
from pathlib import Path

from figures import figure
from marked_block import replace_block

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "results" / "performance.md"
WORKLOAD = ("<!-- workload:begin -->", "<!-- workload:end -->")
FLOPS = ("<!-- flops:begin -->", "<!-- flops:end -->")

STATES = 17
MECHANIZATION_FLOPS = 450
"""``ins::step``: three 3×3 products, Rodrigues, orthonormalisation, two J2
gravity evaluations, Heun; plus 2 sin/cos, 3 sqrt (estimated)."""
PHI_BLOCK_FLOPS = 100
"""Φ's blocks Ĉ Δt, Γ Δt, Ĉ f̂ Δt (estimated)."""
JOSEPH_UPDATE_FLOPS = 2_200
"""One scalar Joseph update: P hᵀ, three rank-one corrections,
symmetrisation (estimated)."""
RANGE_PREDICTION_FLOPS = 1_600
"""The range and rate predictions of one GNSS epoch (estimated: what the
page's earlier hand count of 28 000 flops per second left after the 12
updates)."""
SYMMETRIC_COVARIANCE_FLOPS = 2_600
"""The covariance propagation with symmetry exploited fully (design note)."""


def workload() -> dict[str, float]:
    """The benchmark's constants and what follows from them."""
    source = (ROOT / "benches" / "python" / "bench_tight.py").read_text()

    def constant(name: str) -> float:
        return float(re.search(rf"^{name} = ([\d.]+)$", source, re.M).group(1))

    duration_s, rate_hz = constant("DURATION_S"), constant("RATE_HZ")
    satellites = int(constant("N_SATELLITES"))
    return {
        "duration_s": duration_s,
        "rate_hz": rate_hz,
        "imu_epochs": int(duration_s * rate_hz) + 1,  # both ends sampled
        "gnss_hz": 1.0,
        "satellites": satellites,
        "updates_per_epoch": 2 * satellites,  # a pseudorange and a rate each
        "gnss_epochs": int(duration_s * 1.0),
        "states": STATES,
        "seed": int(constant("SEED")),
    }


def flops() -> dict[str, int]:
    """Flops per IMU epoch by part, and the totals."""
    w = workload()
    one_product = int(figure("phi_structure.non_zeros_17_states")) * STATES * 2
    covariance = 2 * one_product + STATES  # Q adds its diagonal
    per_second = w["gnss_hz"] * (
        w["updates_per_epoch"] * JOSEPH_UPDATE_FLOPS + RANGE_PREDICTION_FLOPS
    )
    amortised = per_second / w["rate_hz"]
    total = MECHANIZATION_FLOPS + PHI_BLOCK_FLOPS + covariance + amortised
    return {
        "one_product": one_product,
        "covariance": covariance,
        "per_second": int(per_second),
        "amortised": int(amortised),
        "total": int(total),
        "symmetric_total": int(total - covariance + SYMMETRIC_COVARIANCE_FLOPS),
    }


def _n(value: float, step: int = 1) -> str:
    """A count rounded to ``step``, thousands apart: 3 960, 60 001."""
    return f"{round(value / step) * step:,}".replace(",", " ")


def render_workload() -> str:
    w = workload()
    return "\n".join(
        [
            WORKLOAD[0],
            f"{w['duration_s']:.0f} s random land-vehicle trajectory (Toulouse) at "
            f"{w['rate_hz']:.0f} Hz = {_n(w['imu_epochs'])} IMU",
            f"epochs, the paper's MEMS IMU (`paper-mems`), {w['gnss_hz']:.0f} Hz GNSS with "
            f"{w['satellites']} satellites",
            f"(pseudorange + pseudorange rate: {w['updates_per_epoch']} scalar updates per "
            f"epoch, {_n(w['gnss_epochs'])} epochs),",
            f"{w['states']}-state closed-loop error-state EKF tuned from the IMU spec "
            f"(`memsnav_benches::SEED` = {w['seed']}).",
            WORKLOAD[1],
        ]
    )


def render_flops() -> str:
    f, w = flops(), workload()
    non_zeros = f["one_product"] // (2 * STATES)
    return "\n".join(
        [
            FLOPS[0],
            "| part | count | flops per IMU epoch |",
            "|---|---|---|",
            "| mechanization (`ins::step`): three 3×3 products, Rodrigues, "
            "orthonormalisation, two J2 gravity evaluations, Heun; plus 2 sin/cos, 3 sqrt "
            f"| ≈ {_n(MECHANIZATION_FLOPS)} | {_n(MECHANIZATION_FLOPS)} |",
            f"| Φ blocks (Ĉ Δt, Γ Δt, Ĉ f̂ Δt) | ≈ {_n(PHI_BLOCK_FLOPS)} | {_n(PHI_BLOCK_FLOPS)} |",
            f"| covariance, one product M Φᵀ: {non_zeros} column terms × {STATES} rows × 2 "
            f"| {_n(f['one_product'])} | |",
            f"| covariance, two products + Q | | ≈ {_n(f['covariance'], 10)} |",
            "| scalar Joseph update: P hᵀ, three rank-one corrections, symmetrisation "
            f"≈ {_n(JOSEPH_UPDATE_FLOPS)} flops; {w['updates_per_epoch']} per GNSS epoch + "
            f"range predictions ≈ {_n(f['per_second'], 1000)} per second | | "
            f"≈ {_n(f['amortised'], 10)} (amortised over {w['rate_hz']:.0f} IMU epochs) |",
            f"| **total** | | **≈ {_n(f['total'], 100)}** |",
            "",
            "With symmetry exploited fully the covariance could drop to "
            f"≈ {_n(SYMMETRIC_COVARIANCE_FLOPS)} flops",
            f"(design note), ≈ {_n(f['symmetric_total'], 100)} in total.",
            FLOPS[1],
        ]
    )


def main(argv: list[str]) -> None:
    if argv == ["--write"]:
        replace_block(PAGE, *WORKLOAD, render_workload())
        replace_block(PAGE, *FLOPS, render_flops())
    else:
        print(render_workload(), render_flops(), sep="\n\n")


if __name__ == "__main__":
    main(sys.argv[1:])
