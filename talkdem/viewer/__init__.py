"""See every episode: a static viewer of run directories, the paper's error-analysis sample, and error
types labelled by people against the automatic classifier.

    from talkdem.viewer import load_runs, write_viewer, sample_errors
    runs = load_runs([Path("results/paper/qwen2.5-coder-0.5b-care")])
    write_viewer(runs, Path("viewer"), sample=sample_errors(runs, 3, seed=0).to_json())
"""

from talkdem.viewer.build import VIEWER_SCHEMA, ViewerFiles, script_json, write_viewer
from talkdem.viewer.diff import word_diff
from talkdem.viewer.episodes import ViewedEpisode, ViewedRun, load_runs
from talkdem.viewer.labels import (
    LABELS_SCHEMA,
    TYPE_NAMES,
    Agreement,
    HumanLabel,
    agreement,
    cohen_kappa,
    label_tables,
    read_labels,
)
from talkdem.viewer.sample import SAMPLE_SCHEMA, ErrorSample, SampledFailure, read_sample, sample_errors

__all__ = [
    "LABELS_SCHEMA",
    "SAMPLE_SCHEMA",
    "TYPE_NAMES",
    "VIEWER_SCHEMA",
    "Agreement",
    "ErrorSample",
    "HumanLabel",
    "SampledFailure",
    "ViewedEpisode",
    "ViewedRun",
    "ViewerFiles",
    "agreement",
    "cohen_kappa",
    "label_tables",
    "load_runs",
    "read_labels",
    "read_sample",
    "sample_errors",
    "script_json",
    "word_diff",
    "write_viewer",
]
