"""The three DMA decoders on one observation sequence: Viterbi, smoothing, filtering."""

from __future__ import annotations

import numpy as np

from projtrack.dma import forward_backward, forward_filter, viterbi

__all__ = ["decode_all"]


def decode_all(log_start: np.ndarray, log_trans: object, log_emission: np.ndarray) -> dict[str, np.ndarray]:
    """Viterbi path, smoothed (forward-backward) and filtered (on-line) argmax paths."""
    post, _ = forward_backward(log_start, log_trans, log_emission)
    return {
        "viterbi": viterbi(log_start, log_trans, log_emission),
        "smooth": np.argmax(post, axis=1),
        "filter": np.argmax(forward_filter(log_start, log_trans, log_emission), axis=1),
    }
