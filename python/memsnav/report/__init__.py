"""Self-contained HTML reports with their figures (PNG, SVG) and the curves
behind the figures (CSV)."""

from memsnav.report.document import Report, figure_to_csv

__all__ = ["Report", "figure_to_csv"]
