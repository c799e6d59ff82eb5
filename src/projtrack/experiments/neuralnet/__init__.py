"""The experiments of the neural-net tracker chapter (Barnard & Casasent, chapter 5).

Modules (everything public is re-exported here):

* :mod:`~projtrack.experiments.neuralnet.table1`: the Sec. VI simulation (data sets, net starts,
  success and the reference solvers' scores);
* :mod:`~projtrack.experiments.neuralnet.studies`: the chapter's Monte Carlo studies (Table 1 at
  several noise levels, readings of the paper, Fig. 5 runs, the fixed-point bound).
"""

from .studies import (TABLE1_KEYS, bound_direct_check, bound_trial, evolution_trial, fixed_point_bound,
                      sensitivity_cell, sensitivity_cells, sensitivity_trial, table1_study, table1_trial, truth_index)
from .table1 import SimulationDraw, draw_simulation, run_draws, score_simulation, simulate, simulate_trials

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
    "evolution_trial",
    "truth_index",
    "bound_trial",
    "fixed_point_bound",
    "bound_direct_check",
]
