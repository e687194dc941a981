"""Figure 13 of the paper: the hybridization architecture, as memsnav
implements it (closed-loop tightly coupled error-state EKF)."""

from __future__ import annotations

from matplotlib.figure import Figure
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch

_WIDTH, _HEIGHT = 0.2, 0.22
# name -> (centre x, centre y, label), axes units.
_BOXES = {
    "imu": (0.12, 0.68, "IMU\n(raw MEMS outputs)"),
    "inversion": (0.40, 0.68, "calibration (LS, §3)\n+ inversion EKFs (§4)"),
    "ins": (0.68, 0.68, "strapdown INS\n(ECEF, §5)"),
    "out": (0.9, 0.68, "navigation\nsolution"),
    "gnss": (0.12, 0.2, "GNSS receiver:\npseudoranges, rates"),
    "ekf": (0.68, 0.2, "error-state EKF, 17 states:\nattitude, velocity, position,\nbiases, clock"),
}
_COLOUR = "#30507a"


def architecture_figure() -> Figure:
    """The block diagram of the tightly coupled, calibrated MEMS/GNSS system."""
    fig = Figure(figsize=(9, 4))
    ax = fig.add_axes((0, 0, 1, 0.9))
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_axis_off()
    fig.suptitle("Fig. 13: Hybridization architecture")
    for name, (x, y, label) in _BOXES.items():
        w = 0.14 if name == "out" else _WIDTH
        ax.add_patch(
            FancyBboxPatch(
                (x - w / 2, y - _HEIGHT / 2),
                w,
                _HEIGHT,
                boxstyle="round,pad=0.005",
                facecolor="#eef3fb",
                edgecolor=_COLOUR,
            )
        )
        ax.text(x, y, label, ha="center", va="center", fontsize=8.5)

    def arrow(start: tuple[float, float], end: tuple[float, float], label: str, dx: float) -> None:
        ax.add_patch(
            FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=12, color=_COLOUR)
        )
        if label:
            mid = ((start[0] + end[0]) / 2 + dx, (start[1] + end[1]) / 2 + 0.03)
            ax.text(*mid, label, fontsize=8, color=_COLOUR, ha="center")

    half_w, half_h = _WIDTH / 2, _HEIGHT / 2
    arrow((0.12 + half_w, 0.68), (0.40 - half_w, 0.68), "S_a, S_g", 0)
    arrow((0.40 + half_w, 0.68), (0.68 - half_w, 0.68), "Γ̂, Ω̂", 0)
    arrow((0.68 + half_w, 0.68), (0.9 - 0.07, 0.68), "", 0)
    arrow((0.12 + half_w, 0.2), (0.68 - half_w, 0.2), "measured ρ, ρ̇", 0)
    arrow((0.64, 0.68 - half_h), (0.64, 0.2 + half_h), "predicted\nρ, ρ̇", -0.08)
    arrow((0.72, 0.2 + half_h), (0.72, 0.68 - half_h), "corrections\n(closed loop)", 0.09)
    return fig
