"""projtrack: estimating shapes and tracks from projections and partial observations.

A shared package for a reproducible book of three documents:

* Karl, Verghese & Willsky (1994), reconstructing ellipsoids from projections
  (:mod:`projtrack.ellipsoids`);
* Marques et al. (2002), trajectory estimation on manifolds, the DMA algorithm
  (:mod:`projtrack.dma`);
* Casasent (1989), time-sequential optical data processing: projection
  correlations (:mod:`projtrack.correlators`), a Hough-transform track initiator
  (:mod:`projtrack.hough`), fast JPDA (:mod:`projtrack.jpda`), a cubic-energy
  neural net (:mod:`projtrack.neuralnet`) and an adaptive KL novelty filter
  (:mod:`projtrack.novelty`).

Shared helpers: :mod:`projtrack.figures` (figure style and saving),
:mod:`projtrack.scorecard` (the reproduction scorecard), :mod:`projtrack.inventory`
(the project's copy of the list of items to reproduce) and
:mod:`projtrack.montecarlo` (reproducible parallel Monte Carlo).

Topic modules are imported on demand (``import projtrack.jpda``) so that each is
importable on its own.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
