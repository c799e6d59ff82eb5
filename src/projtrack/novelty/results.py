"""What the novelty algorithms return: the KL basis, one frame's result and record, a warning."""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

__all__ = ["EigenvalueDroppedWarning", "KLBasis", "NoveltyResult", "FrameRecord"]


class EigenvalueDroppedWarning(RuntimeWarning):
    """An eigenvalue that carries information was dropped because it is below the tolerance.

    Issued by :class:`NoveltyFilter` with ``method="vip"`` when ``T_I = 1`` asks for every
    eigenimage but a candidate eigenvalue above the rounding level of the VIP matrix is smaller
    than ``1e-12`` times the sum of the eigenvalues (the VIP route cannot resolve it), or when an
    eigenvalue of the VIP matrix is not positive beyond rounding.  The ``"qr"`` route keeps
    every eigenvalue above its own (much lower) rounding level.
    """


class KLBasis(NamedTuple):
    """Eigenvalues (descending) and unit-norm eigenimages, shape ``(K, *frame_shape)``.

    Attributes
    ----------
    eigenvalues : numpy.ndarray, shape (K,)
        Descending.
    eigenimages : numpy.ndarray, shape (K, ...) shaped like the frames
        Unit norm, orthonormal when flattened.
    """

    eigenvalues: np.ndarray
    eigenimages: np.ndarray


class NoveltyResult(NamedTuple):
    """What :meth:`NoveltyFilter.partial_fit` returns: the novelty :math:`n_i` (Equation
    (7)) and the decision of Equation (8).

    Attributes
    ----------
    novelty : float
        :math:`n_i`, the fraction of the frame's energy the eigenimages do not explain
        (1 for the first frame).
    novel : bool
        Whether :math:`n_i` exceeds the novelty threshold (the frame then updated the model).
    """

    novelty: float
    novel: bool


@dataclass(frozen=True)
class FrameRecord:
    """One frame of :func:`process_sequence` (what the panels of Figures 2-3 show).

    Attributes
    ----------
    frame : int
        Sequence counter ``j`` (1-based).
    iteration : int
        Iteration counter ``i`` when the frame was tested (number of novel frames including
        this one if it is novel).
    novelty : float
        ``n_i`` of Eq. (7) against the model before this frame.
    novel : bool
        Eq. (8).
    vip : numpy.ndarray
        The ``K_i x K_i`` VIP matrix of Eqs. (4)-(5) (for frame 1, ``[[|x_1|^2]]``).
    fractions : numpy.ndarray or None
        ``F_{i,k}`` of Eq. (10) over the ``K_i`` candidate eigenimages (``None`` if not novel).
    rank : int
        Number of eigenimages kept after the frame (Eq. (11)).
    novel_pixels : numpy.ndarray
        Boolean image ``|x_j - x_hat_j| > T_f`` with ``x_hat_j`` (Eq. (12)) from the model
        *before* the frame (all True for frame 1).
    eigenvalues : numpy.ndarray
        Eigenvalues after the frame.
    first_eigenimage : numpy.ndarray
        ``sqrt(lambda_1) * Phi_1`` after the frame, in grey levels (the background estimate).
    """

    frame: int
    iteration: int
    novelty: float
    novel: bool
    vip: np.ndarray
    fractions: np.ndarray | None
    rank: int
    novel_pixels: np.ndarray
    eigenvalues: np.ndarray
    first_eigenimage: np.ndarray
