"""Joint probabilistic data association (JPDA): Fisher & Casasent (1989).

Implements chapter 4 of Casasent's 1989 report (J. L. Fisher and D. P. Casasent,
"Fast JPDA multitarget tracking algorithm", Appl. Opt. 28, 1989): measurement
validation (Sec. II.A), feasibility matrices and eq. (1) (Sec. II.B), the conventional
computation of the association probabilities beta_jt and eq. (2) (Sec. II.C), the
modified validation matrix (MVM) of eqs. (3)-(4) (Sec. III.A), the fast algorithm with
measurements-used (MU) bit words and eq. (6) (Secs. III.B-D) with the operation counts
of Tables IV-V, a numerical model of the frequency-multiplexed vector-inner-product
processor of Fig. 5 (Sec. IV), and a JPDA tracker built on ``filterpy`` Kalman filters
(the optional dependency ``pip install "projtrack[kalman]"``).

Notation follows the paper: ``m`` measurements, ``T`` targets, a binary validation
matrix of shape ``(m, T + 1)`` whose column 0 (the "no target", i.e. clutter, column)
is all ones, and feasibility matrices that pick exactly one 1 per row with at most one
1 per target column (Sec. II.B). The MVM has shape ``(m + 1, T)``: row ``j`` holds
``P_D,t f_t(z_j) / lambda`` (eq. 4), zero where measurement ``j`` is not validated for
target ``t``, and row 0 the weight of "target ``t`` has no validated measurement".

The convention for row 0: ``1 - P_D,t P_G`` (a detection may fall outside the gate of
probability ``P_G``), the standard JPDA weights; :func:`mvm_from_positions` builds the
MVM this way from the predicted positions and innovation covariances, and
:class:`JPDATracker` uses it. The paper's eq. (3) writes ``1 - P_D,t``, the case
``P_G = 1`` in row 0; :func:`modified_validation_matrix` builds that form (the book's
chapter uses it). :func:`beta` accepts either.

Probability model
-----------------
A feasible joint event assigns each target either "not detected" or a distinct
validated measurement; its weight is the product over targets of the MVM entry it
uses (row 0 for an undetected target), i.e. the product of the individual event
probabilities of Sec. II.C. With a clutter (false-measurement) density ``lambda``
the standard JPDA weights (Fortmann, Bar-Shalom & Scheffe 1983) are recovered by
dividing rows ``j >= 1`` by ``lambda`` (see :func:`mvm_from_positions`); the paper's
form is ``lambda = 1``. ``beta[j, t]`` is the probability of the events in which
measurement ``j`` is associated with target ``t`` and ``beta[0, t]`` that target ``t``
has no validated measurement, eq. (2); every column sums to 1.

.. rubric:: Modules

* :mod:`~projtrack.jpda.validation`: chi-square gates, validation matrix and MVM (II.A, III.A),
  :func:`mvm_from_positions`.
* :mod:`~projtrack.jpda.feasible`: feasible joint events, eq. (1), feasibility matrices (II.B).
* :mod:`~projtrack.jpda.enumeration`: beta by enumerating the feasible events (II.C).
* :mod:`~projtrack.jpda.paper`: the paper's fast algorithm: MU words, stages, eq. (6) (III.B-D).
* :mod:`~projtrack.jpda.forward_backward`: exact beta by one forward-backward sweep over subsets.
* :mod:`~projtrack.jpda.association`: the default beta: independent clusters, sweep on each.
* :mod:`~projtrack.jpda.opcounts`: the operation counter and the counts of Tables IV-V.
* :mod:`~projtrack.jpda.optical`: model of the vector-inner-product processor of Fig. 5 (IV).
* :mod:`~projtrack.jpda.trackers`: JPDA and global-nearest-neighbour trackers (Kalman filters).
"""

from __future__ import annotations

from .validation import (
    gate_threshold,
    mahalanobis_sq,
    modified_validation_matrix,
    mvm_from_positions,
    mvm_to_validation,
    validation_matrix,
)
from .feasible import (
    count_feasible_events,
    feasibility_matrices,
    iter_feasibility_matrices,
)
from .enumeration import beta_enumerated
from .paper import (
    beta_paper,
    mu_words,
    stage_expressions,
    stage_update,
    vector_size,
    vector_size_text_formula,
)
from .forward_backward import beta_forward_backward
from .association import beta, clusters
from .opcounts import OpCount, conventional_op_count, fast_op_count
from .optical import optical_vip_schedule, optical_vip_stage
from .trackers import GNNTracker, JPDATracker

__all__ = [
    "count_feasible_events",
    "iter_feasibility_matrices",
    "feasibility_matrices",
    "gate_threshold",
    "mahalanobis_sq",
    "validation_matrix",
    "modified_validation_matrix",
    "mvm_from_positions",
    "mvm_to_validation",
    "OpCount",
    "beta",
    "beta_enumerated",
    "beta_paper",
    "beta_forward_backward",
    "clusters",
    "mu_words",
    "vector_size",
    "vector_size_text_formula",
    "stage_expressions",
    "conventional_op_count",
    "fast_op_count",
    "optical_vip_schedule",
    "optical_vip_stage",
    "stage_update",
    "JPDATracker",
    "GNNTracker",
]
