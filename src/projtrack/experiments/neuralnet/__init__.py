"""The experiments of the neural-net tracker chapter (Barnard & Casasent, chapter 5).

Modules (everything public is re-exported here):

* :mod:`~projtrack.experiments.neuralnet.table1`: the Sec. VI simulation (data sets, net starts,
  success and the reference solvers' scores);
* :mod:`~projtrack.experiments.neuralnet.criterion`: the exact binomial criterion that judges a
  ten-run table against the paper's Table 1, and each noise level's runs read against its row;
* :mod:`~projtrack.experiments.neuralnet.studies`: the chapter's Monte Carlo studies (Table 1 at
  several noise levels, readings of the paper, Fig. 5 runs, the fixed-point bound);
* :mod:`~projtrack.experiments.neuralnet.sensitivity`: Table 1 under a grid of readings of the paper
  (unit of D, update rule, noise law), each judged by the criterion;
* :mod:`~projtrack.experiments.neuralnet.comparison`: the net against the reference solvers of the
  same cost, against noise and against the number of targets;
* :mod:`~projtrack.experiments.neuralnet.degraded`: the net on data with spurious measurements and
  missing detections;
* :mod:`~projtrack.experiments.neuralnet.failures`: how runs end (converged, cycling with the correct
  state, wandering) and the paper's account of its failures;
* :mod:`~projtrack.experiments.neuralnet.updates`: parallel against serial updates, and the
  frame-by-frame rule that keeps the paper's energy and finds noisy tracks;
* :mod:`~projtrack.experiments.neuralnet.equations`: term 3 of eq. (8) as printed against eq. (9),
  and the connection matrices of eq. (10).
"""

from .comparison import METHODS, accuracy, comparison_cells, comparison_trial, noise_sweep, size_sweep
from .criterion import ci_step, fmt_p, k_range, p_row, p_table, rate_ci, table1_readings, ten_run_replications
from .degraded import OUTCOMES, TOLERATED, DegradedDraw, degraded_outcome, degraded_study, draw_degraded
from .equations import (central_differences, connection_check, eq8_term3_check, term3_eq9, term3_printed,
                        term3_read)
from .failures import (FAILURE_MODES, MODES, PAPER_FAILURES, draws_modes, mode_counts, mode_probability,
                       one_pairing_away, run_modes)
from .sensitivity import (SENSITIVITY_RULES, sensitivity_readings, sensitivity_seed, sensitivity_study,
                          sensitivity_table, sensitivity_verdicts)
from .studies import (TABLE1_KEYS, bound_direct_check, bound_trial, direct_check_trial, evolution_trial,
                      fixed_point_bound, sensitivity_cell, sensitivity_cells, sensitivity_trial, table1_study,
                      table1_trial, truth_index)
from .table1 import SimulationDraw, draw_simulation, run_draws, score_simulation, simulate, simulate_trials
from .updates import frame_descent, frame_rule_study, nearest_admissible, update_order_study

__all__ = [
    "simulate",
    "SimulationDraw",
    "draw_simulation",
    "score_simulation",
    "run_draws",
    "simulate_trials",
    "TABLE1_KEYS",
    "table1_trial",
    "table1_study",
    "sensitivity_trial",
    "sensitivity_cell",
    "sensitivity_cells",
    "SENSITIVITY_RULES",
    "sensitivity_readings",
    "sensitivity_seed",
    "sensitivity_study",
    "sensitivity_verdicts",
    "sensitivity_table",
    "evolution_trial",
    "truth_index",
    "bound_trial",
    "fixed_point_bound",
    "bound_direct_check",
    "direct_check_trial",
    "rate_ci",
    "ci_step",
    "k_range",
    "p_row",
    "p_table",
    "fmt_p",
    "table1_readings",
    "ten_run_replications",
    "MODES",
    "FAILURE_MODES",
    "PAPER_FAILURES",
    "one_pairing_away",
    "run_modes",
    "draws_modes",
    "mode_counts",
    "mode_probability",
    "nearest_admissible",
    "frame_descent",
    "frame_rule_study",
    "update_order_study",
    "term3_printed",
    "term3_read",
    "term3_eq9",
    "central_differences",
    "eq8_term3_check",
    "connection_check",
    "METHODS",
    "comparison_trial",
    "comparison_cells",
    "accuracy",
    "noise_sweep",
    "size_sweep",
    "OUTCOMES",
    "TOLERATED",
    "DegradedDraw",
    "draw_degraded",
    "degraded_outcome",
    "degraded_study",
]
