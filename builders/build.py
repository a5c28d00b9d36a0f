"""Build the TALK-Dem dataset under `data/`: generate, verify, regenerate, write Parquet and the card.

The unit of work is one task: its clean control and fifteen pattern variants, each verified and
regenerated up to two more times when it fails (paper, appendix "Rule-Constrained Generation"). Finished
units are appended to a JSONL checkpoint (one line each, flushed), so a build killed at any
point, `kill -9` included, resumes where it stopped; every request has its own seed, so the resumed result
is byte-identical to an uninterrupted one. A truncated last line (a kill mid-write) is dropped with a warning.
The checkpoint's first line holds the build's settings (generator, prompt set, seed, `--limit`, the tasks'
sha256): only that build resumes from it and deletes it when done; any other build given the same file is
refused before anything in it is cut, reused or deleted.

Units are independent, so `workers` processes can build them side by side (the ranking model, on one thread,
is what takes the time); the parent alone appends to the checkpoint, and the dataset is written in task order,
so the files are the same bytes whatever the number of workers.
"""

from __future__ import annotations

import hashlib
import json
import re
import sys
import time
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from builders.checkpoint import append_record, checkpoint_lock
from builders.generation.ranking import CandidateRanker, Ranker, choose, load_ranker
from builders.interpretation import interpretation
from builders.verification import verify
from builders.verification.stats import MAX_ATTEMPTS, verification_stats
from talkdem.files import replace_file, replacing
from talkdem.paths import data_dir, repo_root
from talkdem.schema import CLEAN, LEVELS, MEMORY_BANK, PATTERN_CONFIGS, TASKS, data_files, features, split_name
from talkdem.seeds import PddlParams
from talkdem.serialization import to_jsonable
from talkdem.speech.base import GenerationRequest, Generator, derive_seed, generate_checked, get_generator
from talkdem.tasks import Task, TaskSet, load_tasks

__all__ = [
    "BuildResult",
    "CheckpointWarning",
    "build",
    "build_unit",
    "build_unit_logged",
    "checkpoint_header",
    "dataset_files",
    "default_checkpoint",
    "read_checkpoint",
    "tasks_digest",
]

CHECKPOINT_FORMAT = 1


class CheckpointWarning(UserWarning):
    """A checkpoint was repaired or discarded."""


@dataclass(frozen=True)
class BuildResult:
    folder: Path
    files: tuple[Path, ...]
    stats: dict[str, Any]
    resumed_units: int
    """Units taken from an existing checkpoint instead of being generated again."""


def default_checkpoint(generator: str, seed: int, limit: int | None = None) -> Path:
    """One path per build configuration: a `--limit` smoke build never touches the checkpoint of an
    interrupted full build of the same generator and seed."""
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", generator)  # e.g. `llm:/models/x.gguf`
    size = "" if limit is None else f"-limit{limit}"
    return repo_root() / ".cache" / "build" / f"checkpoint-{safe}-seed{seed}{size}.jsonl"


def check_output_folder(folder: Path) -> None:
    """Refuse to write a dataset into a folder that holds something else (`--out .` would overwrite the
    project's README.md): the folder must be new, empty, or hold a TALK-Dem dataset card."""
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"{folder}: exists and is not a folder")
    if not folder.is_dir() or not any(folder.iterdir()):
        return
    card = folder / "README.md"
    is_dataset = (
        card.is_file()
        and card.read_text(encoding="utf-8", errors="replace").startswith("---")
        and ("pretty_name: TALK-Dem" in card.read_text(encoding="utf-8", errors="replace"))
    )
    if not is_dataset:
        raise ValueError(
            f"{folder}: not empty and not a TALK-Dem dataset folder (its README.md is not the dataset card); "
            "refusing to write into it: choose a new or empty --out"
        )


def pddl_row(params: PddlParams) -> dict[str, Any]:
    """The task parameters as stored: a parameter the task type does not use is null, not an empty string."""
    return {name: (None if value == "" else value) for name, value in asdict(params).items()}


# --- one unit ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Candidate:
    seed: int
    text: str
    failures: tuple[str, ...] = ()
    """Failures the generator reports itself (an LLM's unparsable or echoed answer)."""
    utterance: bool = True
    """False when the generator gave no utterance at all (nothing for the verifier to check)."""


