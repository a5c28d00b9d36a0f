"""Shard slicing: deterministic, disjoint, covering, balanced; bad shard specifications refused."""

from __future__ import annotations

import pytest

from talkdem.runs.sampling import select_episodes
from talkdem.runs.shards import Shard, parse_shard, shard_of
from talkdem.schema import parse_conditions


def test_shards_partition_the_selection_in_its_order() -> None:
    episodes = select_episodes(parse_conditions(None), 7)
    parts = [shard_of(episodes, Shard(i, 3)) for i in (1, 2, 3)]
    ids = [[e.id for e in part] for part in parts]
    assert sorted(i for part in ids for i in part) == sorted(e.id for e in episodes), (
        "every episode in exactly one shard"
    )
    assert max(map(len, ids)) - min(map(len, ids)) <= 1
    order = {e.id: k for k, e in enumerate(episodes)}
    assert all([order[i] for i in part] == sorted(order[i] for i in part) for part in ids)
    assert ids == [[e.id for e in shard_of(list(reversed(episodes)), Shard(i, 3))][::-1] for i in (1, 2, 3)]


@pytest.mark.parametrize("text", ["0/2", "3/2", "1", "a/b", "1/2/3", "-1/2", "1/0"])
def test_bad_shards_are_refused(text: str) -> None:
    with pytest.raises(ValueError, match="must be I/N"):
        parse_shard(text)


def test_parse_shard() -> None:
    assert parse_shard("2/4") == Shard(2, 4) and str(Shard(2, 4)) == "2/4"
