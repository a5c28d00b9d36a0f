"""TALK-Dem as a Hugging Face `evaluate` metric: a thin wrapper over `talkdem.metrics`.

All logic lives in the package (importable without evaluate); this module declares the features and
forwards to `talkdem.metrics.score_predictions`. Load it offline with
`evaluate.load("<checkout>/evaluate_talkdem")`.
"""

from __future__ import annotations

from typing import Any

import datasets
import evaluate

from talkdem.metrics import score_predictions
from talkdem.metrics.episodes import check_predictions
from talkdem.metrics.stats import BOOTSTRAP_SEED, check_resamples

_CITATION = """\
@inproceedings{talkdem2026,
  title     = {{TALK-Dem}: Benchmarking Robot Task Planning under Dementia-Associated Communication},
  author    = {Anonymous},
  booktitle = {Under review},
  year      = {2026}
}
"""

_DESCRIPTION = """\
TALK-Dem scores robot task plans for household instructions rewritten with five dementia-associated
communication patterns (referential imprecision, object substitution, empty speech, topic drift,
intrusion) at three intensity levels, plus the clean instruction of each task. Each plan (a list of
natural-language skills such as "find a mug", "pick up the mug", ..., "done") is executed in a symbolic
simulator following AI2-THOR / ALFRED rules; a plan succeeds when the ALFRED goal conditions hold.

Measurements (the paper's "Measurements" section and appendix): success rate per condition and per
pattern (mean over levels) with the change from clean and a two-sided paired t-test; clean-conditioned
retention |S_clean ∩ S_pattern,level| / |S_clean|; safety-relevant events introduced by a pattern (absent
under the clean instruction of the same task); plan length of jointly successful clean/pattern pairs;
automatic error types of failures that succeeded under clean; 95% bootstrap intervals over tasks.
"""

_KWARGS_DESCRIPTION = """\
Args:
    predictions (list of list of str): one plan per instruction, a list of skill strings. Strings outside
        the 214-skill vocabulary are not errors: they execute as failed steps.
    references (list of str): the instruction id of each plan, `<task_id>:clean:0` (or `<task_id>:clean`)
        or `<task_id>:<pattern>:<level>`. Plans are paired with instructions by id, not by position.
    retention (bool, default True): compute clean-conditioned retention; every pattern id then needs the
        clean id of its task among the references.
    bootstrap (int, default 1000): bootstrap resamples over tasks for the intervals: 0 (no intervals) or a
        whole number of at least 40 (a 95% percentile interval needs a resample in each 2.5% tail).
    seed (int): the bootstrap seed (fixed by default, so results are reproducible).
    questions (list of int, optional): clarification runs: the questions the planner asked in each episode,
        in the order of the references. With it the result has the clarification measures.
    without (list of list of str, optional): with `questions`, the plans of the same references made
        without clarification, for the success gained per question.
Returns:
    A flat dict. Rates are fractions in [0, 1]; None where undefined (e.g. no episodes of a condition).
    `success_rate/<key>` for `clean`, `<pattern>:<level>`, `<pattern>` (mean over levels), `average`;
    `sr_change/<pattern>` and `sr_change_p/<pattern>` (change from clean, paired t-test p-value);
    `retention/<key>` for `<pattern>:<level>`, `<pattern>`, `average`; `clean_successes`;
    `hazards/<category>/<pattern>`, `hazard_cases/<pattern>`, `hazard_cases`;
    `plan_length/<pattern or all>/{n,clean,transformed,delta,p}`; `errors/<type>`;
    `ci_low/<measure>`, `ci_high/<measure>`; `n_episodes`, `n_tasks`. With `questions`:
    `clarify/{sr,questions,help_rate,gain_per_question,retention}/<all, clean, pattern or pattern:level>`,
    `clarify/unneeded_questions`, `clarify/unneeded_per_clean_episode`; with `without` also
    `clarify/{gained,lost}_{when_asked,without_asking}/<group>`: paired episodes that succeeded only with
    (gained) or only without (lost) clarification, split by whether the episode asked a question.
Raises:
    ValueError (talkdem.metrics.ScoringInputError) naming the offending ids for: empty input, unknown
    or duplicate ids, plans that are not lists of strings (checked as given, before the features cast
    them: a nested step is refused, not turned into a string), predictions and references of different
    lengths, and (with retention) pattern ids without their clean twin. ValueError for a bootstrap
    count that is not 0 or a whole number of at least 40.
Examples:
    >>> import evaluate
    >>> from talkdem.tasks import get_task
    >>> metric = evaluate.load("evaluate_talkdem")
    >>> task_id = "trial_T20190908_111915_948834"  # put a book on a desk
    >>> plan = list(get_task(task_id).reference_plan)
    >>> plan
    ['find a book', 'pick up the book', 'find a desk', 'put down the book', 'done']
    >>> results = metric.compute(
    ...     predictions=[plan[:2] + ["done"], plan, plan],
    ...     references=[f"{task_id}:intrusion:3", f"{task_id}:clean:0", f"{task_id}:intrusion:1"],
    ...     bootstrap=0,
    ... )
    >>> results["success_rate/clean"], results["success_rate/intrusion:1"], results["success_rate/intrusion:3"]
    (1.0, 1.0, 0.0)
    >>> results["retention/intrusion"], results["errors/subgoal_omission"]
    (0.5, 1)
    >>> metric.compute(predictions=[plan], references=[f"{task_id}:intrusion:1"])
    Traceback (most recent call last):
    ...
    talkdem.metrics.episodes.ScoringInputError: retention needs the clean instruction of each task; these pattern ids have no clean twin (add `<task_id>:clean` plans, or call with retention=False to score without retention): trial_T20190908_111915_948834:intrusion:1
"""  # noqa: E501


