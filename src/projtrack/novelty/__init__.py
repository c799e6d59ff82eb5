"""KL novelty detector and filter (Vermeulen & Casasent 1988, chapter 6 of the Casasent report).

P. Vermeulen and D. Casasent, "KL techniques for optimal processing of time sequential
imagery", Proc. SPIE 1007 (1988).  Equation numbers below are those of that paper.

Modules:

- :mod:`~projtrack.novelty.batch`: batch KL through the ``I x I`` VIP matrix (Eqs. (2)-(3)), :func:`vip_matrix`, :func:`batch_kl`, :func:`correlation_matrix`.
- :mod:`~projtrack.novelty.updates`: one recursive update by a new frame, the paper's VIP route and the QR route (Eqs. (4)-(9)), :data:`METHODS`.
- :mod:`~projtrack.novelty.recursive_svd`: :class:`RecursiveSVD`, the classic fixed-rank recursive SVD (Murakami & Kumar).
- :mod:`~projtrack.novelty.filter`: :class:`NoveltyFilter`, the adaptive recursive SVD of Table 1 (Eqs. (4)-(12)).
- :mod:`~projtrack.novelty.classifier`: :class:`NoveltyClassifier`, one filter per class, smallest novelty wins (Table 2).
- :mod:`~projtrack.novelty.sequence`: :func:`process_sequence`, a filter run over a sequence with every frame recorded (Figs. 2-3).
- :mod:`~projtrack.novelty.results`: :class:`KLBasis`, :class:`NoveltyResult`, :class:`FrameRecord`, :class:`EigenvalueDroppedWarning`.
- :mod:`~projtrack.novelty.table1`: :data:`TABLE1_STEPS` and :data:`TABLE1_FLOW`, Table 1 as data (Fig. 1 is drawn from it).
- ``_checks`` and ``_linalg`` (private): the package's frame and threshold checks, and the sign and ordering conventions of eigenimages.

Fig. 1 itself is drawn by :func:`projtrack.experiments.novelty.plot_block_diagram`.

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

from .batch import batch_kl, correlation_matrix, vip_matrix
from .classifier import NoveltyClassifier
from .filter import NoveltyFilter
from .recursive_svd import RecursiveSVD
from .results import EigenvalueDroppedWarning, FrameRecord, KLBasis, NoveltyResult
from .sequence import process_sequence
from .table1 import TABLE1_FLOW, TABLE1_STEPS
from .updates import METHODS

__all__ = [
    "TABLE1_STEPS",
    "TABLE1_FLOW",
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
