"""Dementia-associated linguistic markers of TALK-Dem (and of user-supplied DementiaBank transcripts)."""

from builders.markers.measures import MARKERS, PIPELINE, mtld, text_markers
from builders.markers.report import DIRECTIONS, compute_cells, directions, run_markers

__all__ = ["DIRECTIONS", "MARKERS", "PIPELINE", "compute_cells", "directions", "mtld", "run_markers", "text_markers"]
