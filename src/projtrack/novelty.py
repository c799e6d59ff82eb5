"""KL novelty detector and filter (Vermeulen & Casasent 1988, chapter 6 of the Casasent report).

P. Vermeulen and D. Casasent, "KL techniques for optimal processing of time sequential
imagery", Proc. SPIE 1007 (1988).  Equation numbers below are those of that paper.

Implemented here:

- :func:`vip_matrix` and :func:`batch_kl`: the batch Karhunen-Loeve expansion of a sequence of
  ``I`` images through the small ``I x I`` matrix of vector inner products (the *VIP matrix*,
  Eq. (2)) and the eigenimages built from its eigenvectors (Eq. (3)).  With ``center=False``
  (the paper's choice in Section 3) the eigenvalues are those of the correlation matrix
  ``R = (1/I) sum_i x_i x_i^T``, with ``center=True`` those of the covariance matrix ``C``.
- :class:`RecursiveSVD`: the classic fixed-rank recursive SVD (Murakami & Kumar, refs. 13-14
  of the paper) that keeps ``K`` eigenimages and always discards the smallest one.
- :class:`NoveltyFilter`: the adaptive recursive SVD of Table 1 (steps 1-11): the bordered VIP
  matrix (Eqs. (4)-(5)), the novelty measure (Eqs. (6)-(7)) and detector (Eq. (8)), the
  eigenimage update (Eq. (9)), the information fractions (Eq. (10)), the rank estimate
  (Eq. (11)) and the novelty filter output (Eq. (12)) with its novel-pixel image
  ``|x - x_hat| > T_f``.
- :class:`NoveltyClassifier`: one novelty filter per class, smallest novelty wins (Table 2).
- :func:`process_sequence`: runs a filter over a sequence and records what Figs. 2-3 display.

Two numerical routes for the update (``method=``).  ``"vip"`` is the paper's: eigen-decompose
the bordered VIP matrix ``V_i`` (Eqs. (4)-(5)) and combine eigenimages and frame with its
eigenvectors (Eq. (9)).  ``V_i`` is a Gram matrix, so its condition number is the square of that of
the images it is built from: for near-duplicate frames the small eigenvalues lose half their digits
and the new eigenimages lose orthonormality.  ``"qr"`` (the default) splits the new frame into its
part in the span of the eigenimages and the orthogonal residual (classical Gram-Schmidt, applied
twice) and takes the SVD of the small ``(K+1) x (K+1)`` triangular factor; it gives the same
eigenvalues and eigenimages in exact arithmetic (``V_i = B B^T / i`` with ``B`` that factor) and
computes the novelty of Eq. (7) as ``|residual|^2 / |x|^2`` without cancellation.

Conventions.  Frames may have any shape (they are scanned lexicographically, i.e. flattened
in C order) and any real dtype (8-bit frames are converted to float64).  The stored
``eigenimages_`` are *unit-norm* (the normalized eigenimages of Eq. (3)); the paper's weighted
eigenimages ``Phi_{i,k}`` of Eqs. (5) and (9) have squared norm ``i * lambda_{i,k}`` and are
``sqrt(i * eigenvalues_[k]) * eigenimages_[k]``.  ``eigenvalues_`` are the eigenvalues of the
current VIP matrix ``V_i`` (Eq. (4)), i.e. of the correlation matrix of the ``i`` novel frames
used so far.
"""
from __future__ import annotations

from dataclasses import dataclass
from numbers import Integral, Real
from typing import Any, NamedTuple, Sequence

import numpy as np

__all__ = [
    "TABLE1_STEPS",
    "TABLE1_FLOW",
    "plot_block_diagram",
    "KLBasis",
    "NoveltyResult",
    "FrameRecord",
    "vip_matrix",
    "batch_kl",
    "correlation_matrix",
    "RecursiveSVD",
    "NoveltyFilter",
    "NoveltyClassifier",
    "process_sequence",
    "METHODS",
    "EigenvalueDroppedWarning",
]

#: The numerical routes of the eigenimage update: ``"qr"`` (residual-based, the default) and
#: ``"vip"`` (the paper's bordered VIP matrix, Eqs. (4)-(9)).
METHODS: tuple[str, ...] = ("qr", "vip")


