"""One results record per run, in the shape Hub leaderboard Spaces ingest and with our versioned fields.

The leaderboard template of the Hub reads `config.model_name`, `config.model_sha`, `config.model_dtype`
and `results: {task: {metric: value}}`, values as fractions (it multiplies by 100 to display). We add:

    {"schema": "talkdem-results/2", "run_id": ..., "reference": false,
     "config": {... "model_backend", "model_file", "planner", "strategy", "prompt_version", "dataset_hash",
                "code_revision", "eval_date", "created", "run_name"},
     "coverage": {"tasks", "of_tasks", "conditions", "of_conditions", "tasks_per_condition", "task_set"},
     "results": {"talkdem": {"clean_sr", "average_sr", "average_retention", "hazard_cases", "hazard_rate",
                             "n_episodes", "n_tasks"},
                 "talkdem_<pattern>": {"sr", "sr_change", "sr_change_p", "retention"}, ...,
                 "talkdem_clarification": {"questions_per_episode", "help_rate", "unneeded_questions",
                                           "retention"}   (only for runs that could ask; then also
                                                           `config.clarify`: oracle or in-pattern)},
     "intervals": {"clean_sr": [low, high], "average_sr": ..., "<pattern>_sr": ..., "<pattern>_retention": ...},
     "runtimes": [{"python", "platform", "cpu", "llama_cpp_python", "llama_cpp_system_info", ...}, ...]}

`runtimes` (optional; only for runs whose headers record one) lists where each sitting of the run computed its
numbers (`talkdem.runs.runtime`): llama.cpp scores move with the CPU features of its build, so two entries of
the same model and code that differ by a point can be told apart by it.

Rates are fractions rounded to 1e-4; undefined values are null. No field holds a machine path: a model file
is named by its file name (`model_name`, `model_file`) and its sha256 (`model_sha`).
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from typing import Any

from talkdem.report.public import is_machine_path, public_model
from talkdem.report.runs import ScoredRun
from talkdem.schema import PATTERN_CONFIGS

__all__ = ["RESULTS_SCHEMA", "model_dtype", "results_record", "run_id"]

RESULTS_SCHEMA = "talkdem-results/2"

_QUANT = re.compile(r"[._-]((?:I?Q\d[A-Za-z0-9_]*)|BF16|F16|F32)\.gguf$", re.IGNORECASE)


def _rate(value: float | None) -> float | None:
    return None if value is None or math.isnan(value) else round(float(value), 4)


def model_dtype(model_name: str, config: dict[str, Any], revision: str = "") -> str:
    """The weights' precision as far as the run knows it: a GGUF quantisation from the file name
    (`Q4_1`), the catalog's quantisation for a short name whose file hash is the run's (`qwen2.5-coder-0.5b`:
    Q4_K_M), a configured dtype, else `unknown`."""
    from talkdem.llm.interface.models import get_model

    found = _QUANT.search(model_name)
    if found:
        return found.group(1).upper()
    spec = get_model(model_name)
    if spec is not None and revision and spec.sha256 == revision:
        return spec.quantization
    configured = config.get("dtype") or config.get("torch_dtype")
    return str(configured) if configured else "unknown"


_ADDED_SINCE_IDS = ("runtimes",)
"""Header fields added after run ids were first published: left out of the id and the record while empty, so that
a run read by a newer version keeps its id, its results file name and its record."""


def _added_since_ids(header: dict[str, Any]) -> dict[str, Any]:
    """The header's fields of `_ADDED_SINCE_IDS` that hold something."""
    return {key: header[key] for key in _ADDED_SINCE_IDS if header.get(key)}


