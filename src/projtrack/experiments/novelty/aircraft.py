"""The aircraft study of Table 2 and of the rank claim (Section 2), on rendered aircraft.

Per-class novelty filters or batch KL bases are trained on rendered rolls
(:func:`projtrack.scenes.aircraft.render_rolls`) and tested on rolls between them:
the Table 2 novelty table (:func:`novelty_table`), the trivial one-mean-image baseline
(:func:`mean_image_correct`), recognition by the first ``m`` eigenimages
(:func:`recognized`, :func:`rank_claim_table`), the same under noise
(:func:`noisy_rates`, :func:`noise_rate_draws`, :func:`effective_rank`), the information
rank (:func:`info_rank`) and the classifiers' rate on noisy unseen rolls
(:func:`classifier_noise_draw`).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_probability, as_real, as_rng
from projtrack.novelty import KLBasis, NoveltyClassifier

__all__ = ["novelty_table", "mean_image_correct", "recognized", "rank_claim_table",
           "noisy_rates", "noise_rate_draws", "effective_rank", "info_rank", "centred_eigenvalues",
           "classifier_noise_draw"]


def novelty_table(clf: NoveltyClassifier, images: Mapping[str, Any], rolls: Sequence[float],
                  test_rolls: Sequence[float], names: Sequence[str],
                  row_order: Sequence[str] | None = None) -> pd.DataFrame:
    """Table 2: the novelty of test images against every class model, and the decision.

    Parameters
    ----------
    clf : NoveltyClassifier
        Fitted on the training rolls of the classes ``names``.
    images : mapping
        Class -> images ``(len(rolls), H, W)`` rendered at ``rolls``.
    rolls : sequence of float
        The rolls of ``images``.
    test_rolls : sequence of float
        The rolls tested for every class (each must be in ``rolls``).
    names : sequence of str
        The column order of the table.
    row_order : sequence of str, optional
        The order of the classes in the rows (default ``names``).

    Returns
    -------
    pandas.DataFrame
        One row per class and test roll: the novelty against each class (4 decimals),
        ``Classification`` (the class of smallest novelty) and ``Description`` (``"<class> <roll>°"``).
    """
    if not hasattr(clf, "filters_"):
        raise ValueError("clf must be a fitted NoveltyClassifier")
    rolls = list(rolls)
    missing = [r for r in test_rolls if r not in rolls]
    if missing:
        raise ValueError(f"test_rolls must be among rolls, missing {missing}")
    rows = []
    for n in (names if row_order is None else row_order):
        imgs = images[n][[rolls.index(r) for r in test_rolls]]
        nov = clf.novelties(imgs)                     # columns in clf.classes_ order
        for r, v in zip(test_rolls, nov):
            d = dict(zip(clf.classes_, v))
            rows.append({**{c: round(float(d[c]), 4) for c in names},
                         "Classification": names[int(np.argmin([d[c] for c in names]))],
                         "Description": f"{n} {r}°"})
    return pd.DataFrame(rows)


def mean_image_correct(train: Mapping[str, Any], tests: Mapping[str, Any]) -> int:
    """The trivial baseline: test images recognized by the normalized correlation with one mean image per class.

    Parameters
    ----------
    train : mapping
        Class -> training images ``(n, H, W)``; the classes (and their order) of the decision.
    tests : mapping
        True class -> test images, flattened ``(k, H*W)`` or ``(k, H, W)``.

    Returns
    -------
    int
        Number of test images whose largest ``(t . m_c)^2 / |t|^2`` (``m_c`` the unit mean
        image of class ``c``) is their own class.
    """
    names = list(train)
    unit = {}
    for c in names:
        a = np.asarray(train[c])
        m = a.reshape(len(a), -1).mean(axis=0)
        unit[c] = m / np.linalg.norm(m)
    correct = 0
    for n, t in tests.items():
        if n not in unit:
            raise ValueError(f"tests has a class {n!r} that train does not have")
        t = np.asarray(t, dtype=float)
        t = t.reshape(len(t), -1)
        score = np.stack([(t @ unit[c]) ** 2 / np.sum(t ** 2, axis=1) for c in names], axis=1)
        correct += int(np.sum(np.array(names)[np.argmax(score, axis=1)] == n))
    return correct


def _novelties(t: np.ndarray, bases: Mapping[str, KLBasis], m: int) -> np.ndarray:
    """``(k, n_classes)`` novelty of the flattened test images ``t`` against each class's top ``m``."""
    return np.stack([1 - np.sum((t @ bases[c].eigenimages[:m].reshape(m, -1).T) ** 2, axis=1)
                     / np.sum(t ** 2, axis=1) for c in bases], axis=1)