def _candidates(generator: Generator, batch: list[GenerationRequest]) -> list[list[_Candidate]]:
    """Candidates per request: several from a generator that draws them (rules), else its one checked output."""
    draw = getattr(generator, "generate_candidates", None)
    if draw is not None:
        drawn: list[list[tuple[int, str]]] = draw(batch)
        return [[_Candidate(seed, text) for seed, text in candidates] for candidates in drawn]
    outputs = generate_checked(generator, batch)
    return [
        [_Candidate(r.seed, out.text, tuple(out.failures), bool(out.utterance))]
        for r, out in zip(batch, outputs, strict=True)
    ]


def _check(request: GenerationRequest, candidate: _Candidate) -> dict[str, Any]:
    """The verifier's result, failed ahead of its checks by any failure the generator reported itself."""
    if candidate.utterance:
        check = verify(request.task, request.pattern, request.level, candidate.text)
    else:
        check = {"passed": False, "failed_checks": []}
    if candidate.failures:
        check = {"passed": False, "failed_checks": [*candidate.failures, *check["failed_checks"]]}
    return check


def _generate_verified(
    generator: Generator,
    requests: list[tuple[Task, str, int, str]],
    base_seed: int,
    ranker: CandidateRanker | None = None,
    log: list[dict[str, Any]] | None = None,
) -> list[tuple[str, dict[str, Any], int, dict[str, Any]]]:
    """(text, verification, seed, ranking) per request: of each request's candidates keep those that pass,
    the best-ranked of them (or the first without a ranker); regenerate when none passes, up to MAX_ATTEMPTS.

    A failure the generator reports itself (an LLM's unparsable or echoed answer) fails the candidate ahead of
    the verifier's checks. `log`, when given, receives one record per attempt (pattern, level, attempt, passed,
    failed checks): the reasons of attempts that were regenerated, which the rows do not keep."""
    results: list[tuple[str, dict[str, Any], int, dict[str, Any]] | None] = [None] * len(requests)
    pending = list(range(len(requests)))
    for attempt in range(1, MAX_ATTEMPTS + 1):
        batch = [
            GenerationRequest(
                task, pattern, level, clean, derive_seed(base_seed, task.task_id, pattern, level, attempt), attempt
            )
            for task, pattern, level, clean in (requests[i] for i in pending)
        ]
        drawn = _candidates(generator, batch)
        checks = [[_check(request, c) for c in candidates] for request, candidates in zip(batch, drawn, strict=True)]
        passing = [
            [(c.seed, c.text) for c, check in zip(candidates, found, strict=True) if check["passed"]]
            for candidates, found in zip(drawn, checks, strict=True)
        ]
        scores = _scores(ranker, passing)
        still = []
        for i, request, candidates, found, good, score in zip(
            pending, batch, drawn, checks, passing, scores, strict=True
        ):
            if good:
                best = choose(score, ranker.margin) if ranker is not None else 0
                seed, text = good[best]
                check = next(f for c, f in zip(candidates, found, strict=True) if c.seed == seed and c.text == text)
            else:
                seed, text, check = candidates[0].seed, candidates[0].text, found[0]
                still.append(i)
            if log is not None:
                log.append(
                    {
                        "pattern": request.pattern,
                        "level": request.level,
                        "attempt": attempt,
                        "passed": check["passed"],
                        "failed_checks": list(check["failed_checks"]),
                    }
                )
            ranked = ranker is not None and bool(good)
            ranking = {
                "score": score[best] if ranked else None,
                "model": ranker.model_id if ranker is not None and ranked else None,
                "candidates": len(candidates),
                "passed": len(good),
                # every passing candidate's score: the choice can be checked, or made by another rule, later
                "scored": [{"seed": s, "score": x} for (s, _), x in zip(good, score, strict=True)] if ranked else [],
            }
            results[i] = (text, {**check, "attempts": attempt}, seed, ranking)
        pending = still
        if not pending:
            break
    return [r for r in results if r is not None]


def _scores(ranker: CandidateRanker | None, passing: list[list[tuple[int, str]]]) -> list[list[float]]:
    """Each request's passing candidates scored in one batched call (ranked only where there is a choice)."""
    if ranker is None:
        return [[0.0] * len(good) for good in passing]
    candidates = [c for good in passing for c in good]
    flat = iter(ranker.score_candidates(candidates)) if candidates else iter(())
    return [[next(flat) for _ in good] for good in passing]


def build_unit(
    generator: Generator,
    task: Task,
    base_seed: int,
    patterns: Sequence[str] = PATTERN_CONFIGS,
    ranker: CandidateRanker | None = None,
) -> list[dict[str, Any]]:
    """The 16 rows of one task: its clean control, then each pattern at levels 1-3 (`patterns` narrows
    the patterns, for a quick check of a slow generator)."""
    return build_unit_logged(generator, task, base_seed, patterns, ranker)[0]


