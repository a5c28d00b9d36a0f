"""What published files may say about a run: file names of model files, no URLs or machine paths, and
file stems that never collide."""

from __future__ import annotations

from talkdem.report import is_machine_path, public_config, public_model, unique_stems


def test_paths_are_told_from_hub_ids() -> None:
    for path in ("/home/me/m.gguf", "~/m.gguf", "./m.gguf", "models/m.gguf", "C:\\models\\m.gguf", "/data/x"):
        assert is_machine_path(path), path
    for name in ("HuggingFaceTB/SmolLM2-135M-Instruct", "smollm2-135m-instruct", "org/model", "oracle"):
        assert not is_machine_path(name), name


def test_a_model_file_is_named_by_its_file_name_and_a_server_url_is_dropped() -> None:
    local = public_model({"backend": "llamacpp", "name": "/home/me/w/Q.Q4_K_M.gguf", "revision": "ab" * 32})
    assert local == {"backend": "llamacpp", "name": "Q.Q4_K_M.gguf", "revision": "ab" * 32}
    windows = public_model({"backend": "hf", "name": "C:\\Users\\me\\m.gguf", "revision": ""})
    assert windows["name"] == "m.gguf"
    served = public_model({"backend": "openai", "name": "qwen", "revision": "http://10.0.0.7:8000/v1"})
    assert served == {"backend": "openai", "name": "qwen", "revision": ""}
    config = public_config({"plan_file": "/home/me/plans.jsonl", "limit": 3, "urls": ["https://x.invalid"]})
    assert config == {"plan_file": "plans.jsonl", "limit": 3, "urls": [""]}


def test_stems_stay_apart_where_labels_differ_in_punctuation_or_case() -> None:
    stems = unique_stems(["my model / CARE", "my_model / CARE", "My model / CARE", "other / CARE"])
    assert len({s.casefold() for s in stems}) == 4
    assert stems[3] == "other_CARE"  # a label without a clash keeps its plain stem
    assert unique_stems(["a|b\nc"]) == ["a_b_c"]
    twins = unique_stems(["same", "same"])
    assert twins[0] != twins[1]
