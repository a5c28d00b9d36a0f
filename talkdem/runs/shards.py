"""One run over many machines: `talkdem run --shard I/N` runs a deterministic slice of the episodes, and
`merge_runs` joins the shard directories into one run directory that `report` and `leaderboard` read like any
other.

`split_run` turns a run already under way into shard directories, each seeded with the finished episodes
that belong to it (optionally for a larger selection: more conditions or tasks), so that the rest can go on
on several machines and be merged back; nothing finished is run twice.

The slice: the run's episode ids sorted, every N-th from the I-th (so each shard gets every task type and
condition in about equal share); an episode belongs to exactly one shard whatever the machine. Merging refuses
shards of different runs (the keys that change what an outcome means, and the selection), shards of different
splits, the same shard twice, and an episode present in two shards; it names the missing episodes of an
incomplete set.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from talkdem.files import replace_file
from talkdem.runs.episode_files import PACKED_EPISODES_FILE, episodes_file, pack_bytes
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.runtime import add_runtime
from talkdem.runs.spec import MERGE_KEYS, differences
from talkdem.runs.store import EPISODES_FILE, read_episodes, read_header, run_lock, write_header

if TYPE_CHECKING:
    from talkdem.instructions import Instruction

__all__ = [
    "MERGE_KEYS",
    "MergeResult",
    "Shard",
    "SplitShard",
    "merge_runs",
    "parse_shard",
    "rewrite_episodes",
    "shard_folder",
    "shard_of",
    "split_run",
]


@dataclass(frozen=True)
class Shard:
    index: int
    """1-based."""
    count: int

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"


def parse_shard(text: str) -> Shard:
    """`I/N` with 1 <= I <= N."""
    parts = text.split("/")
    try:
        index, count = (int(p) for p in parts) if len(parts) == 2 else (0, 0)
    except ValueError:
        index = count = 0
    if not 1 <= index <= count:
        raise ValueError(f"shard '{text}' must be I/N with 1 <= I <= N, e.g. 1/4")
    return Shard(index, count)


def shard_of(instructions: Sequence[Instruction], shard: Shard) -> list[Instruction]:
    """The shard's episodes, in the selection's order: sorted ids, every `count`-th from the `index`-th."""
    ids = sorted(i.id for i in instructions)
    mine = set(ids[shard.index - 1 :: shard.count])
    return [i for i in instructions if i.id in mine]


def rewrite_episodes(run_dir: Path, episodes: Sequence[EpisodeRecord]) -> None:
    """Replace the run's episodes atomically (a crash leaves the old file or the new one, never half), in the
    form they are in: a packed run stays packed, so no second episodes file appears beside it."""
    data = "".join(episode.to_line() + "\n" for episode in episodes).encode("utf-8")
    found = episodes_file(run_dir)
    if found is not None and found.name == PACKED_EPISODES_FILE:
        replace_file(found, pack_bytes(data))
    else:
        replace_file(run_dir / EPISODES_FILE, data)


@dataclass(frozen=True)
class MergeResult:
    out: Path
    episodes: int
    missing: tuple[str, ...]


def _selection(header: RunHeader) -> list[str]:
    """The episode ids of the whole (unsharded) run the header describes."""
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    conditions = header.config.get("conditions")
    limit = header.config.get("limit")
    text = ",".join(conditions) if isinstance(conditions, list) else None
    return [i.id for i in select_episodes(parse_conditions(text), limit if isinstance(limit, int) else None)]


def merge_runs(out: Path, shard_dirs: Sequence[Path], allow_incomplete: bool = False) -> MergeResult:
    """Join shard run directories into `out` (new or empty), episodes in the selection's order."""
    if len(shard_dirs) < 1:
        raise ValueError("name at least one shard directory")
    if len({d.resolve() for d in shard_dirs}) != len(shard_dirs):
        raise ValueError("a shard directory is named twice")
    headers = [read_header(d) for d in shard_dirs]
    first = headers[0]
    for directory, header in zip(shard_dirs[1:], headers[1:], strict=True):
        clashes = differences(first, header, MERGE_KEYS)
        if clashes:
            raise ValueError(f"{directory} is not a shard of the same run as {shard_dirs[0]} ({'; '.join(clashes)})")
    shards = [h.config.get("shard") for h in headers]
    counts = {str(s).split("/")[-1] for s in shards if s}
    if len(counts) > 1:
        raise ValueError(f"shards of different splits: {', '.join(str(s) for s in shards)}")
    named = [str(s) for s in shards if s]
    if len(set(named)) != len(named):
        twice = sorted({s for s in named if named.count(s) > 1})
        raise ValueError(f"shard {twice[0]} is named twice ({len(named)} shard directories)")
    seen: dict[str, Path] = {}
    by_id: dict[str, EpisodeRecord] = {}
    for directory in shard_dirs:
        for episode in read_episodes(directory):
            if episode.episode_id in seen:
                raise ValueError(
                    f"episode {episode.episode_id} is in both {seen[episode.episode_id]} and {directory}: "
                    "overlapping shards cannot be merged"
                )
            seen[episode.episode_id] = directory
            by_id[episode.episode_id] = episode
    selection = _selection(first)
    stray = sorted(set(by_id) - set(selection))
    if stray:
        raise ValueError(f"{seen[stray[0]]}: episode {stray[0]} is not in the run's selection")
    missing = tuple(i for i in selection if i not in by_id)
    if missing and not allow_incomplete:
        shown = ", ".join(missing[:10]) + (f" and {len(missing) - 10} more" if len(missing) > 10 else "")
        raise ValueError(f"{len(missing)} of {len(selection)} episodes are missing: {shown}")
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise ValueError(f"{out}: exists and is not an empty folder; choose a new OUT")
    with run_lock(out):
        config = {k: v for k, v in first.config.items() if k not in ("shard", "code_revisions")}
        config["planned_episodes"] = len(selection)
        config["merged_from"] = [str(s) if s else str(d.name) for s, d in zip(shards, shard_dirs, strict=True)]
        served: list[dict[str, Any]] = [h.config["served"] for h in headers if isinstance(h.config.get("served"), dict)]
        if served:
            servers = sorted({url for s in served for url in s.get("servers", [])})
            config["served"] = {**served[0], "servers": servers}
        revisions: list[str] = []
        for header in headers:  # every revision that wrote episodes, in shard order
            recorded = header.config.get("code_revisions")  # where older versions put them
            history = header.code_revisions or tuple(recorded if isinstance(recorded, list) else [header.code_revision])
            revisions += [r for r in history if r and r not in revisions]
        runtimes: tuple[dict[str, str], ...] = ()
        for header in headers:  # every runtime that wrote episodes, in shard order
            for runtime in header.runtimes:
                runtimes = add_runtime(runtimes, runtime)
        merged = first.with_changes(
            config=config,
            code_revisions=tuple(revisions) if len(revisions) > 1 else (),
            runtimes=runtimes,
            status="incomplete" if missing else "complete",
        )
        write_header(out, merged)
        rewrite_episodes(out, [by_id[i] for i in selection if i in by_id])
    return MergeResult(out, len(by_id), missing)