def build_unit_logged(
    generator: Generator,
    task: Task,
    base_seed: int,
    patterns: Sequence[str] = PATTERN_CONFIGS,
    ranker: CandidateRanker | None = None,
) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """`build_unit`'s rows and the unit's generation log: every attempt's outcome and, for a generator that
    reports its usage (the LLM generator), the unit's seconds, generations and tokens."""
    attempts: list[dict[str, Any]] = []
    usage = getattr(generator, "usage", None)
    before = usage() if usage is not None else None
    ((clean, clean_check, clean_seed, clean_rank),) = _generate_verified(
        generator, [(task, CLEAN, 0, "")], base_seed, ranker, attempts
    )
    variants = [(task, p, lvl, clean) for p in patterns for lvl in LEVELS]
    generated = [(CLEAN, 0, clean, clean_check, clean_seed, clean_rank)] + [
        (p, lvl, text, check, seed, rank)
        for (_, p, lvl, _), (text, check, seed, rank) in zip(
            variants, _generate_verified(generator, variants, base_seed, ranker, attempts), strict=True
        )
    ]
    log: dict[str, Any] = {"attempts": attempts}
    if usage is not None and before is not None:
        after = usage()
        log["usage"] = {key: round(after[key] - before.get(key, 0.0), 3) for key in after}
    rows = [
        {
            "id": f"{task.task_id}:{pattern}:{level}",
            "task_id": task.task_id,
            "task_type": task.task_type,
            "pattern": pattern,
            "level": level,
            "instruction": text,
            "clean_instruction": clean,
            "seed_instruction": task.instruction,
            "pddl_params": pddl_row(task.pddl_params),
            "floor_plan": task.floor_plan,
            "scene_objects": list(task.scene.scene_objects),
            "verification": check,
            "generator": generator.name,
            "prompt_version": generator.prompt_version,
            "seed": seed,
            "ranking": rank,
        }
        for pattern, level, text, check, seed, rank in generated
    ]
    return rows, log


# --- checkpoint -------------------------------------------------------------------------------------------------
def tasks_digest(benchmark: Sequence[Task], memory: Sequence[Task]) -> str:
    """sha256 over the tasks a build generates from (each task's stored record, in build order)."""
    digest = hashlib.sha256()
    for task in (*benchmark, *memory):
        digest.update(json.dumps(to_jsonable(task), ensure_ascii=False, sort_keys=True).encode() + b"\n")
    return digest.hexdigest()


def checkpoint_header(
    generator: Generator,
    seed: int,
    limit: int | None,
    benchmark: Sequence[Task],
    memory: Sequence[Task],
    rank_model: str | None = None,
    rank_margin: float | None = None,
) -> dict[str, Any]:
    """The settings of one build, the checkpoint's first line: a checkpoint is resumed only by the build
    that wrote it. A `--limit` smoke build, another seed, generator, prompt set or task file is another
    build (a smoke build that took a full build's checkpoint would reuse its units and then delete it)."""
    return {
        "checkpoint": CHECKPOINT_FORMAT,
        "generator": generator.name,
        "prompt_version": generator.prompt_version,
        "candidates": getattr(generator, "candidates", 1),
        "rank_model": rank_model,
        "rank_margin": rank_margin,
        "seed": seed,
        "limit": limit,
        "smoke": limit is not None,
        "tasks_sha256": tasks_digest(benchmark, memory),
    }


def _differences(found: dict[str, Any], wanted: dict[str, Any]) -> str:
    keys = [k for k in wanted if found.get(k, "(not recorded)") != wanted[k]]
    keys += [k for k in found if k not in wanted]
    return ", ".join(f"{k} {found.get(k, '(not recorded)')!r} there, {wanted.get(k)!r} now" for k in keys)