def recognized(tests: Mapping[str, np.ndarray], bases: Mapping[str, KLBasis], m: int) -> int:
    """Test images whose smallest novelty against the first ``m`` eigenimages of each class is their own.

    ``tests`` maps the true class to flattened float test images ``(k, H*W)``; ``bases`` maps
    each class to its :class:`~projtrack.novelty.KLBasis` (the decision's class order).
    """
    m = as_int(m, "m", minimum=1)
    order = list(bases)
    ok = 0
    for n, t in tests.items():
        if n not in bases:
            raise ValueError(f"tests has a class {n!r} that bases does not have")
        ok += int(np.sum(np.argmin(_novelties(t, bases, m), axis=1) == order.index(n)))
    return ok


def rank_claim_table(tests: Mapping[str, np.ndarray], bases: Mapping[str, KLBasis],
                     ms: Sequence[int]) -> pd.DataFrame:
    """Recognition and information fraction (Eq. (10)) held by the first ``m`` eigenimages.

    Returns
    -------
    pandas.DataFrame
        Index ``m``; ``recognized (of N)`` (``N`` the number of test images) and one
        ``info <class>`` column per class (4 decimals).
    """
    total = sum(len(t) for t in tests.values())
    rows = []
    for m in ms:
        correct = recognized(tests, bases, m)
        cum = [float(bases[n].eigenvalues[:m].sum() / bases[n].eigenvalues.sum()) for n in bases]
        rows.append({"m": m, f"recognized (of {total})": correct,
                     **{f"info {n}": round(c, 4) for n, c in zip(bases, cum)}})
    return pd.DataFrame(rows).set_index("m")


def noisy_rates(rng: np.random.Generator, tests: Mapping[str, np.ndarray],
                bases: Mapping[str, KLBasis], sigma: float, m_max: int) -> list[float]:
    """One noise draw: recognition rate for ``m = 1 .. m_max`` with white noise of std ``sigma`` added.

    The Monte Carlo trial of :func:`noise_rate_draws` (one noise image per test image, drawn
    class by class in the order of ``tests``).
    """
    rng = as_rng(rng)
    sigma = as_real(sigma, "sigma", 0.0)
    m_max = as_int(m_max, "m_max", minimum=1)
    total = sum(len(t) for t in tests.values())
    order = list(bases)
    rates = []
    noisy = {n: t + sigma * rng.standard_normal(t.shape) for n, t in tests.items()}
    for m in range(1, m_max + 1):
        ok = 0
        for n, t in noisy.items():
            ok += int(np.sum(np.argmin(_novelties(t, bases, m), axis=1) == order.index(n)))
        rates.append(ok / total)
    return rates


def noise_rate_draws(tests: Mapping[str, np.ndarray], bases: Mapping[str, KLBasis], sigma: float,
                     n_draws: int, rng: np.random.Generator, m_max: int = 8,
                     *, n_jobs: int | None = None) -> np.ndarray:
    """``(n_draws, m_max)`` recognition rates under noise, through :func:`projtrack.montecarlo.run`."""
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    return np.array(montecarlo.run(noisy_rates, n_draws, as_rng(rng), sigma=sigma, tests=tests,
                                   bases=bases, m_max=m_max, n_jobs=n_jobs))


def effective_rank(rate: Any, n_tests: int = 48) -> int:
    """The smallest ``m`` whose rate is within one test image of the best rate over ``m``."""
    rate = as_array(rate, "rate", ndim=1, allow_empty=False)
    n_tests = as_int(n_tests, "n_tests", minimum=1)
    return int(np.argmax(rate >= rate.max() - 1 / n_tests - 1e-12)) + 1


def info_rank(eigenvalues: Any, information_threshold: float) -> int:
    """Eq. (11) on a batch spectrum: the fewest eigenimages whose fractions sum to ``T_I``."""
    lam = as_array(eigenvalues, "eigenvalues", ndim=1, allow_empty=False)
    ti = as_probability(information_threshold, "information_threshold")
    c = np.cumsum(lam) / lam.sum()
    return int(np.searchsorted(c, ti) + 1)


