"""The adaptive recursive SVD novelty detector and filter (Table 1, Eqs. (4)-(12))."""
from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ._checks import as_fraction, as_frame, as_frames, as_grey_threshold, as_method
from ._linalg import _sign_fix
from .results import EigenvalueDroppedWarning, NoveltyResult
from .updates import (_FRACTION_TOL, _bordered_vip, _novelty_from_vip, _qr_update,
                      _residual_split, _rounding_floor, _update_eigenimages)

__all__ = ["NoveltyFilter"]


class NoveltyFilter:
    r"""Adaptive recursive SVD novelty detector and filter (Table 1 of Vermeulen & Casasent).

    Keeps the Karhunen-Loeve eigenimages of the frames seen so far. Each new frame
    :math:`x` is tested against them: its novelty :math:`n_i = \|x - \hat x\|^2 /
    \|x\|^2` (Eq. (7)), with :math:`\hat x` the projection of :math:`x` on the
    eigenimages, is the fraction of its energy they do not explain; a frame is novel when
    :math:`n_i > T_d` (Eq. (8)), and only novel frames update the eigenimages (Eq. (9))
    and their number (Eqs. (10)-(11)). :meth:`novel_pixels` marks where a frame differs
    from its reconstruction.

    Parameters
    ----------
    novelty_threshold : float in [0, 1]
        :math:`T_d` of Eq. (8): a frame is novel (and updates the model) when
        :math:`n_i > T_d`. :math:`T_d = 0` means every frame is used, including one that
        lies exactly in the span of the eigenimages (:math:`n_i = 0`): its energy still
        belongs to the correlation matrix.
    information_threshold : float in [0, 1]
        :math:`T_I` of Eq. (11): the smallest number of eigenimages whose information
        fractions (Eq. (10)) sum to at least :math:`T_I` is kept. With :math:`T_d = 0`
        and :math:`T_I = 1` the filter reproduces the batch eigen-decomposition of the
        correlation matrix of all frames (up to rounding). With :math:`T_I = 1` the
        ``"qr"`` route keeps every fraction above its rounding level (about
        :math:`10^{-29}`); the ``"vip"`` route drops fractions below :math:`10^{-12}` and
        says so with an :class:`EigenvalueDroppedWarning` when one of them is above its
        rounding level (about :math:`10^{-14}`).
    method : {"qr", "vip"}
        Numerical route of the update: ``"qr"`` (default) works with the residual of the
        new frame and keeps the eigenimages orthonormal to rounding even for
        near-duplicate frames; ``"vip"`` is the paper's bordered VIP matrix (Eqs.
        (4)-(9)), which squares the condition number. Both give the same VIP matrix
        record, novelty and eigen-decomposition in exact arithmetic.

    Attributes
    ----------
    eigenvalues_ : ndarray (K,)
        Eigenvalues :math:`\lambda_{i,k}` of the VIP matrix :math:`V_i` kept after the
        last update (the correlation matrix of the :math:`i` novel frames, Eq. (4)),
        descending.
    eigenimages_ : ndarray (K, ...) shaped like the frames
        Unit-norm eigenimages (orthonormal when flattened), pixel sum :math:`\ge 0`.
    components_ : ndarray (K, n_pixels)
        The same, flattened (scikit-learn convention).
    information_fractions_ : ndarray
        :math:`F_{i,k}` of Eq. (10) over the :math:`K_i` candidate eigenimages of the
        last update (before the excess ones were discarded).
    rank_ : int
        The rank estimate of Eq. (11) after the last update (``len(eigenvalues_)``).
    vip_matrix_ : ndarray
        The VIP matrix of the last frame processed (novel or not).
    novelty_ : float
        :math:`n_i` of the last frame processed.
    n_updates_ : int
        Iteration counter :math:`i`: number of novel frames used (the first frame
        included).
    n_frames_seen_ : int
        Sequence counter :math:`j`.

    Examples
    --------
    A static 16 x 16 background, then a bright square moving along it:

    >>> import numpy as np
    >>> from projtrack.novelty import NoveltyFilter
    >>> background = np.random.default_rng(0).uniform(50, 100, (16, 16))
    >>> frames = [background.copy() for _ in range(6)]
    >>> for k in (3, 4, 5):
    ...     frames[k][4:8, 2 * k:2 * k + 4] = 255.0
    >>> nf = NoveltyFilter(novelty_threshold=0.001)
    >>> [bool(nf.partial_fit(f).novel) for f in frames]
    [True, False, False, True, True, True]
    >>> nf.rank_
    4
    >>> new = background.copy(); new[10:14, 10:14] = 255.0    # the square elsewhere
    >>> round(nf.novelty(new), 3), int(nf.novel_pixels(new).sum())
    (0.187, 223)
    """

    def __init__(self, novelty_threshold: float = 0.001, information_threshold: float = 0.99,
                 method: str = "qr") -> None:
        self.novelty_threshold = as_fraction(novelty_threshold, "novelty_threshold")
        self.information_threshold = as_fraction(information_threshold,
                                                     "information_threshold")
        self.method = as_method(method)
        self._u: np.ndarray | None = None
        self._lam: np.ndarray | None = None
        self.frame_shape_: tuple[int, ...] | None = None
        self.n_updates_ = 0
        self.n_frames_seen_ = 0

    # -- the algorithm ------------------------------------------------------------------------
    def _vector(self, frame: Any, name: str = "frame") -> np.ndarray:
        a = as_frame(frame, name)
        if self.frame_shape_ is not None and a.shape != self.frame_shape_:
            raise ValueError(f"{name}: expected shape {self.frame_shape_} (the shape of the "
                             f"first frame), got {a.shape}")
        return a.ravel()

    def partial_fit(self, frame: Any) -> NoveltyResult:
        """Process one frame (steps 3-10 of Table 1).

        Returns
        -------
        NoveltyResult
            ``(novelty, novel)``: ``n_i`` of Eq. (7) against the model before the frame
            (1 for the first frame) and the detector output of Eq. (8).  A novel frame updates
            the eigenimages (Eq. (9)) and the rank (Eqs. (10)-(11)); a non-novel frame leaves
            the model unchanged.
        """
        x = self._vector(frame)
        if self._u is None:                                   # steps 1-3
            e = float(x @ x)
            if e == 0.0:
                raise ValueError("frame: the first frame is all zero; it cannot start the "
                                 "eigenimage set (its energy, the first eigenvalue, is 0)")
            self.frame_shape_ = np.shape(frame)
            self._u = _sign_fix((x / np.sqrt(e))[None, :])
            self._lam = np.array([e])
            self.n_updates_ = 1
            self.n_frames_seen_ = 1
            self.vip_matrix_ = np.array([[e]])
            self.information_fractions_ = np.array([1.0])
            self.novelty_ = 1.0
            return NoveltyResult(1.0, True)
        self.n_frames_seen_ += 1                              # step 6
        i_prev = self.n_updates_
        v, n, split = self._vip_and_novelty(x, i_prev)       # step 7, Eqs. (4)-(7)
        self.vip_matrix_ = v
        self.novelty_ = n
        if not self._is_novel(n):                             # step 8, Eq. (8)
            return NoveltyResult(n, False)
        if self.method == "qr":                               # step 9, Eq. (9)
            g, u = _qr_update(self._u, self._lam, i_prev, x, split)
        else:
            g, u = _update_eigenimages(self._u, self._lam, i_prev, x, v)
        f = np.abs(g) / np.abs(g).sum()                       # Eq. (10)
        self.information_fractions_ = f
        k_hat = min(self._rank(f), u.shape[0])                # Eq. (11)
        self._lam, self._u = g[:k_hat].copy(), u[:k_hat].copy()   # step 10
        self.n_updates_ = i_prev + 1                          # step 4 (for the next frame)
        return NoveltyResult(n, True)

    def _vip_and_novelty(self, x: np.ndarray, i_prev: int):
        """The VIP matrix of Eqs. (4)-(5) and the novelty of Eq. (7) by the chosen route."""
        if self.method == "vip":
            v = _bordered_vip(self._u, self._lam, i_prev, x)
            return v, _novelty_from_vip(v), None
        split = _residual_split(self._u, x)
        c, _, rho = split
        i = i_prev + 1
        k = self._lam.size
        v = np.empty((k + 1, k + 1))
        v[:k, :k] = np.diag(i_prev * self._lam / i)
        border = np.sqrt(i_prev * self._lam) * c / i
        v[:k, k] = border
        v[k, :k] = border
        xx = float(x @ x)
        v[k, k] = xx / i
        # Eq. (7) without cancellation: 1 - sum of squared direction cosines = |r|^2 / |x|^2
        n = 0.0 if xx <= 0 else float(np.clip(rho * rho / xx, 0.0, 1.0))
        return v, n, split

    def _is_novel(self, n: float) -> bool:
        """Eq. (8): ``n > T_d``; with ``T_d = 0`` every frame is used (even one in the span)."""
        return bool(n > self.novelty_threshold or self.novelty_threshold == 0.0)

    def _rank(self, fractions: np.ndarray) -> int:
        """Eq. (11): smallest m with sum_{k<=m} F_k >= T_I.

        With ``T_I = 1`` every eigenimage is kept whose fraction is above the route's
        tolerance: the rounding level for ``"qr"``, 1e-12 for ``"vip"`` (whose eigenvalues are
        known only to about ``eps`` of the largest).  When the ``"vip"`` route drops a fraction
        below 1e-12 that is above its rounding level, an :class:`EigenvalueDroppedWarning`
        says so.
        """
        if self.information_threshold >= 1.0:
            floor = _rounding_floor(self.method, fractions.size - 1)
            tol = floor if self.method == "qr" else _FRACTION_TOL
            m = max(1, int(np.sum(fractions > tol)))
            dropped = fractions[m:]
            lost = dropped[dropped > floor]
            if lost.size:
                warnings.warn(f"T_I = 1 asks for every eigenimage, but {lost.size} eigenvalue(s) "
                              f"with information fraction down to {float(lost.min()):.3g} (below "
                              f"the tolerance {tol:g} of the '{self.method}' route) were dropped",
                              EigenvalueDroppedWarning, stacklevel=3)
            return m
        c = np.cumsum(fractions)
        m = int(np.searchsorted(c, self.information_threshold - _FRACTION_TOL, side="left")) + 1
        return max(1, min(m, fractions.size))

    def fit(self, frames: Any) -> "NoveltyFilter":
        """Feed every frame of ``frames`` (shape ``(I, *frame_shape)``) in order."""
        for f in as_frames(frames):
            self.partial_fit(f)
        return self

    # -- using the model -----------------------------------------------------------------------
    def _check_fitted(self) -> None:
        if self._u is None:
            raise ValueError("this NoveltyFilter has seen no frame yet; call partial_fit first")

    @property
    def eigenvalues_(self) -> np.ndarray:
        self._check_fitted()
        return self._lam.copy()

    @property
    def eigenimages_(self) -> np.ndarray:
        self._check_fitted()
        return self._u.reshape((-1,) + tuple(self.frame_shape_)).copy()

    @property
    def components_(self) -> np.ndarray:
        self._check_fitted()
        return self._u.copy()

    @property
    def rank_(self) -> int:
        self._check_fitted()
        return int(self._lam.size)

    def novelty(self, frame: Any) -> float:
        """``n`` of Eq. (7) for ``frame`` against the current model, without updating it."""
        self._check_fitted()
        x = self._vector(frame)
        return self._vip_and_novelty(x, self.n_updates_)[1]

    def transform(self, frame: Any) -> np.ndarray:
        """Coefficients ``x^T Phi_k`` of ``frame`` on the unit eigenimages (Eq. (12))."""
        self._check_fitted()
        return self._u @ self._vector(frame)

    def reconstruct(self, frame: Any) -> np.ndarray:
        """Novelty filter output ``x_hat`` of Eq. (12), in the frame's shape.

        ``x_hat = sum_k (x^T Phi_k / |Phi_k|^2) Phi_k``, the orthogonal projection of ``x`` on
        the span of the retained eigenimages.
        """
        self._check_fitted()
        x = self._vector(frame)
        return (self._u.T @ (self._u @ x)).reshape(self.frame_shape_)

    def novel_pixels(self, frame: Any, pixel_threshold: float = 8.0) -> np.ndarray:
        """The novel-pixel image ``|x - x_hat| > T_f`` (Section 4; ``T_f`` = 8 grey levels)."""
        pixel_threshold = as_grey_threshold(pixel_threshold, "pixel_threshold")
        x = as_frame(frame)
        return np.abs(x - self.reconstruct(x)) > pixel_threshold

    def weighted_eigenimages(self) -> np.ndarray:
        """The paper's ``sqrt(lambda_k) Phi_k`` in grey levels (``(K, *frame_shape)``).

        For a static scene the first one approaches the background (Fig. 3).
        """
        return np.sqrt(self.eigenvalues_)[(slice(None),) + (None,) * len(self.frame_shape_)] \
            * self.eigenimages_

