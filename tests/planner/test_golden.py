"""Golden prompts: each strategy's rendered prompt for one fixed episode, compared with a committed file that
was reviewed line by line against the paper's appendix box (docs/strategies.md says how each line departs).

Regenerate after a deliberate change with `TALKDEM_UPDATE_GOLDEN=1 pytest tests/planner/test_golden.py`, then
review the diff and bump `talkdem/planner/prompts/VERSION`.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from golden_support import ANSWER, EPISODE, RecordingLM, bag_of_words

from care.strategy import ContextAwareRetrieval
from talkdem.instructions import load_memory_bank
from talkdem.planner import SayCanPlanner
from talkdem.planner.prompt import prompt_text
from talkdem.planner.strategies import Strategy, load_strategy

GOLDEN = Path(__file__).parent / "golden"


def _strategy(name: str) -> Strategy:
    if name == "care":
        return ContextAwareRetrieval(memory=load_memory_bank(), encode=bag_of_words)
    return load_strategy(name)


def _rendered(name: str) -> dict[str, str]:
    """The planner's prompt, and for CoT and TOCC the generation prompt the model is asked first."""
    lm = RecordingLM()
    planner_input = _strategy(name).prepare([EPISODE.text], lm)[0]
    files = {f"{name}.txt": SayCanPlanner(lm).prompt_for(planner_input)}
    if lm.prompts:
        files[f"{name}_generation.txt"] = lm.prompts[0].prompt
    return files


def _check(files: dict[str, str]) -> None:
    for file_name, text in files.items():
        path = GOLDEN / file_name
        if os.environ.get("TALKDEM_UPDATE_GOLDEN"):
            path.write_text(text)
        assert path.is_file(), f"{path}: no golden file (write it with TALKDEM_UPDATE_GOLDEN=1, then review it)"
        assert text == path.read_text(), f"{path}: the rendered prompt changed; review and regenerate"


@pytest.mark.parametrize("name", ["vanilla", "ap", "cot", "icl", "tocc", "care"])
def test_rendered_prompt_matches_the_reviewed_golden_file(name: str) -> None:
    _check(_rendered(name))


def test_golden_prompts_carry_the_paper_boxes_verbatim() -> None:
    # The boxes' sentences, as the paper prints them, are in the prompts that use them.
    ap = (GOLDEN / "ap.txt").read_text()
    assert prompt_text("aware").removeprefix("Robot: ") in ap and ap.index("Robot: I understand") > ap.index("done.")
    cot_question = (GOLDEN / "cot_generation.txt").read_text()
    assert cot_question.endswith(
        "Please answer: What is the single household task the human is asking for? Answer in one short sentence.\n"
    )
    assert f"Hint: {ANSWER}\nRobot: 1." in (GOLDEN / "cot.txt").read_text()
    for name in ("icl", "care"):
        assert prompt_text("demonstrations_intro") in (GOLDEN / f"{name}.txt").read_text()
    tocc = (GOLDEN / "tocc.txt").read_text()
    assert tocc.endswith(f"Human: {ANSWER}\nRobot: 1.") and EPISODE.text not in tocc
    assert (GOLDEN / "tocc_generation.txt").read_text().endswith("Clear instruction:\n")
