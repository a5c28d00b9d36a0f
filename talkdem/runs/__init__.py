"""Run directories: the header and the per-episode records of a planner run."""

from talkdem.runs.records import RUN_SCHEMA, EpisodeRecord, RunHeader
from talkdem.runs.store import (
    EPISODES_FILE,
    HEADER_FILE,
    PACKED_EPISODES_FILE,
    EpisodeWriter,
    read_episodes,
    read_header,
    write_header,
)

__all__ = [
    "EPISODES_FILE",
    "HEADER_FILE",
    "PACKED_EPISODES_FILE",
    "RUN_SCHEMA",
    "EpisodeRecord",
    "EpisodeWriter",
    "RunHeader",
    "read_episodes",
    "read_header",
    "write_header",
]
