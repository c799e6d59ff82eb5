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

The package has three layers, each importing only the ones below it (checked by
``lint-imports``): the studies the notebooks run, in :mod:`projtrack.experiments`; the
synthetic stand-ins for unpublished data, in :mod:`projtrack.scenes`; and the algorithms,
one topic package each (above), which import neither of the others, nor matplotlib or
pandas. Beside the experiments are the book's helpers, :mod:`projtrack.figures` (figure
style and saving), :mod:`projtrack.scorecard` (the reproduction scorecard) and
:mod:`projtrack.inventory` (the project's copy of the list of items to reproduce); beneath
everything, :mod:`projtrack._validation` (the shared argument checks),
:mod:`projtrack.montecarlo` (reproducible parallel Monte Carlo) and :mod:`projtrack.stable`
(printing numbers that do not depend on the last bits).

Topic packages are imported on demand (``import projtrack.jpda``) so that each is
importable on its own. The algorithm packages need only numpy and scipy; a few functions
need an optional dependency and say which extra installs it when it is missing
(``pip install "projtrack[sdp]"`` for cvxpy, ``[kalman]`` for filterpy, ``[learn]`` for
scikit-learn, ``[fast]`` for the numba kernels).
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("projtrack")
except PackageNotFoundError:  # a source tree that was never installed
    __version__ = "0+unknown"

__all__ = ["__version__"]
