"""Trajectory estimation on manifolds: the DMA algorithm of Marques et al. (2002).

J. S. Marques et al., "Trajectory estimation on manifolds", Signal Processing, 2002.
Everything public lives in ``projtrack.dma.core`` and is re-exported here:
manifold learning (Sec. 3.1, eqs. (1)-(9)), motion models (Sec. 3.2, eqs. (10)-(13)),
sensor models (eqs. (14)-(15)), Viterbi / forward-backward retrieval (Sec. 3.3) and the
:class:`DMA` estimator. :mod:`projtrack.dma.examples` holds the set-ups of the paper's
three examples and the baselines used by the book.
"""

from projtrack.dma.core import *  # noqa: F401,F403
from projtrack.dma.core import __all__ as _core_all

__all__ = list(_core_all)
