"""A bootstrap count is a whole number of resamples: 0 turns the intervals off (documented), otherwise at
least `MIN_RESAMPLES`; -5, 2.5, True or 5 are refused with one line naming the argument, before any plan
is executed, in the library and on the command line alike."""

from __future__ import annotations

from typing import Any

import pytest
from metrics_helpers import BOOK, clean_id, reference

from talkdem.cli import main
from talkdem.metrics import score_predictions


@pytest.mark.parametrize("count", [-5, 2.5, True, "100", 5, 39])
def test_impossible_bootstrap_counts_are_refused(count: Any) -> None:
    with pytest.raises(ValueError, match=r"bootstrap must be .*(0|no intervals)") as refused:
        score_predictions([reference(BOOK)], [clean_id(BOOK)], bootstrap=count)
    assert repr(count) in str(refused.value) or str(count) in str(refused.value)


def test_zero_means_no_intervals_and_a_real_count_gives_them() -> None:
    off = score_predictions([reference(BOOK)], [clean_id(BOOK)], bootstrap=0)
    on = score_predictions([reference(BOOK)], [clean_id(BOOK)], bootstrap=40)
    assert off.intervals == {} and on.intervals["sr/clean"] == (1.0, 1.0)


@pytest.mark.parametrize("command", ["report", "leaderboard"])
def test_the_flag_refuses_counts_too_small_for_an_interval(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main([command, "some-run", "--bootstrap", "5"])
    assert exit_.value.code == 2
    assert "--bootstrap: must be 0 (no intervals) or at least 40" in capsys.readouterr().err
