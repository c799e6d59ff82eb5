"""The :class:`DMA` estimator: learn a manifold and a motion model, retrieve trajectories.

Ties together :mod:`~projtrack.dma.manifold` (Sec. 3.1 of Marques et al., 2002),
:mod:`~projtrack.dma.motion` (Sec. 3.2), :mod:`~projtrack.dma.sensors` and
:mod:`~projtrack.dma.hmm` (Sec. 3.3).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.dma.hmm import forward_backward, forward_filter, log_transitions, viterbi
from projtrack.dma.manifold import learn_manifold
from projtrack.dma.motion import estimate_start, estimate_transitions, neighbor_graph
from projtrack.dma.sensors import SensorModel

__all__ = ["DMA"]


class DMA:
    """Discrete manifold analysis: learn a manifold and a motion model, retrieve trajectories.

    ``fit`` runs the off-line steps of Marques et al. on training trajectories (manifold
    learning, Sec. 3.1; motion model, Sec. 3.2); ``predict_path`` / ``predict`` retrieve
    the prototype sequence from observations with a sensor model (Sec. 3.3) and map it to
    the manifold with eq. (7).

    Parameters
    ----------
    n_regions : int
        Number of regions ``M``.
    n_prototypes : int
        Prototypes per region.
    dim : int, optional
        Local hyperplane dimension (default: chosen by ``max_mse``; if both are None,
        ``dim = 1``).
    max_mse : float, optional
        Eq. (9) error bound that chooses the dimension per region.
    alpha : float
        Smoothing pseudo-count of :func:`estimate_transitions`.
    neighbor_radius : float, optional
        If given, smoothing also allows transitions between prototypes closer than this.
    rng : numpy.random.Generator, optional
        Randomness for EM and k-means (default ``numpy.random.default_rng(0)``).

    Attributes
    ----------
    manifold_ : DiscreteManifold
    transitions_ : scipy.sparse.csr_array, shape (K, K)
    start_ : numpy.ndarray, shape (K,)
    prototypes_ : numpy.ndarray, shape (K, n)
    """

    def __init__(
        self,
        n_regions: int = 8,
        n_prototypes: int = 8,
        *,
        dim: int | None = None,
        max_mse: float | None = None,
        alpha: float = 1e-3,
        neighbor_radius: float | None = None,
        rng: np.random.Generator | None = None,
    ):
        # checked at the door, so that a wrong argument is named before any work is done
        self.n_regions = as_int(n_regions, "n_regions", minimum=1)
        self.n_prototypes = as_int(n_prototypes, "n_prototypes", minimum=1)
        self.dim = None if dim is None else as_int(dim, "dim", minimum=1)
        self.max_mse = None if max_mse is None else as_real(max_mse, "max_mse", 0.0, low_open=True)
        self.alpha = as_real(alpha, "alpha", 0.0, low_open=True)
        self.neighbor_radius = (None if neighbor_radius is None
                                else as_real(neighbor_radius, "neighbor_radius", 0.0, low_open=True))
        self.rng = None if rng is None else as_rng(rng)

    def fit(self, trajectories: Sequence[object]) -> "DMA":
        """Learn the manifold (Sec. 3.1) and the motion model (Sec. 3.2).

        Parameters
        ----------
        trajectories : list of array_like, each (T_i, n)
            Training trajectories (points on the manifold, in time order).
        """
        if isinstance(trajectories, np.ndarray) and trajectories.ndim == 2:
            trajectories = [trajectories]
        trajs = [as_array(t, "trajectories[i]", ndim=2, finite=False) for t in trajectories]
        if not trajs or sum(len(t) for t in trajs) == 0:
            raise ValueError("trajectories is empty: fit needs training trajectories")
        if len({t.shape[1] for t in trajs}) != 1:
            raise ValueError("all trajectories must have the same number of columns")
        X = np.vstack(trajs)
        rng = np.random.default_rng(0) if self.rng is None else as_rng(self.rng)
        dim = self.dim if (self.dim is not None or self.max_mse is not None) else 1
        self.manifold_ = learn_manifold(X, self.n_regions, self.n_prototypes, rng, dim=dim, max_mse=self.max_mse)
        self.prototypes_ = self.manifold_.prototypes
        S = self.manifold_.n_prototypes
        seqs = [self.manifold_.quantize(t) for t in trajs if len(t)]
        nb = None if self.neighbor_radius is None else neighbor_graph(self.prototypes_, self.neighbor_radius)
        self.transitions_ = estimate_transitions(seqs, S, alpha=self.alpha, neighbors=nb)
        self.start_ = estimate_start(seqs, S)
        self.training_sequences_ = seqs
        return self

    def _check_fitted(self) -> None:
        if not hasattr(self, "transitions_"):
            raise ValueError("this DMA instance is not fitted yet: call fit first")

    def log_emission(self, observations: object, sensor: SensorModel) -> np.ndarray:
        """``(N, K)`` sensor log-likelihoods, checked against the prototypes."""
        self._check_fitted()
        if not isinstance(sensor, SensorModel):
            raise TypeError("sensor must be a projtrack.dma.SensorModel")
        if sensor.n_states != self.manifold_.n_prototypes:
            raise ValueError(f"sensor has {sensor.n_states} states, the model {self.manifold_.n_prototypes} prototypes")
        return sensor.log_likelihoods(observations)

    def predict_path(self, observations: object, sensor: SensorModel, *, method: str = "viterbi") -> np.ndarray:
        """Prototype index sequence from observations.

        ``method``: ``"viterbi"`` (off-line MAP path), ``"smooth"`` (per-instant argmax of
        forward-backward posteriors) or ``"filter"`` (on-line argmax of forward posteriors).
        """
        le = self.log_emission(observations, sensor)
        with np.errstate(divide="ignore"):
            ls = np.log(self.start_)
        lt = log_transitions(self.transitions_)
        if method == "viterbi":
            return viterbi(ls, lt, le)
        if method == "smooth":
            return np.argmax(forward_backward(ls, lt, le)[0], axis=1)
        if method == "filter":
            return np.argmax(forward_filter(ls, lt, le), axis=1)
        raise ValueError(f"method must be 'viterbi', 'smooth' or 'filter', got {method!r}")

    def predict(self, observations: object, sensor: SensorModel, *, method: str = "viterbi") -> np.ndarray:
        """Points on the manifold (eq. (7)) of the retrieved prototype sequence, ``(N, n)``."""
        return self.prototypes_[self.predict_path(observations, sensor, method=method)]

    def quantize(self, X: object) -> np.ndarray:
        """Prototype index of each point (Fig. 5)."""
        self._check_fitted()
        return self.manifold_.quantize(X)
