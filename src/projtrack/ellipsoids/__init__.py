"""Ellipsoids as symmetric matrices: projection, reconstruction and dynamics.

Implements W. C. Karl, G. C. Verghese and A. S. Willsky, "Reconstructing ellipsoids from
projections", CVGIP: Graphical Models and Image Processing 56(2), 1994 (KVW):

* representation (Sec. 2): a positive semidefinite (PSD) matrix ``X`` is the ellipsoid
  ``{z : z^T u <= h(u) = sqrt(u^T X u) for all unit u}`` (eq. 1), equivalently
  ``{z : z^T X^{-1} z <= 1}`` when ``X`` is invertible (eq. 2); axes, orientation,
  boundary points, support function and volume (:func:`axes`, :func:`boundary_points`,
  :func:`support`, :func:`volume`, :func:`conic_points`);
* projection (Sec. 3): ``Y = C^T X C`` (eq. 4, :func:`project`);
* matrix-vector form (Sec. 4): the standard symmetric basis (eq. 9, :func:`symmetric_basis`),
  coordinates ``svec``/``smat`` (eqs. 7-8), the operator ``C~`` of eq. (10)
  (:func:`ctilde`), the Kronecker form of eq. (6) (:func:`kron_operator`) and the stacked
  operator of eq. (14) (:func:`stacked_operator`);
* reconstruction (Sec. 5): least squares via the Moore-Penrose inverse (eqs. 15-18) with
  the rank test of Sec. 5.1, interval-constrained least squares ``lower <= X <= upper``
  (Sec. 5.2) by Algorithm 1 of the Appendix (successive rank-one halfspaces, eqs. 27-30,
  :func:`halfspace_reconstruct`) and by a semidefinite program (cvxpy with Clarabel) as the
  modern reference (:func:`reconstruct`); the sufficient condition (19) for a PSD least
  squares estimate (:func:`condition19`);
* dynamics (Sec. 6): the shaping matrix of eq. (23) (:func:`shaping_matrix`), simulation
  of eq. (20) (:func:`simulate`), the state-space form (21) (:func:`state_space`), the
  observability matrix and batch estimate of eqs. (24)-(25) (:func:`observability_matrix`,
  :func:`batch_estimate`, :func:`is_observable`) and a recursive Kalman estimator built on
  :class:`filterpy.kalman.KalmanFilter` (:func:`kalman_estimate`).

Coordinates: ``svec(X)`` lists the upper triangle of ``X`` row by row, off-diagonal
entries multiplied by ``sqrt(2)``; this is exactly the ordering ``l`` of eq. (9), and it
makes ``svec`` an isometry: ``<A, B> = tr(A^T B) = svec(A) . svec(B)``.

Modules (each imported here, so ``projtrack.ellipsoids.<name>`` works for every public name):

* :mod:`~projtrack.ellipsoids.checks` - argument checks: symmetric matrices, orthonormal views, observation lists;
* :mod:`~projtrack.ellipsoids.operators` - Sec. 3-4: ``svec``/``smat``, the symmetric basis, ``C~`` and the projection;
* :mod:`~projtrack.ellipsoids.geometry` - Sec. 2: axes, support function, volume, boundary points, PSD cone;
* :mod:`~projtrack.ellipsoids.intervals` - Sec. 5.2: matrix intervals ``lower <= X <= upper``;
* :mod:`~projtrack.ellipsoids.lsi_solver` - least squares with linear inequality constraints (Lawson & Hanson);
* :mod:`~projtrack.ellipsoids.halfspace` - Algorithm 1 of the Appendix (successive rank-one halfspaces);
* :mod:`~projtrack.ellipsoids.sdp` - the interval-constrained problem as a semidefinite program (cvxpy);
* :mod:`~projtrack.ellipsoids.reconstruction` - Sec. 5: reconstruction, condition (19), ellipse fitting;
* :mod:`~projtrack.ellipsoids.dynamics` - Sec. 6: simulation, observability, batch estimates;
* :mod:`~projtrack.ellipsoids.kalman` - Sec. 6.2: recursive Kalman estimate (filterpy).
"""

from __future__ import annotations

from .checks import check_orthonormal, check_symmetric
from .dynamics import (batch_estimate, batch_estimate_many, batch_rhs, is_observable, observability_matrix,
                       reconstruct_many, shaping_matrix, simulate, state_space)
from .geometry import axes, boundary_points, conic_points, is_psd, nearest_psd, support, volume
from .halfspace import HalfspaceResult, halfspace_reconstruct
from .intervals import in_interval, interval_boundary_point, interval_bounds
from .kalman import KalmanResult, kalman_estimate
from .lsi_solver import lsi
from .operators import (congruence_operator, ctilde, kron_operator, project, smat, stacked_operator, svec,
                        svec_basis_matrix, symmetric_basis)
from .reconstruction import IndefiniteDataWarning, RankDeficientWarning, condition19, fit_centered_ellipse, reconstruct
from .sdp import sdp_reconstruct

__all__ = [
    "RankDeficientWarning", "IndefiniteDataWarning", "check_symmetric", "check_orthonormal",
    "svec", "smat", "symmetric_basis", "ctilde", "congruence_operator", "kron_operator",
    "svec_basis_matrix", "stacked_operator", "project",
    "axes", "support", "volume", "boundary_points", "conic_points", "is_psd", "nearest_psd",
    "interval_bounds", "interval_boundary_point", "in_interval",
    "reconstruct", "halfspace_reconstruct", "HalfspaceResult", "sdp_reconstruct", "lsi",
    "condition19", "fit_centered_ellipse",
    "shaping_matrix", "simulate", "state_space", "observability_matrix", "batch_rhs", "batch_estimate_many", "reconstruct_many",
    "batch_estimate", "is_observable", "kalman_estimate", "KalmanResult",
]
