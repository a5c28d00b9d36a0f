"""A measured sample of the LLM path: a few benchmark tasks of every task type through `--generator llm`,
resumable, summarized for the card (`data/llm_sample/`).

    python -m builders.reporting.llm_sample --backend llamacpp --model qwen2.5-coder-1.5b --threads 1 \\
        --per-type 2 --out OUT            # generate (resumes from OUT/checkpoint.jsonl)
    python -m builders.reporting.llm_sample --out OUT --summarize data/llm_sample

The pick is stated, not tuned: the first `--per-type` benchmark tasks of each of the six task types, in the
order of `tasks/benchmark.jsonl`, interleaved by type. Each task is one unit, built as `talkdem build` builds
it (its clean control and fifteen variants, verified, regenerated up to twice) and appended to the checkpoint
with its generation log, so a killed run resumes where it stopped. `--summarize` writes `summary.json` and
`summary.md` from whatever units are finished, and says how many of how many.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from builders.build import build_unit_logged, read_checkpoint, tasks_digest
from builders.checkpoint import append_record, checkpoint_lock
from builders.generation.llm import LLMGenerator
from builders.reporting.llm_stats import card_section, generation_stats
from talkdem.schema import CLEAN, PATTERN_CONFIGS
from talkdem.tasks import Task, TaskSet, load_tasks

__all__ = ["CHECKPOINT", "examples", "main", "pick_tasks", "run_sample", "summarize"]

CHECKPOINT = "checkpoint.jsonl"
_SAMPLE_FORMAT = 1


def pick_tasks(per_type: int, tasks: Sequence[Task] | None = None) -> list[Task]:
    """The first `per_type` benchmark tasks of each task type, interleaved (the first of every type, then the
    second of every type, ...), task types in order of first appearance: a run stopped early still covers
    every type."""
    if per_type < 1:
        raise ValueError(f"--per-type must be a positive number of tasks, got {per_type}")
    pool = list(tasks) if tasks is not None else load_tasks(TaskSet.BENCHMARK)
    picked: dict[str, list[Task]] = {}
    for task in pool:
        chosen = picked.setdefault(task.task_type, [])
        if len(chosen) < per_type:
            chosen.append(task)
    return [chosen[i] for i in range(per_type) for chosen in picked.values() if i < len(chosen)]


def _header(generator: LLMGenerator, tasks: Sequence[Task], seed: int) -> dict[str, Any]:
    # `checkpoint: 1` makes it a build checkpoint for `read_checkpoint`; `sample` tells it from a build's.
    return {
        "checkpoint": 1,
        "sample": _SAMPLE_FORMAT,
        "generator": generator.name,
        "prompt_version": generator.prompt_version,
        "seed": seed,
        "tasks": [t.task_id for t in tasks],
        "tasks_sha256": tasks_digest(tasks, ()),
    }


def run_sample(generator: LLMGenerator, tasks: Sequence[Task], folder: Path, seed: int = 0) -> int:
    """Build the units not yet in `folder/checkpoint.jsonl`; returns how many were built now."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / CHECKPOINT
    header = _header(generator, tasks, seed)
    built = 0
    with checkpoint_lock(path):
        units = read_checkpoint(path, header)
        if path.stat().st_size == 0:
            append_record(path, header)
        for number, task in enumerate(tasks, start=1):
            key = f"benchmark:{task.task_id}"
            if key in units:
                continue
            rows, log = build_unit_logged(generator, task, seed)
            append_record(path, {"unit": key, "rows": rows, "log": log})
            built += 1
            seconds = log.get("usage", {}).get("seconds", 0.0)
            print(f"[{number}/{len(tasks)}] {task.task_id} {task.task_type}: {seconds:.0f} s", file=sys.stderr)
    return built


def examples(rows: Sequence[dict[str, Any]], per_pattern: int = 3) -> list[dict[str, Any]]:
    """Up to `per_pattern` rows per pattern (clean included), from different tasks, levels 1-3 in turn, passed and
    failed rows alike (the first ones in build order: no picking of good ones)."""
    picked: list[dict[str, Any]] = []
    for pattern in (CLEAN, *PATTERN_CONFIGS):
        these = [r for r in rows if r["pattern"] == pattern]
        tasks_seen: set[str] = set()
        for row in these:
            if len([p for p in picked if p["pattern"] == pattern]) >= per_pattern:
                break
            wanted_level = 0 if pattern == CLEAN else 1 + len(tasks_seen) % 3
            if row["task_id"] in tasks_seen or row["level"] != wanted_level:
                continue
            tasks_seen.add(row["task_id"])
            picked.append(
                {
                    key: row[key]
                    for key in (
                        "id",
                        "task_type",
                        "pattern",
                        "level",
                        "instruction",
                        "clean_instruction",
                        "verification",
                    )
                }
            )
    return picked