def centred_eigenvalues(images: Any) -> np.ndarray:
    """Eigenvalues (descending) of the VIP matrix of ``images`` with their mean removed: those of ``C``.

    Section 2 states the rank for this matrix; the filter's own VIP matrix keeps the mean
    (``R``, the ``eigenvalues`` of the :class:`projtrack.novelty.KLBasis` of :func:`projtrack.novelty.batch_kl`).
    """
    x = as_array(images, "images", allow_empty=False)
    x = x.reshape(len(x), -1).astype(float)
    xc = x - x.mean(axis=0)
    lam = np.linalg.eigvalsh(xc @ xc.T / len(x))[::-1]
    return np.clip(lam, 0.0, None)


def classifier_noise_draw(rng: np.random.Generator, classifiers: Sequence[NoveltyClassifier],
                          clean: Any, truth: Any, sigmas: Sequence[float]) -> list[tuple[float, ...]]:
    """One noise image per test image, scaled by each ``sigma``: every classifier's recognition rate.

    Returns
    -------
    list of tuple
        Per sigma, one rate per classifier (the fraction of ``clean + sigma * noise``
        predicted as ``truth``).
    """
    rng = as_rng(rng)
    clean = as_array(clean, "clean", allow_empty=False)
    truth = np.asarray(truth)
    if truth.shape != clean.shape[:1]:
        raise ValueError(f"truth must have one label per image ({clean.shape[0]}), got shape {truth.shape}")
    noise = rng.standard_normal(clean.shape)
    return [tuple(float(np.mean(c.predict(clean + s * noise) == truth)) for c in classifiers)
            for s in sigmas]


def effective_rank_curve(tests: Mapping[str, np.ndarray], bases: Mapping[str, KLBasis],
                         sigmas: Sequence[float], n_draws: int, seed: int, m_max: int = 8,
                         *, n_jobs: int | None = None) -> pd.DataFrame:
    """The effective rank (:func:`effective_rank`) as a function of the noise ``sigma``.

    Every ``sigma`` uses the same noise draws (the children of
    ``numpy.random.default_rng(seed)``, scaled), so the curve moves with ``sigma`` only.

    Returns
    -------
    pandas.DataFrame
        Per ``sigma``: the mean number of the test images recognized with one eigenimage and with
        the best ``m`` (out of ``N`` test images), the effective rank, and whether three
        eigenimages do as well as the best ``m`` (within one test image).
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    total = sum(len(t) for t in tests.values())
    rows = []
    for s in sigmas:
        rate = noise_rate_draws(tests, bases, s, n_draws, np.random.default_rng(seed), m_max,
                                n_jobs=n_jobs).mean(axis=0)
        rows.append({"sigma": float(s), "recognized, m = 1": float(total * rate[0]),
                     "recognized, best m": float(total * rate.max()),
                     "effective rank": effective_rank(rate, total),
                     "three suffice": bool(rate[min(2, m_max - 1)] >= rate.max() - 1 / total - 1e-12)})
    return pd.DataFrame(rows)


def threshold_sweep(train: Mapping[str, Any], tests: Mapping[str, Any], thresholds: Sequence[float],
                    information_threshold: float = 0.97) -> pd.DataFrame:
    """Per-class novelty filters for several ``T_d``: images used, eigenimages kept, recognition.

    Parameters
    ----------
    train : mapping
        Class -> training images ``(n, H, W)`` in the order they are fed.
    tests : mapping
        True class -> test images ``(k, H, W)``.
    thresholds : sequence of float
        The ``T_d`` values.
    information_threshold : float
        ``T_I``.

    Returns
    -------
    pandas.DataFrame
        Per ``T_d``: the training images used per class (range), the eigenimages kept per class
        (range) and the test images recognized (of all).
    """
    names = list(train)
    x = np.concatenate([np.asarray(train[n]) for n in names])
    y = np.repeat(names, [len(train[n]) for n in names])
    tx = np.concatenate([np.asarray(tests[n]) for n in tests]).astype(float)
    ty = np.repeat(list(tests), [len(tests[n]) for n in tests])
    rows = []
    for td in thresholds:
        clf = NoveltyClassifier(novelty_threshold=as_probability(td, "thresholds"),
                                information_threshold=information_threshold).fit(x, y)
        used = [clf.filters_[n].n_updates_ for n in names]
        kept = [clf.filters_[n].rank_ for n in names]
        span = f"{min(used)}" if min(used) == max(used) else f"{min(used)}-{max(used)}"
        rows.append({"T_d": float(td), "images used per class": f"{span} of {len(train[names[0]])}",
                     "eigenimages per class": f"{min(kept)}-{max(kept)}" if min(kept) != max(kept) else f"{kept[0]}",
                     "recognized": f"{int(np.sum(clf.predict(tx) == ty))} of {len(ty)}"})
    return pd.DataFrame(rows)