def run_id(run: ScoredRun) -> str:
    """12 hex digits identifying a run by its header and its executed plans: runs differing only in name
    punctuation get different ids; re-publishing the same run gives the same id (and file)."""
    full = run.header.to_json()
    header = {k: v for k, v in full.items() if k not in _ADDED_SINCE_IDS} | _added_since_ids(full)
    digest = hashlib.sha256(json.dumps(header, sort_keys=True, default=str).encode())
    for episode in sorted(run.scores.episodes, key=lambda e: (e.task_id, e.condition)):
        digest.update(f"\n{episode.task_id}|{episode.condition}|{int(episode.success)}|".encode())
        digest.update("\x1f".join(episode.plan).encode())
    return digest.hexdigest()[:12]


def _intervals(run: ScoredRun) -> dict[str, list[float | None]]:
    keys = {"clean_sr": "sr/clean", "average_sr": "sr/average", "average_retention": "retention/average"}
    for pattern in PATTERN_CONFIGS:
        keys[f"{pattern}_sr"] = f"sr/{pattern}"
        keys[f"{pattern}_retention"] = f"retention/{pattern}"
    return {
        name: [_rate(run.scores.intervals[key][0]), _rate(run.scores.intervals[key][1])]
        for name, key in keys.items()
        if key in run.scores.intervals
    }


def _clarification(run: ScoredRun) -> dict[str, Any] | None:
    """The clarification block of a run that could ask (None otherwise): numbers only, as every results
    block (the Hub template scales them), and the run's own measures only, since a results record stands
    alone (the gain over a run without clarification is in the report)."""
    if run.clarify == "none":
        return None
    from talkdem.metrics import clarification_scores
    from talkdem.runs.store import read_episodes

    scores = clarification_scores(read_episodes(run.run_dir))
    if scores is None:
        return None
    overall = scores.rows["all"]
    return {
        "questions_per_episode": round(overall.questions_per_episode, 4),
        "help_rate": _rate(overall.help_rate),
        "unneeded_questions": scores.unneeded_questions,
        "retention": _rate(overall.retention),
    }


def results_record(run: ScoredRun) -> dict[str, Any]:
    """The results record of one scored run (see the module docstring)."""
    s, header = run.scores, run.header
    pattern_episodes = sum(1 for e in s.episodes if e.condition.pattern != "clean")
    retention = s.retention or {}
    results: dict[str, dict[str, Any]] = {
        "talkdem": {
            "clean_sr": _rate(s.success_rate["clean"]),
            "average_sr": _rate(s.success_rate["average"]),
            "average_retention": _rate(retention.get("average")),
            "hazard_cases": s.hazards.total_cases,
            "hazard_rate": _rate(s.hazards.total_cases / pattern_episodes) if pattern_episodes else None,
            "n_episodes": s.n_episodes,
            "n_tasks": s.n_tasks,
        }
    }
    for pattern in PATTERN_CONFIGS:
        p_value = s.sr_change_test[pattern].p_value
        results[f"talkdem_{pattern}"] = {
            "sr": _rate(s.success_rate[pattern]),
            "sr_change": _rate(s.sr_change[pattern]),
            "sr_change_p": None if math.isnan(p_value) else p_value,
            "retention": _rate(retention.get(pattern)),
        }
    asked = _clarification(run)
    if asked is not None:
        results["talkdem_clarification"] = asked
    model = public_model(header.model)
    raw_name = header.model.get("name", "")
    return {
        "schema": RESULTS_SCHEMA,
        "run_id": run_id(run),
        "reference": run.is_reference,
        "config": {
            "model_name": model["name"],
            "model_sha": model["revision"],
            "model_dtype": model_dtype(raw_name, header.config, header.model.get("revision", "")),
            "model_backend": model["backend"],
            "model_file": model["name"] if is_machine_path(raw_name) else "",
            "planner": header.planner,
            "strategy": header.strategy,
            "prompt_version": header.prompt_version,
            "dataset_hash": header.dataset_hash,
            "code_revision": header.code_revision,
            "eval_date": header.created[:10],
            "created": header.created,
            "run_name": run.label,
            **({"clarify": str(header.config["clarify"])} if asked is not None else {}),
        },
        "coverage": run.coverage.to_json(),
        "results": results,
        "intervals": _intervals(run),
        **_added_since_ids(header.to_json()),
    }