class EigenvalueDroppedWarning(RuntimeWarning):
    """An eigenvalue that carries information was dropped because it is below the tolerance.

    Issued by :class:`NoveltyFilter` with ``method="vip"`` when ``T_I = 1`` asks for every
    eigenimage but a candidate eigenvalue above the rounding level of the VIP matrix is smaller
    than ``1e-12`` times the sum of the eigenvalues (the VIP route cannot resolve it), or when an
    eigenvalue of the VIP matrix is not positive beyond rounding.  The ``"qr"`` route keeps
    every eigenvalue above its own (much lower) rounding level.
    """

#: The steps of Table 1 (the adaptive recursive SVD algorithm), as implemented by
#: :meth:`NoveltyFilter.partial_fit`; Fig. 1 (the block diagram) is drawn from this list.
TABLE1_STEPS: tuple[tuple[int, str], ...] = (
    (1, "Initialize iteration counter i = 1 and sequence counter j = 1"),
    (2, "Initialize rank estimate K_1 = 1"),
    (3, "Read first image x_1: first eigenimage, eigenvalue |x_1|^2"),
    (4, "Increment iteration counter i"),
    (5, "Increment rank estimate K_i = K_{i-1} + 1"),
    (6, "Increment j, read next image x_j"),
    (7, "Form K_i x K_i VIP matrix V_i (Eqs. 4-5)"),
    (8, "Novel? n_i > T_d (Eqs. 6-8); if not, go to step 6"),
    (9, "Eigen-decompose V_i, new eigenimages (Eq. 9)"),
    (10, "Fractions F (Eq. 10), rank estimate (Eq. 11), discard excess"),
    (11, "More images? go to step 4"),
)

#: The control flow of Table 1: (from step, to step, condition); step 0 is the end.
TABLE1_FLOW: tuple[tuple[int, int, str], ...] = (
    (1, 2, ""), (2, 3, ""), (3, 4, ""), (4, 5, ""), (5, 6, ""), (6, 7, ""), (7, 8, ""),
    (8, 6, "not novel"), (8, 9, "novel"), (9, 10, ""), (10, 11, ""),
    (11, 4, "more images"), (11, 0, "done"),
)

# Relative tolerance below which an information fraction counts as numerically zero in the
# rank estimate (Eq. (11)); it lets T_I = 1 keep every eigenimage that carries information.
_FRACTION_TOL = 1e-12


class KLBasis(NamedTuple):
    """Eigenvalues (descending) and unit-norm eigenimages (``(K, *frame_shape)``)."""

    eigenvalues: np.ndarray
    eigenimages: np.ndarray


class NoveltyResult(NamedTuple):
    """What :meth:`NoveltyFilter.partial_fit` returns: ``n_i`` (Eq. (7)) and Eq. (8)."""

    novelty: float
    novel: bool


@dataclass(frozen=True)
class FrameRecord:
    """One frame of :func:`process_sequence` (what the panels of Figs. 2-3 show).

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


# ---------------------------------------------------------------------------------------------
# validation helpers
# ---------------------------------------------------------------------------------------------
def _check_fraction(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number in [0, 1], got {type(value).__name__}")
    v = float(value)
    if not (0.0 <= v <= 1.0):
        raise ValueError(f"{name} must lie in [0, 1], got {v!r}")
    return v


def _check_method(method: Any) -> str:
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(repr(m) for m in METHODS)}, got {method!r}")
    return method


def _as_frame(frame: Any, name: str = "frame") -> np.ndarray:
    """Validate one frame: real, finite, non-empty; returns a float64 array (same shape)."""
    a = np.asarray(frame)
    if a.dtype == bool or not (np.issubdtype(a.dtype, np.integer)
                               or np.issubdtype(a.dtype, np.floating)):
        raise TypeError(f"{name} must be a real-valued (integer or float) array, got dtype {a.dtype}")
    if a.ndim == 0 or a.size == 0:
        raise ValueError(f"{name} must be a non-empty array with at least one dimension, "
                         f"got shape {a.shape}")
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return a


def _as_frames(frames: Any, name: str = "frames") -> np.ndarray:
    """Validate a stack of frames ``(I, *shape)`` with ``I >= 1``; returns float64."""
    if isinstance(frames, (list, tuple)):
        if len(frames) == 0:
            raise ValueError(f"{name} must contain at least one frame")
        shapes = {np.shape(f) for f in frames}
        if len(shapes) != 1:
            raise ValueError(f"{name}: all frames must have the same shape, got {sorted(shapes)}")
    a = _as_frame(frames, name)
    if a.ndim < 2:
        raise ValueError(f"{name} must have shape (n_frames, *frame_shape), got {a.shape}")
    if a[0].size == 0:
        raise ValueError(f"{name}: frames must be non-empty, got shape {a.shape}")
    return a


def _sign_fix(images: np.ndarray) -> np.ndarray:
    """Deterministic sign: each eigenimage (row) has a non-negative pixel sum."""
    s = images.sum(axis=1)
    flip = np.where(s < 0, -1.0, 1.0)
    return images * flip[:, None]


def _eigh_desc(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (descending) and eigenvectors (columns) of a small symmetric matrix."""
    g, th = np.linalg.eigh((v + v.T) / 2.0)
    return g[::-1], th[:, ::-1]