def read_checkpoint(
    path: Path, header: dict[str, Any], logs: dict[str, dict[str, Any]] | None = None
) -> dict[str, list[dict[str, Any]]]:
    """Finished units by key. A truncated last line is cut off (with a warning); a file that is not this
    build's checkpoint is refused, never deleted nor cut (it may be another build's hours of LLM generation).
    `logs`, when given, receives each unit's generation log (units written without one have none)."""
    if path.exists() and not path.is_file():
        raise ValueError(f"{path}: the checkpoint path is not a file")
    if not path.is_file() or path.stat().st_size == 0:
        return {}
    with path.open("rb") as handle:
        first = handle.readline()
    try:
        found_header = json.loads(first)
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError):
        found_header = None
    if not isinstance(found_header, dict) or found_header.get("checkpoint") != CHECKPOINT_FORMAT:
        raise ValueError(f"{path}: exists and is not a TALK-Dem build checkpoint; refusing to overwrite it")
    if first.endswith(b"\n") and found_header != header:
        # Checked before anything is repaired: another build's checkpoint is left byte for byte as it is.
        raise ValueError(
            f"{path}: checkpoint of another build ({_differences(found_header, header)}); resume it with its "
            "own settings, or give --checkpoint another file (nothing was changed)"
        )
    raw = path.read_bytes()
    lines = raw.split(b"\n")
    complete, tail = lines[:-1], lines[-1]  # `tail` is b"" when the file ends with a newline
    if tail:
        warnings.warn(
            f"{path}: the last checkpoint line is truncated ({len(tail)} bytes, a build killed mid-write); "
            "dropping it and redoing that unit",
            CheckpointWarning,
            stacklevel=2,
        )
        with path.open("r+b") as handle:
            handle.truncate(len(raw) - len(tail))
    if not complete:
        return {}
    units: dict[str, list[dict[str, Any]]] = {}
    for number, line in enumerate(complete[1:], start=2):
        try:
            record = json.loads(line)
        except json.JSONDecodeError as exc:
            raise ValueError(
                f"{path}, line {number}: corrupt checkpoint line ({exc}); delete the file to rebuild"
            ) from exc
        units[record["unit"]] = record["rows"]
        if logs is not None and "log" in record:
            logs[record["unit"]] = record["log"]
    return units


# --- writing ---------------------------------------------------------------------------------------------------------
def _write_parquet(rows: Sequence[dict[str, Any]], features: Any, path: Path) -> Path:
    import pyarrow as pa
    import pyarrow.parquet as pq

    # encode_example turns class-label names into their integer ids, as `datasets` stores them.
    table = pa.Table.from_pylist([features.encode_example(row) for row in rows], schema=features.arrow_schema)
    path.parent.mkdir(parents=True, exist_ok=True)
    with replacing(path) as scratch:
        pq.write_table(table, scratch, compression="zstd", row_group_size=len(rows) or 1)
    return path


def _write_text(path: Path, text: str) -> Path:
    replace_file(path, text)
    return path


def _task_row(task: Task) -> dict[str, Any]:
    params = task.pddl_params
    return {
        "task_id": task.task_id,
        "task_set": task.task_set,
        "task_type": task.task_type,
        "task_name": task.task_name,
        "floor_plan": task.floor_plan,
        "seed_instruction": task.instruction,
        "interpretation": interpretation(task.task_type, params),
        "pddl_params": pddl_row(params),
        "scene_objects": list(task.scene.scene_objects),
        "reference_plan": list(task.reference_plan),
    }


def write_dataset(
    folder: Path,
    benchmark: Sequence[Task],
    memory: Sequence[Task],
    units: dict[str, list[dict[str, Any]]],
    build_info: dict[str, Any],
    generation: dict[str, Any] | None = None,
) -> tuple[list[Path], dict[str, Any]]:
    from builders.card import write_card

    bench_rows = [row for task in benchmark for row in units[f"benchmark:{task.task_id}"]]
    instruction_features = features("instruction")
    written = []
    # One file per split, at the path the schema declares (the card and the loader read the same layout).
    for config, condition_rows in [
        (CLEAN, {"test": [r for r in bench_rows if r["pattern"] == CLEAN]}),
        *(
            (p, {split_name(lvl): [r for r in bench_rows if (r["pattern"], r["level"]) == (p, lvl)] for lvl in LEVELS})
            for p in PATTERN_CONFIGS
        ),
    ]:
        for split, (relative,) in data_files(config).items():
            written.append(_write_parquet(condition_rows[split], instruction_features, folder / relative))
    clean_rows = [r for r in bench_rows if r["pattern"] == CLEAN]

    tasks_by_id = {t.task_id: t for t in memory}
    memory_rows = []
    for task in memory:
        for row in units[f"memory:{task.task_id}"]:
            spec = tasks_by_id[row["task_id"]]
            memory_rows.append(
                {
                    **row,
                    "interpretation": interpretation(spec.task_type, spec.pddl_params),
                    "reference_plan": list(spec.reference_plan),
                }
            )
    ((memory_file,),) = data_files(MEMORY_BANK).values()
    written.append(_write_parquet(memory_rows, features("memory_bank"), folder / memory_file))
    task_files = data_files(TASKS)
    for name, tasks in (("benchmark", benchmark), ("memory", memory)):
        (relative,) = task_files[name]
        written.append(_write_parquet([_task_row(t) for t in tasks], features("task"), folder / relative))

    stats = {
        "build": build_info,
        "benchmark": verification_stats(bench_rows),
        "benchmark_clean": verification_stats([{**r, "pattern": "x"} for r in clean_rows]),
        "memory_bank": verification_stats(memory_rows),
        "counts": {
            "tasks": len(benchmark),
            "instructions": len(bench_rows),
            "memory_tasks": len(memory),
            "memory_items": len(memory_rows),
        },
    }
    if generation is not None:
        stats["generation"] = generation
    written.append(_write_text(folder / "build_stats.json", json.dumps(stats, indent=2) + "\n"))
    written += write_card(folder, stats)
    return written, stats


