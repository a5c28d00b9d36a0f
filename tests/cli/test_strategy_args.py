"""`talkdem run --strategy-arg KEY=VALUE`: a strategy's options, declared by the strategy and typed by that
declaration; a bad value, an unknown key or another strategy's key is one line; the removed strategy flags name
the option that replaces them."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.cli import build_parser, main
from talkdem.cli.run import config_of
from talkdem.planner.strategies import strategies_with_option, strategy_options
from talkdem.runs.plan import plan_run

SMALL = ["--limit", "1", "--conditions", "clean"]


def _options(*argv: str) -> dict[str, object]:
    return plan_run(config_of(build_parser().parse_args(["run", *SMALL, *argv]))).strategy_options


def test_strategy_args_are_typed_by_the_strategys_declaration() -> None:
    care = _options("--strategy", "care", "--strategy-arg", "order=best_first", "--strategy-arg", "dedupe=yes")
    assert care == {"order": "best_first", "dedupe": True}
    tocc = _options("--strategy", "tocc", "--strategy-arg", "max_new_tokens=64", "--strategy-arg", "chat=false")
    assert tocc == {"max_new_tokens": 64, "chat": False} and type(tocc["max_new_tokens"]) is int
    assert _options("--strategy", "vanilla") == {}


def test_the_declared_options_are_the_names_the_header_records() -> None:
    # A header's `config.strategy_args` names these options (CARE also records its fixed k).
    assert [o.name for o in strategy_options("care")] == ["order", "dedupe"]
    assert [o.name for o in strategy_options("cot")] == [o.name for o in strategy_options("tocc")]
    assert [o.name for o in strategy_options("tocc")] == ["max_new_tokens", "chat"]
    assert strategies_with_option("chat") == ("cot", "tocc") and strategy_options("icl") == ()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--strategy", "care", "--strategy-arg", "order=worst_first"],
            "strategy arg order='worst_first': the care strategy's 'order' takes one of best_first, best_last",
        ),
        (
            ["--strategy", "tocc", "--strategy-arg", "max_new_tokens=many"],
            "strategy arg max_new_tokens='many': the tocc strategy's 'max_new_tokens' takes a whole number of "
            "at least 1",
        ),
        (
            ["--strategy", "cot", "--strategy-arg", "chat=maybe"],
            "strategy arg chat='maybe': the cot strategy's 'chat' takes true or false",
        ),
        (
            ["--strategy", "care", "--strategy-arg", "k=5"],
            "strategy arg 'k': the care strategy has no such option (its options: order, dedupe)",
        ),
        (
            ["--strategy", "vanilla", "--strategy-arg", "order=best_first"],
            "strategy arg 'order': the vanilla strategy has no such option (its options: none); care has it",
        ),
        (
            ["--strategy", "care", "--strategy-arg", "chat=false"],
            "strategy arg 'chat': the care strategy has no such option (its options: order, dedupe); cot and tocc "
            "have it",
        ),
        (["--strategy", "care", "--strategy-arg", "order"], "--strategy-arg 'order': expected KEY=VALUE"),
        (["--care-order", "best_first"], "--care-order was removed: use --strategy-arg order=best_first"),
        (["--care-dedupe"], "--care-dedupe was removed: use --strategy-arg dedupe=true"),
        (["--generation-tokens", "64"], "--generation-tokens was removed: use --strategy-arg max_new_tokens=64"),
        (["--generation-plain"], "--generation-plain was removed: use --strategy-arg chat=false"),
        (
            ["--no-mask-failed"],
            "--no-mask-failed was removed: use --feedback none (--feedback message where it followed --feedback both)",
        ),
    ],
)
def test_a_bad_strategy_arg_is_one_line_and_exit_2(
    argv: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", *SMALL, *argv, "--out", str(tmp_path / "r"), "--no-progress"]) == 2
    assert capsys.readouterr().err == f"talkdem run: error: {message}\n"
    assert not (tmp_path / "r").exists()


def test_the_help_fits_a_screen(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "100")
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    shown = capsys.readouterr().out
    assert len(shown.splitlines()) <= 50 and max(len(line) for line in shown.splitlines()) <= 100
    assert "--strategy-arg" in shown and "--care-order" not in shown and "--tokenizer" not in shown