# ---------------------------------------------------------------------------------------------
# batch KL through the VIP matrix (Eqs. (2)-(3))
# ---------------------------------------------------------------------------------------------
def vip_matrix(frames: Any, center: bool = False) -> np.ndarray:
    """The ``I x I`` matrix of vector inner products, Eq. (2) of Vermeulen & Casasent.

    ``v(l, m) = (1/I) (x_l - m)^T (x_m - m)`` with ``m`` the sample mean if ``center`` else 0.

    Parameters
    ----------
    frames : array_like, shape (I, H, W) or (I, ...)
        The image sequence (any real dtype).
    center : bool
        Subtract the mean image (covariance, KL proper) or not (correlation, Section 3).

    Returns
    -------
    numpy.ndarray, shape (I, I)
    """
    x = _as_frames(frames).reshape(len(frames), -1)
    if center:
        x = x - x.mean(axis=0)
    return x @ x.T / x.shape[0]


def correlation_matrix(frames: Any, center: bool = False) -> np.ndarray:
    """The large ``P x P`` matrix ``(1/I) sum (x_i - m)(x_i - m)^T`` (only for small images).

    This is the matrix whose eigen-decomposition Eqs. (2)-(3) avoid; it serves as the oracle.
    """
    x = _as_frames(frames).reshape(len(frames), -1)
    if x.shape[1] > 4096:
        raise ValueError(f"frames: {x.shape[1]} pixels per frame would give a "
                         f"{x.shape[1]}x{x.shape[1]} matrix; use vip_matrix/batch_kl instead")
    if center:
        x = x - x.mean(axis=0)
    return x.T @ x / x.shape[0]


def batch_kl(frames: Any, center: bool = False, n_components: int | None = None,
             rtol: float = 1e-12) -> KLBasis:
    """Batch KL expansion through the small VIP matrix, Eqs. (2)-(3) of Vermeulen & Casasent.

    The eigenvectors ``theta_k`` and eigenvalues ``gamma_k`` of the VIP matrix ``V`` (Eq. (2))
    give the eigenimages ``Phi_k = sum_l theta_k^l x_l / sqrt(I gamma_k)`` (Eq. (3), normalized
    to unit norm; the ``1/I`` of Eq. (2) appears as the ``I`` in the square root) with
    eigenvalues ``lambda_k = gamma_k``, which are the non-zero eigenvalues of the correlation
    (``center=False``) or covariance (``center=True``) matrix.

    Parameters
    ----------
    frames : array_like, shape (I, H, W) or (I, ...)
    center : bool
        Remove the sample mean first (covariance matrix ``C``) or not (correlation ``R``).
    n_components : int, optional
        Keep only the largest ``n_components`` (default: all numerically non-zero ones).
    rtol : float
        Eigenvalues below ``rtol * max(eigenvalue)`` are numerically zero and dropped.

    Returns
    -------
    KLBasis
        ``eigenvalues`` (descending, positive) and unit-norm ``eigenimages`` ``(K, *shape)``.
    """
    a = _as_frames(frames)
    shape = a.shape[1:]
    x = a.reshape(a.shape[0], -1)
    if center:
        x = x - x.mean(axis=0)
    if n_components is not None:
        if isinstance(n_components, bool) or not isinstance(n_components, Integral) \
                or n_components < 1:
            raise ValueError(f"n_components must be a positive integer, got {n_components!r}")
    if not (isinstance(rtol, Real) and 0 <= rtol < 1):
        raise ValueError(f"rtol must be a real number in [0, 1), got {rtol!r}")
    n = x.shape[0]
    g, th = _eigh_desc(x @ x.T / n)
    top = g[0] if g.size else 0.0
    if top <= 0:
        raise ValueError("frames: every frame is zero (after centering); no eigenimage exists")
    keep = g > rtol * top
    if n_components is not None:
        keep &= np.arange(g.size) < n_components
    g, th = g[keep], th[:, keep]
    phi = (th.T @ x) / np.sqrt(n * g)[:, None]
    phi /= np.linalg.norm(phi, axis=1, keepdims=True)
    return KLBasis(g.copy(), _sign_fix(phi).reshape((-1,) + shape))


