"""Banks of correlation filters, one per class, scored by their largest peaks (Sec. III.C)."""

from __future__ import annotations

from typing import Sequence

import numpy as np
import scipy.fft

from projtrack._validation import as_bool, as_int

from ._checks import as_angles, as_stack
from .projections import project_stack

__all__ = ["CorrelationFilterBank", "ProjectionCorrelationClassifier", "Correlation2DClassifier"]


def _batch_correlate1d(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Full correlations of every row of ``a (n, L1)`` with every row of ``b (C, L2)``: ``(n, C, L1+L2-1)``."""
    L = a.shape[1] + b.shape[1] - 1
    nfft = scipy.fft.next_fast_len(L, real=True)
    A = np.fft.rfft(a, nfft)
    B = np.fft.rfft(b[:, ::-1], nfft)
    return np.fft.irfft(A[:, None, :] * B[None, :, :], nfft)[..., :L]


class CorrelationFilterBank:
    """Base class of the correlation filter banks: one reference filter per class.

    Subclasses define ``_build`` (prepare the filters) and ``decision_function`` (one
    score per image and class); :meth:`fit`, :meth:`predict` and :meth:`score` are shared.

    Parameters
    ----------
    zero_mean : bool
        Remove the mean of filters and inputs (Sec. III.B).
    normalize : bool
        Scale filters and inputs to unit energy (Sec. III.C).
    """

    def __init__(self, zero_mean: bool = True, normalize: bool = True):
        self.zero_mean = as_bool(zero_mean, "zero_mean")
        self.normalize = as_bool(normalize, "normalize")

    def _prepare(self, X: np.ndarray) -> np.ndarray:
        X = X.copy()
        if self.zero_mean:
            X -= X.mean(axis=(1, 2), keepdims=True)
        if self.normalize:
            e = np.sqrt(np.sum(X * X, axis=(1, 2), keepdims=True))
            if np.any(e == 0):
                raise ValueError("an image has zero energy (after zero-mean) and cannot be normalized")
            X = X / e
        return X

    def fit(self, X: np.ndarray, y: Sequence[object]):
        """Store one reference filter per class (the mean of its training images).

        Parameters
        ----------
        X : array_like, shape (n, H, W)
            Training images (for the paper's bank: the 26 clean letters).
        y : sequence of labels, length n
            At least two distinct classes (a bank of one filter cannot discriminate).

        Raises
        ------
        ValueError
            If ``X`` is not a finite, non-empty stack of images, ``y`` does not hold one
            label per image or fewer than two classes are given.
        """
        X = as_stack(X, "X")
        y_arr = np.asarray(y)
        if y_arr.ndim != 1 or len(y_arr) != len(X):
            raise ValueError(f"y must be 1-D with one label per image ({len(X)}), got shape {y_arr.shape}")
        classes = np.unique(y_arr)
        if len(classes) < 2:
            raise ValueError(f"y must contain at least 2 classes to classify between, got {len(classes)}: "
                             f"{classes.tolist()}")
        self.classes_ = classes
        refs = np.stack([X[y_arr == c].mean(axis=0) for c in self.classes_])
        self.shape_ = X.shape[1:]
        self.filters_ = self._prepare(refs)
        self._build()
        return self

    def _check_X(self, X: np.ndarray) -> np.ndarray:
        if not hasattr(self, "filters_"):
            raise ValueError("this classifier is not fitted yet: call fit(X, y) first")
        X = as_stack(X, "X")
        if X.shape[1:] != self.shape_:
            raise ValueError(f"X images must have shape {self.shape_}, got {X.shape[1:]}")
        return self._prepare(X)

    def _build(self) -> None:
        """Prepare the filters after :meth:`fit` (subclasses)."""

    def decision_function(self, X: np.ndarray) -> np.ndarray:
        """One score per image and class (defined by the subclasses)."""
        raise NotImplementedError("use ProjectionCorrelationClassifier or Correlation2DClassifier")

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Class with the largest score (:meth:`decision_function`) for each image."""
        scores = self.decision_function(X)
        return self.classes_[np.argmax(scores, axis=1)]

    def score(self, X: np.ndarray, y: Sequence[object]) -> float:
        """Fraction of images classified correctly."""
        return float(np.mean(self.predict(X) == np.asarray(y)))


class ProjectionCorrelationClassifier(CorrelationFilterBank):
    """Bank of 1-D projection-correlation filters, one set per class (Section III.C).

    Each class keeps the projections of its (zero-mean, unit-energy) reference at the
    given angles. An input is projected at the same angles, correlated (full, bipolar)
    with every class's projections, and scored by the **sum over angles of the largest
    correlation peak**; the class with the largest sum wins ("For each filter pair, the
    largest pair of correlation peaks was measured and the peak values were summed").

    Parameters
    ----------
    angles : sequence of float, default (0, 90)
        Projection angles in degrees (0 = vertical, 90 = horizontal; the paper's bank
        used horizontal and vertical, with 45 degrees optional).
    zero_mean : bool, default True
        Remove the mean of filters and inputs (Sec. III.B).
    normalize : bool, default True
        Scale filters and inputs to unit energy (Sec. III.C).
    normalize_projections : bool, default True
        Also scale every 1-D filter and every input projection to unit energy, so that
        by the Cauchy-Schwarz inequality a noise-free input scores highest on its own
        class. With 2-D normalization only, a letter with large projections (``B``)
        out-scores the true class even on noise-free inputs (shown in the book).

    Attributes
    ----------
    classes_ : numpy.ndarray
        The class labels, sorted.
    filters_ : numpy.ndarray, shape (n_classes, H, W)
        The reference image of each class (the mean of its training images, after the
        zero-mean and energy normalization).

    Examples
    --------
    Three 12 x 12 letters as references, then shifted noisy copies to classify:

    >>> import numpy as np
    >>> from projtrack.correlators import ProjectionCorrelationClassifier
    >>> L = np.zeros((12, 12)); L[2:10, 3] = 1; L[9, 3:9] = 1
    >>> T = np.zeros((12, 12)); T[2, 2:10] = 1; T[2:10, 6] = 1
    >>> O = np.zeros((12, 12))
    >>> O[2:10, 2] = O[2:10, 9] = O[2, 2:10] = O[9, 2:10] = 1
    >>> clf = ProjectionCorrelationClassifier(angles=(0, 90))
    >>> clf = clf.fit(np.stack([L, T, O]), ["L", "T", "O"])
    >>> rng = np.random.default_rng(0)
    >>> X = np.stack([np.roll(a, (1, -1), axis=(0, 1)) + rng.normal(0, 0.2, a.shape)
    ...               for a in (L, T, O)])
    >>> clf.predict(X)
    array(['L', 'T', 'O'], dtype='<U1')
    >>> np.round(clf.decision_function(X[:1]), 2)  # classes_ L, O, T
    array([[1.8 , 1.4 , 1.58]])
    """

    def __init__(self, angles: Sequence[float] = (0.0, 90.0), zero_mean: bool = True, normalize: bool = True,
                 normalize_projections: bool = True):
        super().__init__(zero_mean, normalize)
        self.angles = as_angles(angles)
        self.normalize_projections = as_bool(normalize_projections, "normalize_projections")

    def _unit(self, P: np.ndarray) -> np.ndarray:
        if not self.normalize_projections:
            return P
        e = np.sqrt(np.sum(P * P, axis=1, keepdims=True))
        if np.any(e == 0):
            raise ValueError("a projection has zero energy and cannot be normalized")
        return P / e

    def _build(self) -> None:
        self.filter_projections_ = [self._unit(project_stack(self.filters_, t)) for t in self.angles]

    def peak_scores(self, X: np.ndarray) -> np.ndarray:
        """Largest projection-correlation peak per image, class and angle: ``(n, n_classes, n_angles)``."""
        X = self._check_X(X)
        out = np.empty((len(X), len(self.classes_), len(self.angles)))
        for a, t in enumerate(self.angles):
            P = self._unit(project_stack(X, t))
            out[:, :, a] = _batch_correlate1d(P, self.filter_projections_[a]).max(axis=2)
        return out

    def decision_function(self, X: np.ndarray) -> np.ndarray:
        """Sum over angles of the largest projection-correlation peak, ``(n, n_classes)``."""
        return self.peak_scores(X).sum(axis=2)

    def summed_output_scores(self, X: np.ndarray) -> np.ndarray:
        """Largest value of the correlations summed over angles at a common lag, ``(n, n_classes)``.

        This is what one detector of a frequency-multiplexed space-integrating correlator
        (Fig. 8) reads: the correlations of all projections of one filter set add at the
        same time step before the peak is taken. It equals :meth:`decision_function` only
        when the peaks of all angles fall at the same lag (for example, centred inputs).

        Raises
        ------
        ValueError
            If the classifier is not fitted, ``X`` is not a stack of images of the fitted
            shape, or the projections at the bank's angles differ in length (they cannot
            share one time axis).
        """
        X = self._check_X(X)
        lengths = {P.shape[1] for P in self.filter_projections_}
        if len(lengths) != 1:
            raise ValueError(f"summed outputs need projections of equal length at every angle, got {sorted(lengths)}")
        total = None
        for a, t in enumerate(self.angles):
            P = self._unit(project_stack(X, t))
            c = _batch_correlate1d(P, self.filter_projections_[a])
            total = c if total is None else total + c
        return total.max(axis=2)


class Correlation2DClassifier(CorrelationFilterBank):
    """The same filter bank with full 2-D bipolar correlations: score = largest 2-D peak.

    Parameters
    ----------
    zero_mean, normalize : bool
        As for :class:`ProjectionCorrelationClassifier`.
    chunk : int, default 256
        Inputs correlated per FFT batch (memory bound).
    """

    def __init__(self, zero_mean: bool = True, normalize: bool = True, chunk: int = 256):
        super().__init__(zero_mean, normalize)
        self.chunk = as_int(chunk, "chunk", minimum=1)

    def _build(self) -> None:
        H, W = self.shape_
        self._fft_shape = (scipy.fft.next_fast_len(2 * H - 1, real=True), scipy.fft.next_fast_len(2 * W - 1, real=True))
        self._F = np.fft.rfft2(self.filters_[:, ::-1, ::-1], self._fft_shape)

    def decision_function(self, X: np.ndarray) -> np.ndarray:
        """Largest 2-D correlation value per image and class, ``(n, n_classes)``."""
        X = self._check_X(X)
        H, W = self.shape_
        out = np.empty((len(X), len(self.classes_)))
        for s in range(0, len(X), self.chunk):
            A = np.fft.rfft2(X[s:s + self.chunk], self._fft_shape)
            c = np.fft.irfft2(A[:, None] * self._F[None], self._fft_shape)[..., :2 * H - 1, :2 * W - 1]
            out[s:s + self.chunk] = c.max(axis=(2, 3))
        return out

