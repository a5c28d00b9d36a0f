"""Leaderboard: a results record per run (the Hub leaderboard template's shape plus our versioned fields),
rankings of comparable runs only, a static Space folder, and publishing it.

from talkdem.leaderboard import write_leaderboard
write_leaderboard(score_runs([Path("runs/a"), Path("runs/b")]), Path("board"))  # a static Space folder
"""

from talkdem.leaderboard.page import SUBMIT_STEPS, render_html
from talkdem.leaderboard.publish import (
    RESULTS_PATTERNS,
    SPACE_PATTERNS,
    check_space_folder,
    not_uploaded,
    publish_results,
    publish_space,
    results_upload_plan,
    space_upload_plan,
)
from talkdem.leaderboard.ranking import RANK_KEY, ComparableGroup, Standings, rank_records
from talkdem.leaderboard.records import RESULTS_SCHEMA, model_dtype, results_record, run_id
from talkdem.leaderboard.space import SPACE_FRONT_MATTER, read_results, results_path, write_leaderboard, write_space
from talkdem.leaderboard.validate import ResultsFileError, load_results_file, validate_record

__all__ = [
    "RANK_KEY",
    "RESULTS_PATTERNS",
    "RESULTS_SCHEMA",
    "SPACE_FRONT_MATTER",
    "SPACE_PATTERNS",
    "SUBMIT_STEPS",
    "ComparableGroup",
    "ResultsFileError",
    "Standings",
    "check_space_folder",
    "load_results_file",
    "model_dtype",
    "not_uploaded",
    "publish_results",
    "publish_space",
    "rank_records",
    "read_results",
    "render_html",
    "results_path",
    "results_record",
    "results_upload_plan",
    "run_id",
    "space_upload_plan",
    "validate_record",
    "write_leaderboard",
    "write_space",
]