# ---------------------------------------------------------------------------------------------
# the bordered VIP update shared by the recursive algorithms (Eqs. (4), (5), (9))
# ---------------------------------------------------------------------------------------------
def _bordered_vip(u: np.ndarray, lam: np.ndarray, i_prev: int, x: np.ndarray) -> np.ndarray:
    """VIP matrix V_i of Eqs. (4)-(5) for prior unit eigenimages ``u`` and new frame ``x``.

    The weighted eigenimages are ``Phi_{i-1,l} = sqrt((i-1) lambda_l) u_l``, so
    ``v(l,l) = (i-1)/i lambda_l`` (Eq. (4)), ``v(l,K) = x^T Phi_{i-1,l} / i`` and
    ``v(K,K) = x^T x / i`` (Eq. (5)).
    """
    i = i_prev + 1
    k = lam.size
    w = np.sqrt(i_prev * lam)
    v = np.empty((k + 1, k + 1))
    v[:k, :k] = np.diag(i_prev * lam / i)
    border = w * (u @ x) / i
    v[:k, k] = border
    v[k, :k] = border
    v[k, k] = float(x @ x) / i
    return v


def _novelty_from_vip(v: np.ndarray) -> float:
    """Eqs. (6)-(7): ``n = 1 - sum_k v(k,K)^2 / (v(k,k) v(K,K))``, clipped to [0, 1]."""
    k = v.shape[0] - 1
    vkk = v[k, k]
    if vkk <= 0:  # an all-zero frame lies in every subspace: nothing new
        return 0.0
    alpha2 = v[:k, k] ** 2 / (np.diag(v)[:k] * vkk)   # squared direction cosines, Eq. (6)
    return float(np.clip(1.0 - alpha2.sum(), 0.0, 1.0))


def _rounding_floor(method: str, k: int) -> float:
    """Information fraction below which an eigenvalue is rounding noise for ``method``.

    The ``"qr"`` route computes singular values to about ``eps`` of the largest, so
    eigenvalues (their squares) to about ``eps**2`` of the largest; the ``"vip"`` route
    eigen-decomposes the Gram matrix itself, so its eigenvalues are only known to about ``eps``.
    """
    eps = np.finfo(float).eps * 8 * (k + 1)
    return eps ** 2 if method == "qr" else eps