def summarize(folder: Path, target: Path, model_sha256: str = "", context: str = "") -> dict[str, Any]:
    """Write `target/summary.json` and `target/summary.md` from the finished units in `folder`."""
    path = folder / CHECKPOINT
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no sample checkpoint (run the sample first)")
    # Read, never repaired: the run may be appending right now, and a torn last line is its own to cut.
    lines = path.read_bytes().split(b"\n")[:-1]
    header = json.loads(lines[0])
    units: dict[str, list[dict[str, Any]]] = {}
    logs: dict[str, dict[str, Any]] = {}
    for line in lines[1:]:
        record = json.loads(line)
        units[record["unit"]] = record["rows"]
        if "log" in record:
            logs[record["unit"]] = record["log"]
    order = [f"benchmark:{task_id}" for task_id in header["tasks"]]
    done = [key for key in order if key in units]
    rows = [row for key in done for row in units[key]]
    stats = generation_stats(rows, [logs[key] for key in done if key in logs])
    sample = {
        "tasks_done": len(done),
        "tasks_planned": len(order),
        "rule": "the first tasks of each of the six task types in benchmark order, taken in turn by type",
        "generator": header["generator"],
        "model_sha256": model_sha256,
        "prompt_version": header["prompt_version"],
        "seed": header["seed"],
    }
    context = context or (
        f"Measured on a sample of {len(done)} of {len(order)} benchmark tasks ({sample['rule']}), "
        f"{len(rows)} utterances, generator `{header['generator']}`"
        + (f" (GGUF sha256 `{model_sha256[:16]}...`)" if model_sha256 else "")
        + f", prompts `{header['prompt_version']}`."
    )
    shown = examples(rows)
    summary = {"sample": sample, "context": context, "stats": stats, "examples": shown}
    target.mkdir(parents=True, exist_ok=True)
    (target / "summary.json").write_text(json.dumps(summary, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    markdown = card_section(stats, context, shown)
    (target / "summary.md").write_text(markdown + "\n", encoding="utf-8")
    return summary


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m builders.reporting.llm_sample", description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="sample folder (holds checkpoint.jsonl)")
    parser.add_argument("--backend", default="llamacpp", help="LLM backend (hf, llamacpp, vllm, openai)")
    parser.add_argument("--model", default="qwen2.5-coder-1.5b", help="model (catalog name, file or served name)")
    parser.add_argument("--base-url", help="server URL for --backend openai")
    parser.add_argument("--threads", type=int, help="CPU threads (llamacpp, hf)")
    parser.add_argument("--per-type", type=int, default=2, help="tasks per task type (default 2: 12 tasks)")
    parser.add_argument("--seed", type=int, default=0, help="build seed (default 0)")
    parser.add_argument("--text", action="store_true", help="plain-text answers even where JSON is supported")
    parser.add_argument("--summarize", type=Path, metavar="FOLDER", help="only write the summary into FOLDER")
    parser.add_argument("--model-sha256", default="", help="recorded in the summary (the GGUF's sha256)")
    parser.add_argument("--context", default="", help="the summary's sentence on what was run")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.summarize is not None:
            summary = summarize(args.out, args.summarize, args.model_sha256, args.context)
            print(json.dumps(summary["sample"], indent=2))
            return 0
        from talkdem.llm.interface.registry import load_model

        options: dict[str, Any] = {}
        if args.base_url:
            options["base_url"] = args.base_url
        if args.threads is not None:
            options["threads"] = args.threads
        backend = load_model(args.backend, args.model, **options)
        generator = LLMGenerator(backend, structured=not args.text)
        built = run_sample(generator, pick_tasks(args.per_type), args.out, args.seed)
        print(f"built {built} units into {args.out / CHECKPOINT}", file=sys.stderr)
        return 0
    except (ValueError, FileNotFoundError, ImportError) as error:
        print(f"llm_sample: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    raise SystemExit(main())