@evaluate.utils.file_utils.add_start_docstrings(_DESCRIPTION, _KWARGS_DESCRIPTION)
class TalkDem(evaluate.Metric):  # type: ignore[misc]  # evaluate ships no type information
    """Success rate, clean-conditioned retention, hazards, plan length and error types of TALK-Dem plans."""

    def _info(self) -> evaluate.MetricInfo:
        return evaluate.MetricInfo(
            description=_DESCRIPTION,
            citation=_CITATION,
            inputs_description=_KWARGS_DESCRIPTION,
            features=datasets.Features(
                {
                    "predictions": datasets.Sequence(datasets.Value("string")),
                    "references": datasets.Value("string"),
                }
            ),
            homepage="https://github.com/talk-dem/talk-dem",
            codebase_urls=["https://github.com/talk-dem/talk-dem"],
            reference_urls=["https://github.com/talk-dem/talk-dem/blob/main/evaluate_talkdem/README.md"],
        )

    # `evaluate` casts the inputs through the features before `_compute` sees them, and Arrow turns a nested
    # step `[["find a box"]]` into the string "['find a box']": the inputs are checked as given, here.
    # (Each override needs a docstring: `evaluate` appends the inputs' description to it.)
    def compute(self, *, predictions: Any = None, references: Any = None, **kwargs: Any) -> Any:
        """Score the plans (see the module's inputs description); inputs are checked as given."""
        if predictions is not None or references is not None:
            check_predictions(predictions, references)
        if "bootstrap" in kwargs:
            check_resamples(kwargs["bootstrap"])
        return super().compute(predictions=predictions, references=references, **kwargs)

    def add_batch(self, *, predictions: Any = None, references: Any = None, **kwargs: Any) -> None:
        """Add plans and their ids for a later `compute()`; checked as given."""
        check_predictions(predictions, references)
        super().add_batch(predictions=predictions, references=references, **kwargs)

    def add(self, *, prediction: Any = None, reference: Any = None, **kwargs: Any) -> None:
        """Add one plan and its id for a later `compute()`; checked as given."""
        check_predictions([prediction], [reference])
        super().add(prediction=prediction, reference=reference, **kwargs)

    def _compute(
        self,
        predictions: list[list[str]],
        references: list[str],
        retention: bool = True,
        bootstrap: int = 1000,
        seed: int = BOOTSTRAP_SEED,
        questions: list[int] | None = None,
        without: list[list[str]] | None = None,
    ) -> dict[str, Any]:
        scores = score_predictions(predictions, references, retention=retention, bootstrap=bootstrap, seed=seed)
        out = dict(scores.flat())
        if questions is not None:
            out.update(_clarification(references, scores, questions, without))
        elif without is not None:
            raise ValueError("`without` pairs a clarification run: give `questions` too")
        return out


def _clarification(
    references: list[str], scores: Any, questions: list[int], without: list[list[str]] | None
) -> dict[str, Any]:
    """The clarification measures (NaN as None, like every other value)."""
    import math

    from talkdem.metrics import clarification_from_outcomes

    if len(questions) != len(references):
        raise ValueError(f"{len(questions)} question counts for {len(references)} references")
    successes = {e.instruction_id: e.success for e in scores.episodes}
    # Scoring keys each episode by its reference as given (`<task>:clean` stays short), so the references are the keys.
    counts = dict(zip(references, questions, strict=True))
    baseline = None
    if without is not None:
        check_predictions(without, references)
        plain = score_predictions(without, references, retention=False, bootstrap=0)
        baseline = {e.instruction_id: e.success for e in plain.episodes}
    found = clarification_from_outcomes(successes, counts, baseline)
    flat = found.flat() if found is not None else {}
    return {k: None if isinstance(v, float) and math.isnan(v) else v for k, v in flat.items()}
