"""Cards in this repository declare only apps that exist (the evaluate module's card once declared a Gradio
Space with an `app.py` that was never written)."""

from __future__ import annotations

from pathlib import Path

from huggingface_hub import RepoCard

ROOT = Path(__file__).resolve().parents[2]


def test_the_evaluate_module_card_declares_no_missing_app() -> None:
    card = RepoCard.load(ROOT / "evaluate_talkdem" / "README.md")
    data = card.data.to_dict()
    app = data.get("app_file")
    assert app is None or (ROOT / "evaluate_talkdem" / app).is_file()
    assert "sdk" not in data or app is not None
    assert data["title"] == "TALK-Dem" and "metric" in data["tags"]