def _update_eigenimages(u: np.ndarray, lam: np.ndarray, i_prev: int, x: np.ndarray,
                        v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (9) (the ``"vip"`` route): eigen-decompose V_i and form the new unit eigenimages.

    Eigenvalues that are not positive cannot give an eigenimage and are dropped; a
    :class:`EigenvalueDroppedWarning` is issued when one of them is larger in magnitude than
    the rounding level of the VIP matrix.
    """
    import warnings

    g, th = _eigh_desc(v)
    w = np.sqrt(i_prev * lam)
    phi = (th[:-1].T * w) @ u + np.outer(th[-1], x)      # Eq. (9), weighted eigenimages
    norms = np.linalg.norm(phi, axis=1)
    good = (g > 0) & (norms > 0)
    bad = g[~good]
    floor = _rounding_floor("vip", lam.size) * float(np.abs(g).sum())
    if bad.size and np.max(np.abs(bad)) > floor:
        warnings.warn(f"the VIP route dropped {bad.size} non-positive eigenvalue(s) down to "
                      f"{float(bad.min()):.3g}, above its rounding level {floor:.3g}; "
                      "use method='qr'", EigenvalueDroppedWarning, stacklevel=4)
    phi = phi[good] / norms[good, None]
    return g[good], _sign_fix(phi)


def _residual_split(u: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Coefficients ``c = U x``, residual ``r = x - U^T c`` and ``|r|`` (Gram-Schmidt twice)."""
    c = u @ x
    r = x - u.T @ c
    c2 = u @ r                     # re-orthogonalization: "twice is enough"
    r = r - u.T @ c2
    return c + c2, r, float(np.linalg.norm(r))


def _qr_update(u: np.ndarray, lam: np.ndarray, i_prev: int, x: np.ndarray,
               split: tuple[np.ndarray, np.ndarray, float] | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
    """The ``"qr"`` route of the update: same result as Eqs. (4)-(9), without the Gram matrix.

    The weighted eigenimages and the new frame are ``A = [sqrt(i_prev lam) u ; x] = B^T Q``
    with ``Q = [u ; r/|r|]`` orthonormal and ``B`` upper triangular,
    ``B = [[diag(sqrt(i_prev lam)), c], [0, |r|]]``.  With ``B = W S Z^T`` (SVD) the new unit
    eigenimages are ``W^T Q`` and the eigenvalues of ``V_i = A A^T / i`` are ``S^2 / i``.
    Returns all ``K_i`` eigenvalues (descending; the last is 0 when the frame lies in the span)
    and the eigenimages of the positive ones.
    """
    i = i_prev + 1
    k = lam.size
    c, r, rho = split if split is not None else _residual_split(u, x)
    b = np.zeros((k + 1, k + 1))
    b[np.arange(k), np.arange(k)] = np.sqrt(i_prev * lam)
    b[:k, k] = c
    b[k, k] = rho
    if rho > 0:
        q = np.vstack([u, r[None, :] / rho])
        wl, sv, _ = np.linalg.svd(b)
    else:                          # the frame lies in the span: rank cannot grow
        q = u
        wl, sv, _ = np.linalg.svd(b[:k])
        sv = np.concatenate([sv, [0.0]])
    g = sv ** 2 / i
    phi = wl.T @ q
    phi /= np.linalg.norm(phi, axis=1, keepdims=True)
    return g, _sign_fix(phi)


# ---------------------------------------------------------------------------------------------
# classic fixed-rank recursive SVD
# ---------------------------------------------------------------------------------------------
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
        if isinstance(n_components, bool) or not isinstance(n_components, Integral) \
                or n_components < 1:
            raise ValueError(f"n_components must be a positive integer, got {n_components!r}")
        self.n_components = int(n_components)
        self._buffer: list[np.ndarray] = []
        self._u: np.ndarray | None = None
        self._lam: np.ndarray | None = None
        self.n_frames_seen_ = 0
        self.frame_shape_: tuple[int, ...] | None = None

    def partial_fit(self, frame: Any) -> "RecursiveSVD":
        """Add one frame; returns ``self``."""
        a = _as_frame(frame)
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
        for f in _as_frames(frames):
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


# ---------------------------------------------------------------------------------------------
# the adaptive recursive SVD: novelty detector and filter (Table 1)
# ---------------------------------------------------------------------------------------------
class NoveltyFilter:
    """Adaptive recursive SVD novelty detector and filter (Table 1 of Vermeulen & Casasent).

    Parameters
    ----------
    novelty_threshold : float in [0, 1]
        ``T_d`` of Eq. (8): a frame is novel (and updates the model) when ``n_i > T_d``.
        ``T_d = 0`` means every frame is used, including one that lies exactly in the span of
        the eigenimages (``n_i = 0``): its energy still belongs to the correlation matrix.
    information_threshold : float in [0, 1]
        ``T_I`` of Eq. (11): the smallest number of eigenimages whose information fractions
        (Eq. (10)) sum to at least ``T_I`` is kept.  With ``T_d = 0`` and ``T_I = 1`` the
        filter reproduces the batch eigen-decomposition of the correlation matrix of all
        frames (up to rounding).  With ``T_I = 1`` the ``"qr"`` route keeps every fraction
        above its rounding level (about ``1e-29``); the ``"vip"`` route drops fractions below
        1e-12 and says so with an :class:`EigenvalueDroppedWarning` when one of them is above
        its rounding level (about ``1e-14``).
    method : {"qr", "vip"}
        Numerical route of the update (see the module docstring): ``"qr"`` (default) works
        with the residual of the new frame and keeps the eigenimages orthonormal to rounding
        even for near-duplicate frames; ``"vip"`` is the paper's bordered VIP matrix (Eqs.
        (4)-(9)), which squares the condition number.  Both give the same VIP matrix record,
        novelty and eigen-decomposition in exact arithmetic.

    Attributes
    ----------
    eigenvalues_ : ndarray (K,)
        Eigenvalues ``lambda_{i,k}`` of the VIP matrix ``V_i`` kept after the last update
        (the correlation matrix of the ``i`` novel frames, Eq. (4)), descending.
    eigenimages_ : ndarray (K, ...) shaped like the frames
        Unit-norm eigenimages (orthonormal when flattened), pixel sum >= 0.
    components_ : ndarray (K, n_pixels)
        The same, flattened (scikit-learn convention).
    information_fractions_ : ndarray
        ``F_{i,k}`` of Eq. (10) over the ``K_i`` candidate eigenimages of the last update
        (before the excess ones were discarded).
    rank_ : int
        The rank estimate of Eq. (11) after the last update (``len(eigenvalues_)``).
    vip_matrix_ : ndarray
        The VIP matrix of the last frame processed (novel or not).
    novelty_ : float
        ``n_i`` of the last frame processed.
    n_updates_ : int
        Iteration counter ``i``: number of novel frames used (the first frame included).
    n_frames_seen_ : int
        Sequence counter ``j``.
    """

    def __init__(self, novelty_threshold: float = 0.001, information_threshold: float = 0.99,
                 method: str = "qr") -> None:
        self.novelty_threshold = _check_fraction(novelty_threshold, "novelty_threshold")
        self.information_threshold = _check_fraction(information_threshold,
                                                     "information_threshold")
        self.method = _check_method(method)
        self._u: np.ndarray | None = None
        self._lam: np.ndarray | None = None
        self.frame_shape_: tuple[int, ...] | None = None
        self.n_updates_ = 0
        self.n_frames_seen_ = 0

    # -- the algorithm ------------------------------------------------------------------------
    def _vector(self, frame: Any, name: str = "frame") -> np.ndarray:
        a = _as_frame(frame, name)
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
        import warnings

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
        for f in _as_frames(frames):
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
        if isinstance(pixel_threshold, bool) or not isinstance(pixel_threshold, Real) \
                or not np.isfinite(pixel_threshold) or pixel_threshold < 0:
            raise ValueError(f"pixel_threshold must be a finite number >= 0, got {pixel_threshold!r}")
        x = _as_frame(frame)
        return np.abs(x - self.reconstruct(x)) > pixel_threshold

    def weighted_eigenimages(self) -> np.ndarray:
        """The paper's ``sqrt(lambda_k) Phi_k`` in grey levels (``(K, *frame_shape)``).

        For a static scene the first one approaches the background (Fig. 3).
        """
        return np.sqrt(self.eigenvalues_)[(slice(None),) + (None,) * len(self.frame_shape_)] \
            * self.eigenimages_


# ---------------------------------------------------------------------------------------------
# per-class novelty classifier (Table 2)
# ---------------------------------------------------------------------------------------------
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
        self.novelty_threshold = _check_fraction(novelty_threshold, "novelty_threshold")
        self.information_threshold = _check_fraction(information_threshold,
                                                     "information_threshold")
        self.method = _check_method(method)

    def fit(self, frames: Any, labels: Sequence[Any]) -> "NoveltyClassifier":
        """Train one filter per label on ``frames`` (``(n, *shape)``) in the given order."""
        x = _as_frames(frames)
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
        x = _as_frames(frames)
        return np.array([[f.novelty(xi) for f in self.filters_.values()] for xi in x])

    def predict(self, frames: Any) -> np.ndarray:
        """Class of smallest novelty for every frame."""
        nov = self.novelties(frames)
        return self.classes_[np.argmin(nov, axis=1)]


# ---------------------------------------------------------------------------------------------
# a whole sequence, recorded as in Figs. 2-3
# ---------------------------------------------------------------------------------------------
def process_sequence(frames: Any, novelty_threshold: float, information_threshold: float,
                     pixel_threshold: float = 8.0, method: str = "qr") -> list[FrameRecord]:
    """Run a :class:`NoveltyFilter` over ``frames`` and record every frame (Figs. 2-3).

    Parameters
    ----------
    frames : array_like, shape (I, H, W) or (I, ...)
    novelty_threshold, information_threshold : float
        ``T_d`` and ``T_I``.
    pixel_threshold : float
        ``T_f`` of the novel-pixel image (8 grey levels in the paper).
    method : {"qr", "vip"}
        Numerical route of the update (:class:`NoveltyFilter`).

    Returns
    -------
    list of FrameRecord
    """
    x = _as_frames(frames)
    filt = NoveltyFilter(novelty_threshold, information_threshold, method)
    out = []
    for j, frame in enumerate(x, start=1):
        if j == 1:
            mask = np.ones(frame.shape, dtype=bool)
        else:
            mask = filt.novel_pixels(frame, pixel_threshold)
        iteration = filt.n_updates_ + 1 if j > 1 else 1
        n, novel = filt.partial_fit(frame)
        out.append(FrameRecord(
            frame=j, iteration=iteration, novelty=n, novel=novel,
            vip=filt.vip_matrix_.copy(),
            fractions=filt.information_fractions_.copy() if novel else None,
            rank=filt.rank_, novel_pixels=mask, eigenvalues=filt.eigenvalues_,
            first_eigenimage=filt.weighted_eigenimages()[0]))
    return out


# ---------------------------------------------------------------------------------------------
# Fig. 1: the block diagram, drawn from TABLE1_STEPS and TABLE1_FLOW
# ---------------------------------------------------------------------------------------------
def plot_block_diagram(ax=None):
    """Draw Fig. 1 (block diagram of the adaptive recursive SVD) from :data:`TABLE1_STEPS`.

    Steps are stacked top to bottom; decision steps (those with conditional exits in
    :data:`TABLE1_FLOW`) are drawn as diamonds, loops as arrows on the sides.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch, Polygon

    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 7.2))
    steps = dict(TABLE1_STEPS)
    decisions = {a for a, _, c in TABLE1_FLOW if c}
    order = [s for s, _ in TABLE1_STEPS] + [0]
    ypos = {s: -k for k, s in enumerate(order)}
    w, h = 4.6, 0.62
    for s in order:
        y = ypos[s]
        label = "end" if s == 0 else f"{s}. {steps[s]}"
        if s in decisions:
            ax.add_patch(Polygon([(-w / 2, y), (0, y + h / 1.6), (w / 2, y), (0, y - h / 1.6)],
                                 closed=True, fc="#fdf3d8", ec="k", lw=0.8))
        else:
            ax.add_patch(FancyBboxPatch((-w / 2, y - h / 2), w, h,
                                        boxstyle="round,pad=0.02,rounding_size=0.12",
                                        fc="#e8eef7" if s else "#dddddd", ec="k", lw=0.8))
        ax.text(0, y, label, ha="center", va="center", fontsize=7.2)
    for a, b, cond in TABLE1_FLOW:
        ya, yb = ypos[a], ypos[b]
        if yb == ya - 1:     # straight down
            ax.annotate("", xy=(0, yb + h / 2 + 0.02), xytext=(0, ya - h / 2 - 0.02),
                        arrowprops=dict(arrowstyle="-|>", lw=0.8, color="k"))
            if cond:
                ax.text(0.08, (ya + yb) / 2, cond, fontsize=6.5, va="center", style="italic")
        else:                # loop back on a side
            side = 1 if cond == "not novel" else -1
            x0 = side * w / 2
            xs = side * (w / 2 + 0.5)
            ax.annotate("", xy=(x0 if b not in decisions else side * w / 2, yb),
                        xytext=(xs, yb), arrowprops=dict(arrowstyle="-|>", lw=0.8, color="k"))
            ax.plot([x0, xs, xs], [ya, ya, yb], color="k", lw=0.8)
            ax.text(xs + side * 0.08, (ya + yb) / 2, cond, fontsize=6.5, style="italic",
                    rotation=90, va="center", ha="left" if side > 0 else "right")
    ax.set_xlim(-w / 2 - 1.0, w / 2 + 1.0)
    ax.set_ylim(ypos[0] - 0.6, 0.6)
    ax.set_axis_off()
    return ax
