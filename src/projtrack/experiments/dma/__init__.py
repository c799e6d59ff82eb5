"""The experiments of the manifold chapter (Marques et al., 2002): the paper's three examples.

* :mod:`~projtrack.experiments.dma.decoding`: Viterbi, smoothed and filtered paths of one sequence.
* :mod:`~projtrack.experiments.dma.sphere`: Example 1, the sphere chain, its Monte Carlo and the Kalman baseline.
* :mod:`~projtrack.experiments.dma.roads`: Example 2, roads and a range radar, its Monte Carlo and the EKF baseline.
* :mod:`~projtrack.experiments.dma.slotcar`: Example 3, background subtraction and training on the slot-car video.

Every Monte Carlo study (:func:`sphere_trials`, :func:`road_trials`) runs through
:func:`projtrack.montecarlo.run`.
"""

from projtrack.experiments.dma.decoding import decode_all
from projtrack.experiments.dma.roads import RoadExample, ekf_range, lost_drives, make_road_example, road_trials
from projtrack.experiments.dma.slotcar import active_pixels, fit_slotcar, training_background
from projtrack.experiments.dma.sphere import (
    H_SPHERE,
    SPHERE_CHAINS,
    SphereExample,
    kalman_sphere,
    make_sphere_example,
    sphere_trials,
)

__all__ = [
    "H_SPHERE",
    "SPHERE_CHAINS",
    "SphereExample",
    "make_sphere_example",
    "decode_all",
    "sphere_trials",
    "kalman_sphere",
    "RoadExample",
    "make_road_example",
    "road_trials",
    "lost_drives",
    "ekf_range",
    "active_pixels",
    "fit_slotcar",
    "training_background",
]