def dataset_files(folder: Path) -> dict[str, bytes]:
    """Everything a build writes (Parquet, card, statistics), by path relative to `folder`."""
    names = [*folder.glob("*/*.parquet"), folder / "README.md", folder / "build_stats.json"]
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(names) if p.is_file()}


# --- the build ---------------------------------------------------------------------------------------------------
def build(
    folder: Path | None = None,
    *,
    generator: str | Generator = "rules",
    seed: int = 0,
    checkpoint: Path | None = None,
    tasks_folder: Path | None = None,
    progress: bool = True,
    throttle: float = 0.0,
    limit: int | None = None,
    candidates: int | None = None,
    rank_model: str | None = None,
    rank_margin: float = 0.0,
    workers: int = 1,
) -> BuildResult:
    """Generate, verify and write the whole dataset into `folder` (default `data/`).

    `candidates` sets how many candidates a generator that draws them (`rules`) draws per request (default
    its own, 4); `rank_model` names the llama.cpp model that ranks the verified ones (None: the first that
    passes is kept, no model is loaded), and `rank_margin` how far below the best score (nats per token) the
    kept one may be (`builders.generation.ranking.choose`; 0 keeps the best).

    `tasks_folder` is where `tasks/benchmark.jsonl` and `tasks/memory.jsonl` are read (default `data/`).
    `throttle` sleeps that many seconds after each unit (used by the kill-and-resume test).
    `limit`, if given, builds only the first `limit` benchmark tasks and memory tasks (a smoke build of a
    slow generator); the dataset written is then partial and says so in its statistics.
    `workers` > 1 builds units in that many processes, each with its own generator and ranking model; it
    needs the generator by name (an LLM generator object holds a loaded model or a server connection, which
    a process cannot share).
    """
    if workers < 1:
        raise ValueError(f"workers must be a positive number, got {workers}")
    if workers > 1 and not isinstance(generator, str):
        raise ValueError(
            f"workers={workers} needs the generator by name (e.g. 'rules'); a generator object is built in one process"
        )
    gen = get_generator(generator) if isinstance(generator, str) else generator
    if candidates is not None:
        if not hasattr(gen, "candidates"):
            raise ValueError(f"generator '{gen.name}' ({gen.prompt_version}) draws one utterance per request")
        if candidates < 1:
            raise ValueError(f"candidates must be a positive number, got {candidates}")
        gen.candidates = candidates
    source = Path(tasks_folder) if tasks_folder else data_dir()
    benchmark = load_tasks(TaskSet.BENCHMARK, source)
    memory = load_tasks(TaskSet.MEMORY, source)
    if limit is not None:
        if limit < 1:
            raise ValueError(f"limit must be a positive number of tasks, got {limit}")
        benchmark, memory = benchmark[:limit], memory[:limit]
    folder = Path(folder) if folder else data_dir()
    check_output_folder(folder)
    path = checkpoint or default_checkpoint(gen.name, seed, limit)
    ranker = load_ranker(rank_model, margin=rank_margin)
    pool = _WorkerSettings(str(generator), candidates, rank_model, rank_margin, workers) if workers > 1 else None
    with checkpoint_lock(path):
        return _build_locked(gen, folder, benchmark, memory, path, seed, limit, progress, throttle, ranker, pool)


@dataclass(frozen=True)
class _WorkerSettings:
    """What a worker process needs to build units exactly as the parent would."""

    generator: str
    candidates: int | None
    rank_model: str | None
    rank_margin: float
    workers: int


