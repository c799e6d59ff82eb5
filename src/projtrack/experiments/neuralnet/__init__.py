"""The experiments of the neural-net tracker chapter (Barnard & Casasent, chapter 5).

Modules (everything public is re-exported here):

* :mod:`~projtrack.experiments.neuralnet.table1`: the Sec. VI simulation (data sets, net starts,
  success and the reference solvers' scores), how each run ends (converged, a 2-cycle with the
  correct state, another cycle, wandering), and the Table 1 and Fig. 5 figures;
* :mod:`~projtrack.experiments.neuralnet.criterion`: the exact binomial criterion that judges a
  ten-run table against the paper's Table 1, each noise level's runs read against its row, and
  the paper's account of its failures;
* :mod:`~projtrack.experiments.neuralnet.studies`: the chapter's Monte Carlo studies (Table 1 at
  several noise levels, readings of the paper, Fig. 5 runs, the fixed-point bound and its tables);
* :mod:`~projtrack.experiments.neuralnet.sensitivity`: Table 1 under a grid of readings of the paper
  (unit of D, update rule, noise law), each judged by the criteria;
* :mod:`~projtrack.experiments.neuralnet.comparison`: the net against the reference solvers of the
  same cost, against noise and against the number of targets; parallel against serial updates;
  the frame-by-frame rule that keeps the paper's energy and finds noisy tracks;
* :mod:`~projtrack.experiments.neuralnet.equations`: term 3 of eq. (8) as printed against eq. (9),
  and the connection matrices of eq. (10);
* :mod:`~projtrack.experiments.neuralnet.degraded`: the claims of Sec. IV on data with spurious
  measurements and missing detections.
"""

from .comparison import (METHODS, accuracy, net_standard_error, comparison_cells, comparison_trial, frame_descent, frame_rule_study,
                         frame_rule_table, nearest_admissible, noise_sweep, operation_counts, optimum_net_ratios, descent_rounds, plot_comparison, plot_timing, size_sweep, update_order_study)
from .criterion import (PAPER_FAILURES, ci_step, fmt_p, k_range, mode_probability, p_row, p_table, rate_ci,
                        stable_down, stable_up, table1_readings, table1_tables, ten_run_replications)
from .degraded import (OUTCOMES, TOLERATED, DegradedDraw, degraded_outcome, degraded_optimum, degraded_optimum_study,
                       degraded_study, draw_degraded, measurement_counts, tolerance_readings)
from .equations import (bound_text, central_differences, connection_check, connection_table, eq8_term3_check,
                        gradient_forms, plot_architecture, term3_eq9, term3_printed, term3_read)
from .sensitivity import (SENSITIVITY_RULES, plot_readings, sensitivity_readings, sensitivity_seed, sensitivity_study,
                          sensitivity_table, sensitivity_verdicts)
from .studies import (TABLE1_KEYS, bound_direct_check, bound_holds, bound_table, bound_trial, cut_for_rates,
                      direct_check_trial, evolution_trial, first_sweep_pattern, end_states, fixed_point_bound, fixed_point_grid, plot_fixed_point_bound,
                      sensitivity_cell, sensitivity_cells, sensitivity_trial, table1_study, table1_trial, truth_index)
from .table1 import (FAILURE_MODES, MODES, SimulationDraw, draw_simulation, draws_modes, mode_counts, one_pairing_away,
                     plot_fig5, plot_table1, run_draws, run_modes, score_simulation, simulate, simulate_trials)

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
    "bound_table",
    "fixed_point_grid",
    "cut_for_rates",
    "bound_holds",
    "rate_ci",
    "ci_step",
    "stable_up",
    "stable_down",
    "k_range",
    "p_row",
    "p_table",
    "fmt_p",
    "table1_readings",
    "ten_run_replications",
    "table1_tables",
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
    "frame_rule_table",
    "update_order_study",
    "term3_printed",
    "term3_read",
    "term3_eq9",
    "central_differences",
    "eq8_term3_check",
    "gradient_forms",
    "bound_text",
    "connection_check",
    "connection_table",
    "plot_architecture",
    "plot_table1",
    "plot_fixed_point_bound",
    "plot_readings",
    "plot_fig5",
    "plot_comparison",
    "plot_timing",
    "METHODS",
    "comparison_trial",
    "comparison_cells",
    "accuracy", "net_standard_error",
    "noise_sweep",
    "size_sweep",
    "OUTCOMES",
    "TOLERATED",
    "DegradedDraw",
    "draw_degraded",
    "degraded_outcome",
    "degraded_study",
    "degraded_optimum",
    "degraded_optimum_study", "measurement_counts", "tolerance_readings",
    "first_sweep_pattern",
    "end_states",
    "operation_counts",
    "optimum_net_ratios",
    "descent_rounds",
]
