"""The TALK-Dem measurements: execute plans in the simulator, then success rate, clean-conditioned
retention, introduced hazards, plan length, paired tests, bootstrap intervals and error types.

Importing this package loads numpy and the simulator only: never evaluate, datasets or torch (scipy is
imported inside the tests that need it).

    from talkdem.metrics import score_plans
    scores = score_plans({"<task_id>:clean:0": ["find a mug", ...], ...})
    scores.success_rate["clean"], scores.retention["average"], scores.flat()
"""

from talkdem.metrics.clarification import (
    CLARIFICATION_GROUPS,
    ClarificationRow,
    ClarificationScores,
    asked_questions,
    clarification_from_outcomes,
    clarification_scores,
    used_clarification,
)
from talkdem.metrics.episodes import (
    EpisodeResult,
    ScoringInputError,
    execute_plans,
    instruction_index,
    pair_predictions,
    plan_length,
    results_from_run,
    split_instruction_id,
)
from talkdem.metrics.errors import ERROR_LABELS, ErrorClassification, ErrorType, classify_error, required_state
from talkdem.metrics.hazards import HAZARD_CATEGORIES, HazardCounts, introduced_hazards
from talkdem.metrics.length import PlanLengthRow, plan_length_pairs
from talkdem.metrics.rates import MEASURES, condition_key, measures, outcome_matrix, task_retention
from talkdem.metrics.scores import (
    ClassifiedError,
    Scores,
    compare_retention,
    compute_scores,
    error_cases,
    score_plans,
    score_predictions,
    score_run,
)
from talkdem.metrics.stats import (
    BOOTSTRAP_SEED,
    TestResult,
    bootstrap_ci,
    clustered_mean_test,
    detectable_difference,
    paired_ttest,
    stars,
)
from talkdem.schema import CONDITIONS

__all__ = [
    "BOOTSTRAP_SEED",
    "CLARIFICATION_GROUPS",
    "CONDITIONS",
    "ERROR_LABELS",
    "HAZARD_CATEGORIES",
    "MEASURES",
    "ClarificationRow",
    "ClarificationScores",
    "ClassifiedError",
    "EpisodeResult",
    "ErrorClassification",
    "ErrorType",
    "HazardCounts",
    "PlanLengthRow",
    "Scores",
    "ScoringInputError",
    "TestResult",
    "asked_questions",
    "bootstrap_ci",
    "clarification_from_outcomes",
    "clarification_scores",
    "classify_error",
    "clustered_mean_test",
    "compare_retention",
    "compute_scores",
    "condition_key",
    "detectable_difference",
    "error_cases",
    "execute_plans",
    "instruction_index",
    "introduced_hazards",
    "measures",
    "outcome_matrix",
    "pair_predictions",
    "paired_ttest",
    "plan_length",
    "plan_length_pairs",
    "required_state",
    "results_from_run",
    "score_plans",
    "score_predictions",
    "score_run",
    "split_instruction_id",
    "stars",
    "task_retention",
    "used_clarification",
]
