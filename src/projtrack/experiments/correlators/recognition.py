"""The 26-letter recognition test of Sec. III.C as Monte Carlo studies of noisy letters.

* :func:`noise_sweep`: correctness of several filter banks on every letter over a grid of
  noise levels, plus the reference bank under the two readings of "uniform" noise;
* :func:`noise_extent_study`: correctness of one bank when the noise covers only the
  central part of the image, under several noise laws, and of its summed-output rule;
* :func:`predictor_accuracy`: correctness of any classifiers (banks, baselines) over a
  grid of Gaussian noise levels, all on the same noisy images.

Each trial draws one noisy copy of every letter (:func:`projtrack.scenes.letters.noisy`)
per noise level; trials run through :func:`projtrack.montecarlo.run`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_array, as_choice, as_int, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["noise_sweep", "noise_extent_study", "predictor_accuracy"]


def _check_bank(bank: object, name: str) -> None:
    if not (hasattr(bank, "predict") and hasattr(bank, "classes_")):
        raise TypeError(f"{name} must be a fitted classifier (with predict and classes_), got {type(bank).__name__}")


def _check_images(images: object, labels: object) -> tuple[np.ndarray, np.ndarray]:
    images = as_array(images, "images", ndim=3, allow_empty=False)
    labels = np.asarray(labels)
    if labels.shape != (len(images),):
        raise ValueError(f"labels must hold one label per image ({len(images)}), got shape {labels.shape}")
    return images, labels


def _sweep_trial(rng, banks, images, labels, sigmas, reference):
    out = np.zeros((len(sigmas), len(banks) + 2, len(images)), dtype=bool)
    for j, s in enumerate(sigmas):
        X = letters.noisy(images, float(s), rng)[0]
        for c, clf in enumerate(banks.values()):
            out[j, c] = clf.predict(X) == labels
        Xu = letters.noisy(images, float(s), rng, distribution="uniform")[0]
        out[j, len(banks)] = banks[reference].predict(Xu) == labels
        Xr = letters.noisy(images, float(s) / np.sqrt(3), rng, distribution="uniform")[0]
        out[j, len(banks) + 1] = banks[reference].predict(Xr) == labels
    return out


def noise_sweep(banks: Mapping[str, object], images: np.ndarray, labels: Sequence[object],
                sigmas: Sequence[float], n_draws: int, rng: np.random.Generator, *,
                reference: str) -> np.ndarray:
    """Which letters each bank gets right, over a grid of Gaussian noise levels.

    Every trial and noise level draws one copy of every image with Gaussian noise of
    standard deviation sigma over the whole image (zero-mean after the noise, as in
    Sec. III.B) for all ``banks``; then the ``reference`` bank also sees uniform noise of
    standard deviation sigma, and uniform noise on ``[-sigma, sigma]``.

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
    reference : str
        Name of the bank that also sees the uniform noises.

    Returns
    -------
    numpy.ndarray of bool, shape (n_draws, len(sigmas), len(banks) + 2, n)
        Correct or not, per trial, level, column (the banks in order, then the two
        uniform readings) and image.
    """
    if not banks:
        raise ValueError("banks must not be empty")
    for k, b in banks.items():
        _check_bank(b, f"banks[{k!r}]")
    reference = as_choice(reference, "reference", tuple(banks))
    images, labels_arr = _check_images(images, labels)
    sig = as_array(sigmas, "sigmas", ndim=1, allow_empty=False)
    if np.any(sig < 0):
        raise ValueError(f"sigmas must be >= 0, got {sig}")
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    res = montecarlo.run(_sweep_trial, n_draws, as_rng(rng), dict(banks), images, labels_arr, sig, reference)
    return np.array(res)


def _extent_trial(rng, bank, images, labels, sigmas, extents, laws, summed_sigmas):
    out = np.zeros((len(extents) * len(laws), len(sigmas), len(images)), dtype=bool)
    summed = np.zeros((len(extents), len(summed_sigmas), len(images)), dtype=bool)
    for i, (e, (law, f)) in enumerate((e, v) for e in extents for v in laws.values()):
        for j, s in enumerate(sigmas):
            X = letters.noisy(images, float(s) * f, rng, extent=e, distribution=law)[0]
            out[i, j] = bank.predict(X) == labels
            if law == "gaussian" and float(s) in summed_sigmas:
                summed[extents.index(e), summed_sigmas.index(float(s))] = (
                    bank.classes_[np.argmax(bank.summed_output_scores(X), axis=1)] == labels)
    return out, summed


def noise_extent_study(bank: object, images: np.ndarray, labels: Sequence[object], sigmas: Sequence[float],
                       extents: Sequence[int], laws: Mapping[str, tuple[str, float]],
                       summed_sigmas: Sequence[float], n_draws: int,
                       rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Which letters one bank gets right when the noise covers only the central ``extent x extent``.

    For every extent and noise law (``laws``: name -> ``(distribution, factor)``, the
    noise standard deviation being ``factor * sigma``; ``distribution`` as in
    :func:`projtrack.scenes.letters.noisy`) and every sigma, one noisy copy of every
    image is classified. On the Gaussian readings at the ``summed_sigmas`` the
    summed-output rule (:meth:`~projtrack.correlators.ProjectionCorrelationClassifier.summed_output_scores`)
    is scored as well.

    Returns
    -------
    ok : numpy.ndarray of bool, shape (n_draws, len(extents) * len(laws), len(sigmas), n)
        Readings ordered extent-major (every law of the first extent first).
    summed : numpy.ndarray of bool, shape (n_draws, len(extents), len(summed_sigmas), n)
    """
    _check_bank(bank, "bank")
    if not hasattr(bank, "summed_output_scores"):
        raise TypeError("bank must have summed_output_scores (a ProjectionCorrelationClassifier)")
    images, labels_arr = _check_images(images, labels)
    sig = as_array(sigmas, "sigmas", ndim=1, allow_empty=False)
    if np.any(sig < 0):
        raise ValueError(f"sigmas must be >= 0, got {sig}")
    extents = tuple(as_int(e, "extents", minimum=1) for e in extents)
    if not extents or not laws:
        raise ValueError("extents and laws must not be empty")
    laws = {str(k): (as_choice(d, f"laws[{k!r}]", ("gaussian", "uniform")), as_real(f, f"laws[{k!r}]", 0.0))
            for k, (d, f) in laws.items()}
    summed_sigmas = tuple(as_real(s, "summed_sigmas", 0.0) for s in summed_sigmas)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    res = montecarlo.run(_extent_trial, n_draws, as_rng(rng), bank, images, labels_arr, sig, extents, laws,
                         summed_sigmas)
    return np.array([r[0] for r in res]), np.array([r[1] for r in res])