@dataclass(frozen=True)
class SplitShard:
    run_dir: Path
    shard: Shard
    seeded: int
    """Finished episodes copied in from the split run."""
    planned: int


def shard_folder(out: Path, shard: Shard) -> Path:
    """Where `split_run` puts a shard: `OUT/shard-I-of-N`."""
    return out / f"shard-{shard.index}-of-{shard.count}"


def split_run(
    run_dir: Path, count: int, out: Path, conditions: str | None = None, limit: int | None = None
) -> list[SplitShard]:
    """Split the `talkdem run` directory `run_dir` into `count` shard directories under `out` (new or empty).

    The selection is the run's own (its header's conditions and sample size) unless `conditions` or `limit`
    give a larger one; every finished episode must belong to it. Each shard's header is the run's, with the
    shard and the new selection, so `talkdem run --shard I/N --out OUT/shard-I-of-N` with the run's settings
    resumes it, and `talkdem merge` joins the shards back into one run.
    """
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    if count < 2:
        raise ValueError(f"split into at least 2 shards, not {count}")
    with run_lock(run_dir):
        header = read_header(run_dir)
        done = {episode.episode_id: episode for episode in read_episodes(run_dir)}
    if header.config.get("shard"):
        raise ValueError(f"{run_dir}: is shard {header.config['shard']} of a run; merge the shards and split the merge")
    if "conditions" not in header.config:
        raise ValueError(f"{run_dir}: not a `talkdem run` directory (its header records no episode selection)")
    recorded = header.config.get("conditions")
    text = conditions if conditions is not None else ",".join(recorded) if isinstance(recorded, list) else None
    recorded_limit = header.config.get("limit")
    size = limit if limit is not None else recorded_limit if isinstance(recorded_limit, int) else None
    parsed = parse_conditions(text)
    selection = select_episodes(parsed, size)
    selected = {instruction.id for instruction in selection}
    stray = sorted(set(done) - selected)
    if stray:
        raise ValueError(
            f"{run_dir}: episode {stray[0]} is not in the selection to split ({len(stray)} finished episodes are "
            "not); give --conditions and --limit that include the run's own"
        )
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise ValueError(f"{out}: exists and is not an empty folder; choose a new OUT")
    shards = []
    for index in range(1, count + 1):
        shard = Shard(index, count)
        mine = shard_of(selection, shard)
        folder = shard_folder(out, shard)
        folder.mkdir(parents=True)
        config = {
            **{k: v for k, v in header.config.items() if k != "merged_from"},  # merge writes its own
            "conditions": [str(c) for c in parsed],
            "limit": size,
            "shard": str(shard),
            "planned_episodes": len(mine),
        }
        seeded = [done[i.id] for i in mine if i.id in done]
        status = "complete" if len(seeded) == len(mine) else "incomplete"
        with run_lock(folder):
            write_header(folder, header.with_changes(config=config, status=status))
            rewrite_episodes(folder, seeded)
        shards.append(SplitShard(folder, shard, len(seeded), len(mine)))
    return shards