_worker: tuple[Generator, Ranker | None, bool] | None = None
"""The generator, ranker and whether to log, of this worker process (set once by `_start_worker`)."""


def _start_worker(settings: _WorkerSettings) -> None:
    global _worker
    gen = get_generator(settings.generator)
    if settings.candidates is not None:
        gen.candidates = settings.candidates  # type: ignore[attr-defined]
    _worker = (
        gen,
        load_ranker(settings.rank_model, margin=settings.rank_margin),
        getattr(gen, "usage", None) is not None,
    )


_Built = tuple[str, list[dict[str, Any]], dict[str, Any] | None]
"""A finished unit: its key, its rows and its generation log (None where the generator keeps none)."""


def _one_unit(gen: Generator, ranker: CandidateRanker | None, logged: bool, key: str, task: Task, seed: int) -> _Built:
    if logged:
        rows, log = build_unit_logged(gen, task, seed, ranker=ranker)
        return key, rows, log
    return key, build_unit(gen, task, seed, ranker=ranker), None


def _worker_unit(job: tuple[str, Task, int]) -> _Built:
    assert _worker is not None, "the worker was not started"
    return _one_unit(*_worker, *job)


def _built_units(
    todo: Sequence[tuple[str, Task]],
    gen: Generator,
    seed: int,
    ranker: CandidateRanker | None,
    logged: bool,
    pool: _WorkerSettings | None,
) -> Iterator[_Built]:
    """Each unit built, in task order in this process, else in the order the workers finish."""
    if pool is None:
        for key, task in todo:
            yield _one_unit(gen, ranker, logged, key, task, seed)
        return
    import multiprocessing

    # spawn, not fork: a forked llama.cpp model (or any threaded library) is not safe to use in the child.
    context = multiprocessing.get_context("spawn")
    # Leaving the block (all done, or stopped by Ctrl-C or SIGTERM) terminates the workers at once: a unit they
    # had not finished was never written, and the next run builds it again.
    with context.Pool(pool.workers, _start_worker, (pool,)) as workers:
        yield from workers.imap_unordered(_worker_unit, [(key, task, seed) for key, task in todo])


def _build_locked(
    gen: Generator,
    folder: Path,
    benchmark: Sequence[Task],
    memory: Sequence[Task],
    path: Path,
    seed: int,
    limit: int | None,
    progress: bool,
    throttle: float,
    ranker: CandidateRanker | None = None,
    pool: _WorkerSettings | None = None,
) -> BuildResult:
    from tqdm import tqdm

    todo = [(f"benchmark:{t.task_id}", t) for t in benchmark] + [(f"memory:{t.task_id}", t) for t in memory]
    rank_id = ranker.model_id if ranker is not None else None
    header = checkpoint_header(gen, seed, limit, benchmark, memory, rank_id, ranker.margin if ranker else None)
    # Only a generator that reports its usage (the LLM generator) gets the attempt log and costs in its
    # statistics: the rules build's files stay byte-identical whatever the machine's speed.
    logged = getattr(gen, "usage", None) is not None
    logs: dict[str, dict[str, Any]] = {}
    units = read_checkpoint(path, header, logs)
    resumed = sum(1 for key, _ in todo if key in units)
    if path.stat().st_size == 0:  # the lock created it empty
        append_record(path, header)

    bar = tqdm(
        total=len(todo), initial=resumed, desc="talkdem build", unit="task", disable=not progress, file=sys.stderr
    )
    remaining = [(key, task) for key, task in todo if key not in units]
    for key, rows, log in _built_units(remaining, gen, seed, ranker, logged, pool):
        if log is not None:
            append_record(path, {"unit": key, "rows": rows, "log": log})
            logs[key] = log
        else:
            append_record(path, {"unit": key, "rows": rows})
        units[key] = rows
        bar.update(1)
        if throttle:
            time.sleep(throttle)
    bar.close()

    build_info = {
        "generator": gen.name,
        "prompt_version": gen.prompt_version,
        "seed": seed,
        "candidates": getattr(gen, "candidates", 1),
        "rank_model": rank_id,
        "rank_margin": ranker.margin if ranker is not None else None,
    }
    generation = None
    if logged:
        from builders.reporting.llm_stats import generation_stats

        keys = [f"benchmark:{t.task_id}" for t in benchmark]
        generation = generation_stats([r for k in keys for r in units[k]], [logs[k] for k in keys if k in logs])
    files, stats = write_dataset(folder, benchmark, memory, units, build_info, generation)
    path.unlink()
    return BuildResult(folder, tuple(files), stats, resumed)
