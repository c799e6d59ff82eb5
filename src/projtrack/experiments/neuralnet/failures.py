"""How the net's runs end, and the paper's account of its failures (Sec. VI).

The paper: "As noise increased, correct convergence or two other conditions occurred (the
neural net wandered with no apparent trend to convergence or it oscillated between two
states, one being the correct solution and the other differing in one target/measurement
pairing.)" Table 1 has three failed runs (one of ten at 5% noise, two at 7.5%), so the two
modes were both seen among three failures and no third one was.

* :data:`MODES`: how a run ends;
* :func:`one_pairing_away`: whether a state differs from the correct one in the pairing of a
  single target in a single frame;
* :func:`run_modes`: the mode of every run of a batch (a 2-cycle is followed for one more sweep
  to find the other state of the cycle); :func:`draws_modes` for the runs of several draws;
* :func:`mode_counts`: how many runs end in each mode;
* :func:`mode_probability`: the probability that the paper's three failures, drawn from given
  shares of failure modes, show both of its modes and no other.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from projtrack._validation import as_int, as_probability
from projtrack.neuralnet import NetResult, is_correct_assignment, run_net, states_to_assignment

__all__ = ["MODES", "FAILURE_MODES", "PAPER_FAILURES", "one_pairing_away", "run_modes", "draws_modes", "mode_counts",
           "mode_probability"]

#: How a run ends: converged to the correct or to a wrong state; a 2-cycle between the correct
#: state and one a single pairing away (the paper's oscillation); any other cycle; wandering
#: (neither converged nor cycling within the sweep limit).
MODES: tuple[str, ...] = ("correct", "wrong", "cycle with the truth", "other cycle", "wandering")

#: The modes of a failed run.
FAILURE_MODES: tuple[str, ...] = MODES[1:]

#: Failed runs in Table 1: 10 - 9 at 5% noise and 10 - 8 at 7.5%.
PAPER_FAILURES = 3


def one_pairing_away(X: np.ndarray, truth: np.ndarray) -> bool:
    """Whether ``X`` differs from ``truth`` in the pairings of one target in one frame only.

    The two states must differ, and only within one row ``X[i, :, a]``: one pairing added,
    removed or moved to another measurement. (A swap of two targets' measurements changes two
    rows and is two pairings.)

    Parameters
    ----------
    X, truth : array_like of 0/1, shape (N_T, N_M, N_P)
    """
    X, truth = np.asarray(X), np.asarray(truth)
    if X.shape != truth.shape or X.ndim != 3:
        raise ValueError(f"X and truth must be states of one shape (N_T, N_M, N_P), got {X.shape} and {truth.shape}")
    rows = np.any(X != truth, axis=1)  # (N_T, N_P)
    return int(rows.sum()) == 1


def run_modes(D: np.ndarray, res: NetResult, labels: Sequence[np.ndarray], **net_options: Any) -> np.ndarray:
    """The :data:`MODES` label of every run of a batch.

    Parameters
    ----------
    D : ndarray, shape (B, N_P - 2, N_M, N_M, N_M)
        The distance tensor of each run (as given to :func:`projtrack.neuralnet.run_net`).
    res : NetResult
        The batch's result.
    labels : sequence of B arrays of int, shape (N_P, N_M)
        ``labels[k][a, alpha]``: the target of measurement ``alpha`` of frame ``a`` in run ``k``'s
        data set. The net's targets are interchangeable: a state is correct when every target
        follows one true track (:func:`projtrack.neuralnet.is_correct_assignment`).
    **net_options
        The options the nets ran with (``coefficients``, ``offset``, ``mode``, ``self_coupling``,
        ``exact_energy``): a run that ends in a 2-cycle is swept once more with them, which gives
        the other state of the cycle.

    Returns
    -------
    ndarray of str, shape (B,)
    """
    if not isinstance(res, NetResult):
        raise TypeError(f"res must be a NetResult, got {type(res).__name__}")
    D = np.asarray(D, dtype=float)
    B = len(res.status)
    if D.ndim != 5 or D.shape[0] != B:
        raise ValueError(f"D must hold one tensor per run, shape ({B}, N_P - 2, N_M, N_M, N_M), got {D.shape}")
    labels = list(labels)
    if len(labels) != B:
        raise ValueError(f"labels must hold one array per run ({B}), got {len(labels)}")
    out = np.full(B, "wandering", dtype=object)
    for k in range(B):
        if res.status[k] == "converged":
            out[k] = "correct" if _is_correct(res.states[k], labels[k]) else "wrong"
        elif res.status[k] == "oscillating":
            out[k] = "other cycle"
    two = np.flatnonzero((res.status == "oscillating") & (res.period == 2))
    if two.size:
        partner = run_net(D[two], res.states[two].astype(float), max_iter=1, **net_options).states
        for j, k in enumerate(two):
            a, b = res.states[k], partner[j]
            if _is_correct(a, labels[k]) and one_pairing_away(b, a) or _is_correct(b, labels[k]) and one_pairing_away(a, b):
                out[k] = "cycle with the truth"
    return out.astype(str)


def _is_correct(X: np.ndarray, labels: np.ndarray) -> bool:
    """Whether binary states are the correct assignment (targets are interchangeable)."""
    return is_correct_assignment(states_to_assignment(X), np.asarray(labels))


def draws_modes(draws: Sequence[Any], results: Sequence[NetResult], **net_options: Any) -> list[np.ndarray]:
    """:func:`run_modes` for the nets of several simulation draws, as one batch.

    Parameters
    ----------
    draws : sequence of SimulationDraw
        As from :func:`projtrack.experiments.neuralnet.draw_simulation`.
    results : sequence of NetResult
        One per draw (:func:`projtrack.experiments.neuralnet.run_draws`).
    **net_options
        The options the nets ran with.

    Returns
    -------
    list of ndarray of str
        The modes of each draw's runs.
    """
    draws, results = list(draws), list(results)
    if len(draws) != len(results) or not draws:
        raise ValueError(f"draws and results must be non-empty and of one length, got {len(draws)}, {len(results)}")
    D = np.concatenate([np.repeat(d.D, d.n_starts, axis=0) for d in draws])
    labels = [d.scenes[k // d.n_starts].labels for d in draws for k in range(len(d.X0))]
    res = NetResult(np.concatenate([r.states for r in results]), np.concatenate([r.status for r in results]),
                    np.concatenate([r.iterations for r in results]), np.concatenate([r.period for r in results]))
    modes = run_modes(D, res, labels, **net_options)
    out, k = [], 0
    for r in results:
        out.append(modes[k:k + len(r.status)])
        k += len(r.status)
    return out


def mode_counts(modes: np.ndarray) -> dict[str, int]:
    """How many runs end in each of :data:`MODES`."""
    modes = np.asarray(modes)
    unknown = set(np.unique(modes)) - set(MODES)
    if unknown:
        raise ValueError(f"modes holds labels that are not in MODES: {sorted(unknown)}")
    return {m: int((modes == m).sum()) for m in MODES}


def mode_probability(truth_cycle: float, wandering: float, n_failures: int = PAPER_FAILURES) -> float:
    """Probability that ``n_failures`` failed runs show both of the paper's modes and no other.

    With the shares ``q`` (a 2-cycle with the correct state) and ``w`` (wandering) among failed
    runs, ``n`` independent failures all fall in these two modes, at least one in each, with
    probability ``(q + w)^n - q^n - w^n``.

    Parameters
    ----------
    truth_cycle, wandering : float
        The shares ``q`` and ``w`` (``q + w <= 1``).
    n_failures : int, default 3
        Failed runs in the paper's Table 1 (:data:`PAPER_FAILURES`).
    """
    q = as_probability(truth_cycle, "truth_cycle")
    w = as_probability(wandering, "wandering")
    if q + w > 1 + 1e-12:
        raise ValueError(f"truth_cycle + wandering must be <= 1, got {q + w}")
    n = as_int(n_failures, "n_failures", minimum=2)
    return float(max(0.0, min(1.0, (q + w) ** n - q ** n - w ** n)))
