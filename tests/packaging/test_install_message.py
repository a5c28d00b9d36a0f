"""Without llama-cpp-python, the error says how to install it in a way that works: TALK-Dem is not on PyPI,
so `pip install 'talkdem[llamacpp]'` finds nothing; the message names the extra's own requirement (read from
pyproject.toml here, so the two cannot drift apart) and the checkout and wheel forms."""

from __future__ import annotations

import sys
import tomllib

import pytest

from talkdem.paths import repo_root


def test_the_missing_extra_names_an_install_that_works(monkeypatch: pytest.MonkeyPatch) -> None:
    from talkdem.llm.backends.llamacpp import LlamaCppLM

    monkeypatch.setitem(sys.modules, "llama_cpp", None)  # import llama_cpp now raises ImportError
    with pytest.raises(ImportError) as refused:
        LlamaCppLM("smollm2")
    message = str(refused.value)
    (requirement,) = tomllib.loads((repo_root() / "pyproject.toml").read_text())["project"]["optional-dependencies"][
        "llamacpp"
    ]
    assert f"pip install '{requirement}'" in message
    assert "pip install -e '.[llamacpp]'" in message and ".whl[llamacpp]" in message
    assert "talkdem[llamacpp]" not in message
