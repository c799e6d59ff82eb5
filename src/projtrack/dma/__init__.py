"""Trajectory estimation on manifolds: the DMA algorithm of Marques et al. (2002).

J. S. Marques et al., "Trajectory estimation on manifolds", Signal Processing, 2002. Every
public name of the modules below is re-exported here (``projtrack.dma.viterbi``, ...):

* :mod:`~projtrack.dma.hmm`: Viterbi, forward filtering and forward-backward in log space, dense or sparse (Sec. 3.3).
* :mod:`~projtrack.dma.manifold`: EM/GMM regions, local PCA frames and k-means prototypes (Sec. 3.1, eqs. (1)-(9)).
* :mod:`~projtrack.dma.motion`: Markov motion models on prototypes, learned or from a velocity field (Sec. 3.2, eqs. (10)-(13)).
* :mod:`~projtrack.dma.sensors`: sensor models ``p(y | u_k)`` of the three examples (eqs. (14)-(15)).
* :mod:`~projtrack.dma.estimator`: the :class:`DMA` estimator that ties them together.

The set-ups of the paper's three examples and the baselines used by the book are
experiments: :mod:`projtrack.experiments.dma`.
"""

from projtrack.dma.estimator import DMA
from projtrack.dma.hmm import (
    check_row_stochastic,
    forward_backward,
    forward_filter,
    log_transitions,
    path_log_probability,
    viterbi,
)
from projtrack.dma.manifold import DiscreteManifold, learn_manifold, select_n_regions
from projtrack.dma.motion import (
    estimate_start,
    estimate_transitions,
    neighbor_graph,
    transitions_from_velocity_field,
)
from projtrack.dma.sensors import ActivePixelSensor, LinearGaussianSensor, RangeCosineSensor, SensorModel

__all__ = [
    "viterbi",
    "forward_filter",
    "forward_backward",
    "path_log_probability",
    "log_transitions",
    "check_row_stochastic",
    "DiscreteManifold",
    "learn_manifold",
    "select_n_regions",
    "estimate_transitions",
    "estimate_start",
    "neighbor_graph",
    "transitions_from_velocity_field",
    "SensorModel",
    "LinearGaussianSensor",
    "RangeCosineSensor",
    "ActivePixelSensor",
    "DMA",
]