def _predictor_trial(rng, predictors, images, labels, sigmas):
    out = np.zeros((len(sigmas), len(predictors), len(images)), dtype=bool)
    for j, s in enumerate(sigmas):
        X = letters.noisy(images, float(s), rng)[0]
        out[j] = [predict(X) == labels for predict in predictors]
    return out


def predictor_accuracy(predictors: Mapping[str, Callable[[np.ndarray], np.ndarray]], images: np.ndarray,
                       labels: Sequence[object], sigmas: Sequence[float], n_draws: int,
                       rng: np.random.Generator) -> np.ndarray:
    """Which images each predictor gets right, over a grid of Gaussian noise levels.

    Every trial and noise level draws one noisy copy of every image (Gaussian noise over
    the whole image, zero-mean after, :func:`projtrack.scenes.letters.noisy`) and gives
    the same stack ``(n, H, W)`` to every predictor.

    Parameters
    ----------
    predictors : mapping of name to callable
        Each maps a stack of images to one predicted label per image (e.g. a bank's
        ``predict``, or a baseline classifier with its own preprocessing).
    images, labels, sigmas, n_draws, rng
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
    sig = as_array(sigmas, "sigmas", ndim=1, allow_empty=False)
    if np.any(sig < 0):
        raise ValueError(f"sigmas must be >= 0, got {sig}")
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    res = montecarlo.run(_predictor_trial, n_draws, as_rng(rng), list(predictors.values()), images, labels_arr, sig)
    return np.array(res)
