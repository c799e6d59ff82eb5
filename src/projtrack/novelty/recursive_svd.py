"""The classic fixed-rank recursive SVD (Murakami & Kumar), the baseline of Section 2."""
from __future__ import annotations

from typing import Any

import numpy as np

from ._checks import as_frame, as_frames, as_positive_count
from .batch import batch_kl
from .updates import _bordered_vip, _update_eigenimages

__all__ = ["RecursiveSVD"]


class RecursiveSVD:
    """Fixed-rank recursive SVD (Murakami & Kumar 1982; Section 2 of Vermeulen & Casasent).

    The first ``K + 1`` frames give ``K + 1`` eigenimages by the batch VIP route (Eqs. (2)-(3))
    and the smallest is discarded; every later frame is bordered onto the ``K`` eigenimages
    weighted by the square roots of their eigenvalues (Eqs. (4)-(5)), the ``K + 1`` new
    eigenimages are formed (Eq. (9)) and the smallest is always discarded.  No mean is removed
    (center the frames beforehand if the covariance is wanted).

    Parameters
    ----------
    n_components : int
        The rank ``K`` fixed in advance.

    Attributes
    ----------
    eigenvalues_ : ndarray (K,)
    eigenimages_ : ndarray (K, ...) shaped like the frames, unit norm
    n_frames_seen_ : int
    """

    def __init__(self, n_components: int) -> None:
        self.n_components = as_positive_count(n_components, "n_components")
        self._buffer: list[np.ndarray] = []
        self._u: np.ndarray | None = None
        self._lam: np.ndarray | None = None
        self.n_frames_seen_ = 0
        self.frame_shape_: tuple[int, ...] | None = None

    def partial_fit(self, frame: Any) -> "RecursiveSVD":
        """Add one frame; returns ``self``."""
        a = as_frame(frame)
        if self.frame_shape_ is None:
            self.frame_shape_ = a.shape
        elif a.shape != self.frame_shape_:
            raise ValueError(f"frame: expected shape {self.frame_shape_}, got {a.shape}")
        x = a.ravel()
        self.n_frames_seen_ += 1
        if self._u is None:
            self._buffer.append(x)
            if len(self._buffer) == self.n_components + 1:
                basis = batch_kl(np.stack(self._buffer), n_components=self.n_components)
                self._lam = basis.eigenvalues
                self._u = basis.eigenimages.reshape(len(self._lam), -1)
                self._buffer = []
            return self
        i_prev = self.n_frames_seen_ - 1
        v = _bordered_vip(self._u, self._lam, i_prev, x)
        g, u = _update_eigenimages(self._u, self._lam, i_prev, x, v)
        self._lam, self._u = g[: self.n_components], u[: self.n_components]
        return self

    def fit(self, frames: Any) -> "RecursiveSVD":
        """Feed every frame of ``frames`` (shape ``(I, *frame_shape)``) in order."""
        for f in as_frames(frames):
            self.partial_fit(f)
        return self

    def _check_fitted(self) -> None:
        if self._u is None:
            raise ValueError(f"RecursiveSVD needs at least n_components + 1 = "
                             f"{self.n_components + 1} frames before it has eigenimages")

    @property
    def eigenvalues_(self) -> np.ndarray:
        self._check_fitted()
        return self._lam.copy()

    @property
    def eigenimages_(self) -> np.ndarray:
        self._check_fitted()
        return self._u.reshape((-1,) + self.frame_shape_).copy()

