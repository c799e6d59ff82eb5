"""The experiments of the neural-net tracker chapter (Barnard & Casasent, chapter 5).

Modules (everything public is re-exported here):

* :mod:`~projtrack.experiments.neuralnet.table1`: the Sec. VI simulation (data sets, net starts,
  success and the reference solvers' scores).
"""

from .table1 import simulate

__all__ = ["simulate"]
