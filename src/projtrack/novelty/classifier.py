"""Per-class novelty filters as a classifier: the smallest novelty wins (Table 2)."""
from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ._checks import as_fraction, as_frames, as_method
from .filter import NoveltyFilter

__all__ = ["NoveltyClassifier"]


class NoveltyClassifier:
    """One :class:`NoveltyFilter` per class; a frame goes to the class of smallest novelty.

    This is the classifier of Table 2 of Vermeulen & Casasent: each class's training frames
    are fed in order to its own filter (``T_d``, ``T_I`` as given), and a test frame's novelty
    (Eq. (7)) is computed against every class model without updating it.

    Parameters
    ----------
    novelty_threshold, information_threshold : float in [0, 1]
        ``T_d`` and ``T_I`` of every class filter.
    method : {"qr", "vip"}
        Numerical route of the filters' update (:class:`NoveltyFilter`).

    Attributes
    ----------
    classes_ : ndarray
        Sorted class labels.
    filters_ : dict
        Label -> fitted :class:`NoveltyFilter`.
    """

    def __init__(self, novelty_threshold: float = 0.06, information_threshold: float = 0.97,
                 method: str = "qr") -> None:
        self.novelty_threshold = as_fraction(novelty_threshold, "novelty_threshold")
        self.information_threshold = as_fraction(information_threshold,
                                                     "information_threshold")
        self.method = as_method(method)

    def fit(self, frames: Any, labels: Sequence[Any]) -> "NoveltyClassifier":
        """Train one filter per label on ``frames`` (``(n, *shape)``) in the given order."""
        x = as_frames(frames)
        y = np.asarray(labels)
        if y.ndim != 1 or y.shape[0] != x.shape[0]:
            raise ValueError(f"labels must be 1-D with one label per frame ({x.shape[0]}), "
                             f"got shape {y.shape}")
        self.classes_ = np.unique(y)
        self.filters_ = {}
        for c in self.classes_:
            f = NoveltyFilter(self.novelty_threshold, self.information_threshold, self.method)
            self.filters_[c.item() if hasattr(c, "item") else c] = f.fit(x[y == c])
        return self

    def _check_fitted(self) -> None:
        if not hasattr(self, "filters_"):
            raise ValueError("this NoveltyClassifier is not fitted; call fit first")

    def novelties(self, frames: Any) -> np.ndarray:
        """``(n, n_classes)`` novelty of every frame against every class model (Eq. (7))."""
        self._check_fitted()
        x = as_frames(frames)
        return np.array([[f.novelty(xi) for f in self.filters_.values()] for xi in x])

    def predict(self, frames: Any) -> np.ndarray:
        """Class of smallest novelty for every frame."""
        nov = self.novelties(frames)
        return self.classes_[np.argmin(nov, axis=1)]

