"""Exactness of the fast beta methods: random MVMs compared with the enumeration (JPDA chapter).

Each trial draws one random, partly gated MVM (``m = 0..7``, ``T = 1..7``) and returns the
largest differences of :func:`projtrack.jpda.beta_paper` and :func:`projtrack.jpda.beta`
from :func:`projtrack.jpda.beta_enumerated`, the column-sum error, and the difference of
a baseline that must fail (per-target PDA, without mutual exclusion). It also records how far
the unnormalized columns of eq. (6) are from sharing one sum (Sec. III.D normalizes all of
them by the sum of any one column), and the same for the baseline
(:func:`normalization_summary`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_int, as_real, as_rng
from projtrack.jpda import beta, beta_enumerated, beta_paper

from .optables import beta_in_situ

__all__ = ["equivalence_trial", "equivalence_study", "equivalence_summary", "normalization_summary"]


def equivalence_trial(rng: np.random.Generator) -> dict:
    """One random MVM: largest differences of the fast methods (and a baseline) from enumeration.

    Returns a dict with ``paper`` and ``fast`` (max ``|beta - beta_enumerated|``), ``sum``
    (max ``|sum_j beta_jt - 1|`` of the enumeration), ``pda`` (the baseline's difference),
    ``size`` (``m T``), ``norm`` (the relative spread ``(max - min) / max`` of the column sums
    of eq. (6), from :func:`~projtrack.experiments.jpda.beta_in_situ`) and ``pda_norm`` (the
    same for the baseline's unnormalized columns, the MVM's own columns).
    """
    rng = as_rng(rng)
    m_, T_ = int(rng.integers(0, 8)), int(rng.integers(1, 8))
    w = rng.random((m_ + 1, T_)) * (rng.random((m_ + 1, T_)) < rng.uniform(0.2, 1.0))
    w[0] = rng.uniform(0.05, 0.95, T_)
    ref = beta_enumerated(w)
    pda = w / w.sum(axis=0)  # per-target PDA, no mutual exclusion
    sums = beta_in_situ(w).column_sums  # eq. (6): A b' for every target, before normalization

    def spread(x: np.ndarray) -> float:
        return float((x.max() - x.min()) / x.max())

    return {"paper": float(np.abs(beta_paper(w) - ref).max()),
            "fast": float(np.abs(beta(w) - ref).max()),
            "sum": float(np.abs(ref.sum(axis=0) - 1).max()),
            "pda": float(np.abs(pda - ref).max()), "size": m_ * T_,
            "norm": spread(sums), "pda_norm": spread(w.sum(axis=0))}


def equivalence_study(n_trials: int, seed: int) -> pd.DataFrame:
    """``n_trials`` :func:`equivalence_trial` rows (through :func:`projtrack.montecarlo.run`)."""
    n_trials = as_int(n_trials, "n_trials", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    return pd.DataFrame(montecarlo.run(equivalence_trial, n_trials, np.random.default_rng(seed)))


def equivalence_summary(study: pd.DataFrame, bound: float = 1e-12) -> pd.DataFrame:
    """The largest difference from the enumeration of each method in an :func:`equivalence_study`.

    Rows: the paper's algorithm, the package default and the per-target PDA baseline;
    columns ``method``, ``largest |beta - enumeration|`` and ``below <bound>``.
    """
    if not isinstance(study, pd.DataFrame) or not {"paper", "fast", "pda"} <= set(study.columns) or study.empty:
        raise ValueError("study must be a non-empty equivalence_study table")
    bound = as_real(bound, "bound", 0.0, low_open=True)
    worst = [float(study[k].max()) for k in ("paper", "fast", "pda")]
    return pd.DataFrame({"method": ["paper's algorithm (beta_paper)", "package default (beta)",
                                    "per-target PDA (baseline)"],
                         "largest |beta - enumeration|": worst,
                         f"below {bound:g}": [w < bound for w in worst]})


def normalization_summary(study: pd.DataFrame, bound: float = 1e-12) -> pd.DataFrame:
    """Do all columns share one normalization constant? The largest spread in an equivalence study.

    Rows: the columns of eq. (6) (the paper's algorithm, before normalization) and the
    per-target PDA baseline, whose columns have no reason to share a sum; columns
    ``unnormalized columns``, ``largest relative spread of the column sums`` and
    ``below <bound>``.
    """
    if not isinstance(study, pd.DataFrame) or not {"norm", "pda_norm"} <= set(study.columns) or study.empty:
        raise ValueError("study must be a non-empty equivalence_study table")
    bound = as_real(bound, "bound", 0.0, low_open=True)
    worst = [float(study[k].max()) for k in ("norm", "pda_norm")]
    return pd.DataFrame({"unnormalized columns": ["eq. (6), A b' (paper's algorithm)",
                                                  "per-target PDA (baseline)"],
                         "largest relative spread of the column sums": worst,
                         f"below {bound:g}": [x < bound for x in worst]})
