"""The experiments of the neural-net tracker chapter (Barnard & Casasent, chapter 5).

Modules (everything public is re-exported here):

* :mod:`~projtrack.experiments.neuralnet.table1`: the Sec. VI simulation (data sets, net starts,
  success and the reference solvers' scores);
* :mod:`~projtrack.experiments.neuralnet.studies`: the chapter's Monte Carlo studies (Table 1 at
  several noise levels, readings of the paper, Fig. 5 runs, the fixed-point bound).
"""

from .studies import (TABLE1_KEYS, bound_direct_check, bound_trial, evolution_trial, fixed_point_bound,
                      sensitivity_cell, sensitivity_trial, table1_study, table1_trial, truth_index)
from .table1 import simulate

__all__ = [
    "simulate",
    "TABLE1_KEYS",
    "table1_trial",
    "table1_study",
    "sensitivity_trial",
    "sensitivity_cell",
    "evolution_trial",
    "truth_index",
    "bound_trial",
    "fixed_point_bound",
    "bound_direct_check",
]
