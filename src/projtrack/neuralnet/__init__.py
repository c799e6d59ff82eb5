"""Multitarget tracking with a cubic-energy binary Hopfield net: Barnard & Casasent (1988).

Implements chapter 5 of Casasent's 1989 report (E. Barnard and D. Casasent,
"Multitarget tracking with cubic energy optical neural nets", Appl. Opt. 1989).

Neuron ``X[i, alpha, a]`` is 1 when target ``i`` is assigned measurement ``alpha`` of
time step (frame) ``a``; a net has ``N_T x N_M x N_P`` neurons. Implemented:

* the distance tensor ``D[a, alpha, beta, gamma] = |r_alpha^a - 2 r_beta^{a+1} + r_gamma^{a+2}|``
  of eq. (7) (:func:`distance_tensor`), with zero-vector padding of missing measurements
  (:func:`pad_measurements`);
* the energy of eq. (8) (:func:`energy`) and its derivative eq. (9)
  (:func:`energy_gradient`);
* binary neurons updated by eq. (4) with the paper's raised threshold
  ``2 A3 N_T + 0.035``, serial (asynchronous) or parallel sweeps, an iteration limit and
  detection of convergence and oscillation (:func:`run_net`, batched over many nets),
  with two other readings of the update (no self term in term 3, exact energy change;
  :func:`update_inputs`);
* the fixed points of one-to-one assignments: an active neuron's input is exactly
  ``A4`` times the sum of its D terms (:func:`neuron_distance_sums`), so an assignment
  is a fixed point if and only if that stays below a limit set by the offset and the
  update rule (:func:`fixed_point_limit`, :func:`is_fixed_point`), checked over all
  assignments at once by :func:`assignment_max_sums`;
* the linear-algebra form of the optical architecture (Sec. IV-V): the fixed connection
  matrices ``T1``-``T3`` of eq. (10) (:func:`connection_matrices`), the full rank-3 tensor
  and the tensor-matrix inner product ``y4 = D . x x^T`` of eqs. (11)-(12)
  (:func:`full_tensor`, :func:`tensor_matrix_product`) and the paper's reduced per-target
  form with ``N_M`` matrices of size ``(N_M N_P)^2`` (:func:`reduced_tensor`,
  :func:`reduced_tensor_product`), and the SLM sizes of both (:func:`slm_sizes`);
* reference solutions of the same assignment problem: the exact optimum of the summed
  eq. (7) cost by dynamic programming over frame assignments (:func:`optimal_assignment`),
  frame-to-frame :func:`scipy.optimize.linear_sum_assignment` on Euclidean distance
  (:func:`nearest_neighbour_assignment`), a greedy frame-by-frame assignment on eq. (7)
  (:func:`greedy_assignment`) and its block-coordinate improvement in which every frame
  is re-solved exactly by a linear assignment with the other frames fixed
  (:func:`coordinate_descent_assignment`).

Indexing conventions: ``positions`` has shape ``(N_P, N_M, dim)``; ``D`` has shape
``(N_P - 2, N_M, N_M, N_M)``; states ``X`` have shape ``(..., N_T, N_M, N_P)``; the
neuron vector ``x`` of Sec. IV is ``X.reshape(-1)`` (target slowest, so that
``x = (z_1, ..., z_NT)`` with ``z_i = X[i].reshape(-1)`` as in Sec. V). An assignment is
an int array ``(N_T, N_P)`` of measurement indices.

Modules (everything public is re-exported here):

* :mod:`~projtrack.neuralnet.coefficients`: the weights ``A1``-``A4`` of eq. (8) and the paper's values;
* :mod:`~projtrack.neuralnet.distances`: zero-vector padding of measurements and the distance tensor of eq. (7);
* :mod:`~projtrack.neuralnet.cubic_energy`: the energy of eq. (8) and its derivative eq. (9);
* :mod:`~projtrack.neuralnet.dynamics`: random starts and the serial or parallel binary updates of eq. (4);
* :mod:`~projtrack.neuralnet.assignments`: assignments read from states, checked against the truth and costed;
* :mod:`~projtrack.neuralnet.fixed_points`: which one-to-one assignments are fixed points of the update;
* :mod:`~projtrack.neuralnet.optics`: the matrices and tensor products of the optical architecture;
* :mod:`~projtrack.neuralnet.references`: reference solvers (exact optimum, nearest neighbour, greedy,
  coordinate descent).

The Sec. VI experiment (data sets, many starts, scoring) is
:func:`projtrack.experiments.neuralnet.simulate`.
"""

from .assignments import assignment_cost, assignment_to_states, is_correct_assignment, states_to_assignment
from .coefficients import PAPER_COEFFICIENTS, PAPER_OFFSET, Coefficients
from .distances import distance_tensor, pad_measurements
from .dynamics import NetResult, initial_states, run_net, update_inputs
from .cubic_energy import energy, energy_gradient, energy_gradient_loops
from .fixed_points import assignment_max_sums, fixed_point_limit, is_fixed_point, neuron_distance_sums
from .optics import (connection_matrices, full_tensor, gradient_linear_algebra, reduced_tensor,
                     reduced_tensor_product, slm_sizes, tensor_matrix_product)
from .references import (coordinate_descent_assignment, greedy_assignment, nearest_neighbour_assignment,
                         optimal_assignment)

__all__ = [
    "PAPER_COEFFICIENTS",
    "PAPER_OFFSET",
    "Coefficients",
    "NetResult",
    "pad_measurements",
    "distance_tensor",
    "energy",
    "energy_gradient",
    "energy_gradient_loops",
    "initial_states",
    "run_net",
    "update_inputs",
    "is_fixed_point",
    "fixed_point_limit",
    "neuron_distance_sums",
    "assignment_max_sums",
    "states_to_assignment",
    "assignment_to_states",
    "is_correct_assignment",
    "assignment_cost",
    "connection_matrices",
    "full_tensor",
    "tensor_matrix_product",
    "reduced_tensor",
    "reduced_tensor_product",
    "gradient_linear_algebra",
    "slm_sizes",
    "optimal_assignment",
    "nearest_neighbour_assignment",
    "greedy_assignment",
    "coordinate_descent_assignment",
]
