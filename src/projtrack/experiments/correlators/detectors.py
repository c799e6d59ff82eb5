"""The detector rule of the frequency-multiplexed correlator (Fig. 8) against the paper's sum of peaks.

:func:`detector_rule_study` classifies noisy (optionally shifted) letters with the
summed-output rule of one detector per class and with the sum of the separate peaks.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["detector_rule_study"]


def _rule_trial(rng, bank, images, labels, cases, extent):
    out = []
    for sigma, shift in cases:
        clean = images
        if shift:
            d = rng.integers(-shift, shift + 1, size=(len(images), 2))
            clean = np.stack([np.roll(a, tuple(int(v) for v in s), axis=(0, 1)) for a, s in zip(images, d)])
        X = letters.noisy(clean, sigma, rng, extent=extent)[0]
        p_sum = bank.classes_[np.argmax(bank.summed_output_scores(X), axis=1)]
        p_peaks = bank.predict(X)
        out.append([np.mean(p_sum == labels), np.mean(p_peaks == labels), np.mean(p_sum == p_peaks)])
    return out


def detector_rule_study(bank: object, images: np.ndarray, labels: Sequence[object],
                        cases: Sequence[tuple[float, int]], n_draws: int, rng: np.random.Generator, *,
                        extent: int | None = None) -> np.ndarray:
    """Accuracy of the summed-output and sum-of-peaks rules of a projection bank, and their agreement.

    For every case ``(sigma, shift)`` each trial shifts every image cyclically by a random
    ``(dy, dx)`` with ``|dy|, |dx| <= shift`` (no shift when 0), adds Gaussian noise over
    the central ``extent x extent`` pixels (``None``: the whole image;
    :func:`projtrack.scenes.letters.noisy`) and classifies it by the largest summed
    detector output (:meth:`~projtrack.correlators.ProjectionCorrelationClassifier.summed_output_scores`)
    and by the bank's own rule (:meth:`predict`). Trials run through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    numpy.ndarray, shape (n_draws, len(cases), 3)
        Per trial and case: fraction correct by the summed output, by the sum of peaks,
        and fraction of images on which the two rules pick the same class.
    """
    if not (hasattr(bank, "summed_output_scores") and hasattr(bank, "classes_")):
        raise TypeError("bank must be a fitted ProjectionCorrelationClassifier")
    images = as_array(images, "images", ndim=3, allow_empty=False)
    labels = np.asarray(labels)
    if labels.shape != (len(images),):
        raise ValueError(f"labels must hold one label per image ({len(images)}), got shape {labels.shape}")
    cases = [(as_real(s, "cases sigma", 0.0), as_int(h, "cases shift", minimum=0)) for s, h in cases]
    if not cases:
        raise ValueError("cases must not be empty")
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    extent = None if extent is None else as_int(extent, "extent", minimum=1)
    return np.array(montecarlo.run(_rule_trial, n_draws, as_rng(rng), bank, images, labels, cases, extent))
