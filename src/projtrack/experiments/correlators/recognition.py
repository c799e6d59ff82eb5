"""The 26-letter recognition test of Sec. III.C as Monte Carlo studies of noisy letters.

* :func:`noise_sweep`: correctness of several filter banks on every letter over a grid of
  noise levels;
* :func:`recognition_study`: correctness of the paper's bank on several glyph sets (one
  alphabet each) and noise laws, by the sum of separate peaks (Sec. III.C) and by the
  summed detector output of the frequency-multiplexed correlator (Sec. IV);
* :func:`margin_study`: the difference between the true class's score and the best false
  one, per projection, for several banks (does a 45-degree filter widen it?);
* :func:`predictor_accuracy`: correctness of any classifiers (banks, baselines) over a
  grid of noise levels, all on the same noisy images;
* :func:`detection_study`: the paper's bank scored on its rectified output (negative values
  set to 0, Secs. III.B and V) and on the magnitude of its output (what an intensity
  detector sees), on the same noisy images.

Each trial draws one noisy copy of every letter (:func:`projtrack.scenes.letters.noisy`,
noise over the central ``extent x extent`` pixels, then the image made zero mean) per noise
level; trials run through :func:`projtrack.montecarlo.run`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_choice, as_int, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["noise_sweep", "recognition_study", "RULES", "margin_study", "predictor_accuracy", "DETECTIONS",
           "detection_study"]

#: The two classification rules of :func:`recognition_study`.
RULES: tuple[str, ...] = ("sum of peaks", "summed output")


def _check_bank(bank: object, name: str) -> None:
    if not (hasattr(bank, "predict") and hasattr(bank, "classes_")):
        raise TypeError(f"{name} must be a fitted classifier (with predict and classes_), got {type(bank).__name__}")


def _check_images(images: object, labels: object) -> tuple[np.ndarray, np.ndarray]:
    images = as_array(images, "images", ndim=3, allow_empty=False)
    labels = np.asarray(labels)
    if labels.shape != (len(images),):
        raise ValueError(f"labels must hold one label per image ({len(images)}), got shape {labels.shape}")
    return images, labels


def _check_sigmas(sigmas: object) -> np.ndarray:
    sig = as_array(sigmas, "sigmas", ndim=1, allow_empty=False)
    if np.any(sig < 0):
        raise ValueError(f"sigmas must be >= 0, got {sig}")
    return sig


def _check_extent(extent: object) -> int | None:
    return None if extent is None else as_int(extent, "extent", minimum=1)


def _sweep_trial(rng, banks, images, labels, sigmas, extent, distribution):
    out = np.zeros((len(sigmas), len(banks), len(images)), dtype=bool)
    for j, s in enumerate(sigmas):
        X = letters.noisy(images, float(s), rng, extent=extent, distribution=distribution)[0]
        for c, clf in enumerate(banks.values()):
            out[j, c] = clf.predict(X) == labels
    return out


def noise_sweep(banks: Mapping[str, object], images: np.ndarray, labels: Sequence[object],
                sigmas: Sequence[float], n_draws: int, rng: np.random.Generator, *,
                extent: int | None = None, distribution: str = "gaussian") -> np.ndarray:
    """Which letters each bank gets right, over a grid of noise levels.

    Every trial and noise level draws one noisy copy of every image (noise of standard
    deviation sigma over the central ``extent x extent`` pixels, ``None`` for the whole
    image; zero-mean after the noise, as in Sec. III.B), classified by all ``banks``.

    Parameters
    ----------
    banks : mapping of name to fitted classifier
        Classifiers with ``predict`` (e.g. :class:`projtrack.correlators.ProjectionCorrelationClassifier`).
    images : array_like, shape (n, H, W)
        The clean images (the 26 letters).
    labels : sequence, length n
        The true label of each image.
    sigmas : sequence of float
        Noise levels (>= 0).
    n_draws : int
        Trials (noisy copies of every image per level).
    rng : numpy.random.Generator
        Parent generator of the trials.
    extent : int, optional
        Side of the central square that receives noise.
    distribution : {"gaussian", "uniform"}
        The noise law (:func:`projtrack.scenes.letters.noisy`).

    Returns
    -------
    numpy.ndarray of bool, shape (n_draws, len(sigmas), len(banks), n)
        Correct or not, per trial, level, bank and image.
    """
    if not banks:
        raise ValueError("banks must not be empty")
    for k, b in banks.items():
        _check_bank(b, f"banks[{k!r}]")
    images, labels_arr = _check_images(images, labels)
    sig = _check_sigmas(sigmas)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    distribution = as_choice(distribution, "distribution", ("gaussian", "uniform"))
    res = montecarlo.run(_sweep_trial, n_draws, as_rng(rng), dict(banks), images, labels_arr, sig,
                         _check_extent(extent), distribution)
    return np.array(res)


def _study_trial(rng, banks, images, labels, sigmas, laws, extent):
    out = np.zeros((len(banks), len(laws), len(sigmas), len(RULES), images.shape[1]), dtype=bool)
    for a, (bank, imgs) in enumerate(zip(banks, images)):
        for k, law in enumerate(laws):
            for j, s in enumerate(sigmas):
                X = letters.noisy(imgs, float(s), rng, extent=extent, distribution=law)[0]
                out[a, k, j, 0] = bank.predict(X) == labels
                out[a, k, j, 1] = bank.classes_[np.argmax(bank.summed_output_scores(X), axis=1)] == labels
    return out


def recognition_study(banks: Sequence[object], alphabets: np.ndarray, labels: Sequence[object],
                      sigmas: Sequence[float], laws: Sequence[str], n_draws: int, rng: np.random.Generator, *,
                      extent: int | None = None) -> np.ndarray:
    """Which letters the paper's bank gets right, per glyph set, noise law, level and rule.

    Parameters
    ----------
    banks : sequence of fitted ProjectionCorrelationClassifier
        One bank per glyph set, fitted on that glyph set's letters.
    alphabets : array_like, shape (len(banks), n, H, W)
        The clean letters of each glyph set.
    labels : sequence, length n
        The true label of each letter.
    sigmas : sequence of float
        Noise levels (standard deviations, >= 0).
    laws : sequence of {"gaussian", "uniform"}
        Noise laws (uniform noise of the same standard deviation).
    n_draws : int
        Trials; each draws one noisy copy of every letter per glyph set, law and level.
    rng : numpy.random.Generator
        Parent generator of the trials.
    extent : int, optional
        Side of the central square that receives noise (``None``: the whole image).

    Returns
    -------
    numpy.ndarray of bool, shape (n_draws, len(banks), len(laws), len(sigmas), 2, n)
        Correct or not by the sum of separate peaks (the bank's ``predict``, Sec. III.C)
        and by the summed detector output (``summed_output_scores``, Sec. IV), in the
        order of :data:`RULES`.
    """
    banks = list(banks)
    if not banks:
        raise ValueError("banks must not be empty")
    for i, b in enumerate(banks):
        _check_bank(b, f"banks[{i}]")
        if not hasattr(b, "summed_output_scores"):
            raise TypeError(f"banks[{i}] must be a ProjectionCorrelationClassifier (with summed_output_scores)")
    alphabets = as_array(alphabets, "alphabets", ndim=4, allow_empty=False)
    if len(alphabets) != len(banks):
        raise ValueError(f"alphabets must hold one alphabet per bank ({len(banks)}), got {len(alphabets)}")
    _, labels_arr = _check_images(alphabets[0], labels)
    sig = _check_sigmas(sigmas)
    laws = [as_choice(law, "laws", ("gaussian", "uniform")) for law in laws]
    if not laws:
        raise ValueError("laws must not be empty")
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    res = montecarlo.run(_study_trial, n_draws, as_rng(rng), banks, alphabets, labels_arr, sig, laws,
                         _check_extent(extent))
    return np.array(res)


def _margin_trial(rng, banks, images, labels, sigmas, extent):
    out = np.zeros((len(sigmas), len(banks), len(images)))
    for j, s in enumerate(sigmas):
        X = letters.noisy(images, float(s), rng, extent=extent)[0]
        for b, bank in enumerate(banks):
            scores = bank.decision_function(X) / len(bank.angles)
            idx = np.searchsorted(bank.classes_, labels)
            true = scores[np.arange(len(X)), idx]
            others = scores.copy()
            others[np.arange(len(X)), idx] = -np.inf
            out[j, b] = true - others.max(axis=1)
    return out


def margin_study(banks: Sequence[object], images: np.ndarray, labels: Sequence[object], sigmas: Sequence[float],
                 n_draws: int, rng: np.random.Generator, *, extent: int | None = None) -> np.ndarray:
    """Difference between the true class's score and the largest false one, per projection.

    Every trial and level draws one noisy copy of every image (Gaussian noise, as in
    :func:`noise_sweep`), scored by every bank (``decision_function``: the sum over the
    bank's angles of the largest projection-correlation peak) and divided by the bank's
    number of angles, so that banks of two and three projections compare on one scale
    (each unit-energy peak is at most 1). A positive margin is a correct decision.

    Returns
    -------
    numpy.ndarray, shape (n_draws, len(sigmas), len(banks), n)
    """
    banks = list(banks)
    if not banks:
        raise ValueError("banks must not be empty")
    for i, b in enumerate(banks):
        _check_bank(b, f"banks[{i}]")
        if not (hasattr(b, "decision_function") and hasattr(b, "angles")):
            raise TypeError(f"banks[{i}] must be a ProjectionCorrelationClassifier (with angles)")
    images, labels_arr = _check_images(images, labels)
    for i, b in enumerate(banks):
        if not np.all(np.isin(labels_arr, b.classes_)):
            raise ValueError(f"labels must be classes of banks[{i}]")
    sig = _check_sigmas(sigmas)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    return np.array(montecarlo.run(_margin_trial, n_draws, as_rng(rng), banks, images, labels_arr, sig,
                                   _check_extent(extent)))


def _predictor_trial(rng, predictors, images, labels, sigmas, extent):
    out = np.zeros((len(sigmas), len(predictors), len(images)), dtype=bool)
    for j, s in enumerate(sigmas):
        X = letters.noisy(images, float(s), rng, extent=extent)[0]
        out[j] = [predict(X) == labels for predict in predictors]
    return out


def predictor_accuracy(predictors: Mapping[str, Callable[[np.ndarray], np.ndarray]], images: np.ndarray,
                       labels: Sequence[object], sigmas: Sequence[float], n_draws: int,
                       rng: np.random.Generator, *, extent: int | None = None) -> np.ndarray:
    """Which images each predictor gets right, over a grid of Gaussian noise levels.

    Every trial and noise level draws one noisy copy of every image (Gaussian noise over
    the central ``extent x extent`` pixels, zero-mean after,
    :func:`projtrack.scenes.letters.noisy`) and gives the same stack ``(n, H, W)`` to every
    predictor.

    Parameters
    ----------
    predictors : mapping of name to callable
        Each maps a stack of images to one predicted label per image (e.g. a bank's
        ``predict``, or a baseline classifier with its own preprocessing).
    images, labels, sigmas, n_draws, rng, extent
        As for :func:`noise_sweep`.

    Returns
    -------
    numpy.ndarray of bool, shape (n_draws, len(sigmas), len(predictors), n)
    """
    if not predictors:
        raise ValueError("predictors must not be empty")
    for k, f in predictors.items():
        if not callable(f):
            raise TypeError(f"predictors[{k!r}] must be callable, got {type(f).__name__}")
    images, labels_arr = _check_images(images, labels)
    sig = _check_sigmas(sigmas)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    res = montecarlo.run(_predictor_trial, n_draws, as_rng(rng), list(predictors.values()), images, labels_arr, sig,
                         _check_extent(extent))
    return np.array(res)


#: The output detections of :func:`detection_study`.
DETECTIONS: tuple[str, ...] = ("rectified", "magnitude")


def _correlate_rows(P: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Full correlations of every row of ``P (n, L1)`` with every row of ``F (c, L2)``: ``(n, c, L1 + L2 - 1)``."""
    L = P.shape[1] + F.shape[1] - 1
    nfft = 1 << (L - 1).bit_length()
    out = np.fft.irfft(np.fft.rfft(P, nfft)[:, None, :] * np.fft.rfft(F[:, ::-1], nfft)[None, :, :], nfft)
    return out[..., :L]


def _detected_scores(bank, X: np.ndarray) -> np.ndarray:
    """Sum over the bank's angles of the largest rectified and of the largest absolute output: ``(2, n, classes)``."""
    X = np.array(X, dtype=float)
    if bank.zero_mean:
        X -= X.mean(axis=(1, 2), keepdims=True)
    if bank.normalize:
        X /= np.sqrt(np.sum(X * X, axis=(1, 2), keepdims=True))
    out = np.zeros((2, len(X), len(bank.classes_)))
    for a, t in enumerate(bank.angles):
        P = C.project_stack(X, t)
        if bank.normalize_projections:
            P = P / np.linalg.norm(P, axis=1, keepdims=True)
        c = _correlate_rows(P, bank.filter_projections_[a])
        out[0] += np.maximum(c.max(axis=2), 0.0)
        out[1] += np.abs(c).max(axis=2)
    return out


def _detection_trial(rng, bank, images, labels, sigmas, extent):
    out = np.zeros((len(sigmas), len(DETECTIONS), len(images)), dtype=bool)
    for j, s in enumerate(sigmas):
        X = letters.noisy(images, float(s), rng, extent=extent)[0]
        scores = _detected_scores(bank, X)
        out[j] = bank.classes_[np.argmax(scores, axis=2)] == labels
    return out


def detection_study(bank: object, images: np.ndarray, labels: Sequence[object], sigmas: Sequence[float],
                    n_draws: int, rng: np.random.Generator, *, extent: int | None = None) -> np.ndarray:
    """Which letters a projection bank gets right when its outputs are rectified or magnitude-detected.

    The bank (a fitted :class:`projtrack.correlators.ProjectionCorrelationClassifier`)
    scores each class by the sum over its angles of the largest value of each output, the
    output either rectified (negative values set to 0, the "thresholded at zero volts"
    output of Sec. III.B; its largest value is that of the bipolar output unless all are
    negative) or magnitude-detected (``|c|``, what an intensity detector keeps, whose
    negative peaks become positive). Noise as in :func:`predictor_accuracy` (Gaussian).

    Returns
    -------
    numpy.ndarray of bool, shape (n_draws, len(sigmas), len(DETECTIONS), n)
        Correct or not, per trial, level, detection (:data:`DETECTIONS`) and image.
    """
    _check_bank(bank, "bank")
    if not all(hasattr(bank, k) for k in ("filter_projections_", "angles", "normalize_projections")):
        raise TypeError("bank must be a fitted ProjectionCorrelationClassifier")
    images, labels_arr = _check_images(images, labels)
    sig = _check_sigmas(sigmas)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    return np.array(montecarlo.run(_detection_trial, n_draws, as_rng(rng), bank, images, labels_arr, sig,
                                   _check_extent(extent)))
