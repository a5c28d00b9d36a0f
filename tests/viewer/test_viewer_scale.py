"""The viewer on 10,000+ episodes: generated run directories (eleven copies of the committed CARE run of
`results/paper/`, 960 episodes each, their final states left out to keep the files small) give 10,560 episodes.
The page loads the index alone, filters and searches it quickly, and loads a detail file only when an episode opens."""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path
from typing import Any

import pytest
from viewer_browser import PAPER, drive, index_of

from talkdem.runs.episode_files import episodes_file, read_episode_bytes
from talkdem.viewer import load_runs, write_viewer

COPIES = 11

_STEPS = """
out.count0 = $('count').textContent; out.chunks0 = chunksLoaded(); out.summary = $('summary').textContent;
var t0 = performance.now();
set('f-pattern', 'intrusion'); set('f-level', '2'); set('f-outcome', '0'); set('search', 'knife');
out.searchMs = performance.now() - t0; out.filterMs = Number(document.body.dataset.filterMs);
out.count1 = $('count').textContent; out.rows1 = rows(); out.chunksAfterFilter = chunksLoaded();
document.querySelector('#episodes tbody tr').click();
waitFor(opened, function(){ out.chunksOpen = chunksLoaded(); out.title = $('episode-title').textContent; finish(); });
"""


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, float]:
    root = tmp_path_factory.mktemp("large")
    source = PAPER / "qwen2.5-coder-0.5b-care"
    lines = []
    stored = episodes_file(source)  # committed runs may be packed
    assert stored is not None, f"{source}: no episodes"
    for line in read_episode_bytes(stored).decode("utf-8").splitlines():
        record = json.loads(line)
        record["trace"].pop("final_state", None)
        lines.append(json.dumps(record))
    dirs = []
    for n in range(COPIES):
        run_dir = root / f"copy-{n:02d}"
        run_dir.mkdir()
        shutil.copy(source / "header.json", run_dir / "header.json")
        (run_dir / "episodes.jsonl").write_text("\n".join(lines) + "\n", encoding="utf-8")
        dirs.append(run_dir)
    start = time.perf_counter()
    write_viewer(load_runs(dirs), root / "viewer")
    return root / "viewer", time.perf_counter() - start


def test_ten_thousand_episodes_load_filter_and_open_lazily(generated: tuple[Path, float], tmp_path: Path) -> None:
    viewer, seconds = generated
    index = index_of(viewer)
    assert len(index["rows"]) == 960 * COPIES >= 10_000
    assert index["chunks"] == len(list((viewer / "data").glob("chunk-*.js"))) == -(-960 * COPIES // 200)
    assert seconds < 60, f"building the viewer of {960 * COPIES} episodes took {seconds:.0f} s"
    seen: dict[str, Any] = drive(viewer / "index.html", _STEPS, tmp_path / "profile")
    assert seen["count0"] == "10,560 of 10,560 episodes"
    assert seen["chunks0"] == [] and seen["chunksAfterFilter"] == []
    assert seen["loadedAt"] < 5000, f"the page took {seen['loadedAt']:.0f} ms to load"
    assert seen["filterMs"] < 300 and seen["searchMs"] < 2000, seen
    print(  # shown with -s: the numbers docs/viewer.md quotes
        f"built in {seconds:.1f} s; loaded in {seen['loadedAt']:.0f} ms; filter {seen['filterMs']:.1f} ms; "
        f"four filters and a search {seen['searchMs']:.0f} ms"
    )
    f = {name: i for i, name in enumerate(index["fields"])}
    wanted = [
        i
        for i, r in enumerate(index["rows"])
        if r[f["pattern"]] == "intrusion"
        and r[f["level"]] == 2
        and not r[f["success"]]
        and "knife" in r[f["instruction"]].lower()
    ]
    assert wanted and seen["count1"] == f"{len(wanted):,} of 10,560 episodes"
    assert [r["row"] for r in seen["rows1"]] == wanted[:100]
    first = wanted[0]
    twin = index["rows"][first][f["clean_row"]]
    assert seen["title"] == index["rows"][first][f["episode_id"]]
    assert set(seen["chunksOpen"]) == {first // 200, twin // 200}  # the episode's chunk and its clean twin's
