"""The experiments of the manifold chapter (Marques et al., 2002): the paper's three examples.

* :mod:`~projtrack.experiments.dma.curve`: Figs. 2-3, the clockwise chain learned on a closed curve and its speed sensitivity.
* :mod:`~projtrack.experiments.dma.decoding`: Viterbi, smoothed and filtered paths of one sequence.
* :mod:`~projtrack.experiments.dma.sphere`: Example 1, the sphere chain, its Monte Carlo and readings, the Kalman baseline.
* :mod:`~projtrack.experiments.dma.roads`: Example 2, roads and a range radar, its Monte Carlo and readings, the EKF baseline.
* :mod:`~projtrack.experiments.dma.slotcar`: Example 3, background subtraction, training, the tracking and sensitivity studies.
* :mod:`~projtrack.experiments.dma.plots`: the Example 3 figures (Fig. 9 and the harder condition).

Every Monte Carlo study (:func:`sphere_trials`, :func:`road_trials`, :func:`no_data_errors`,
:func:`tracking_study`) runs through
:func:`projtrack.montecarlo.run`.
"""

from projtrack.experiments.dma.curve import clockwise_order, other_moves, speed_sensitivity
from projtrack.experiments.dma.decoding import decode_all
from projtrack.experiments.dma.roads import (
    RoadExample,
    block_summary,
    ekf_range,
    error_summary,
    lost_drives,
    make_road_example,
    no_data_errors,
    road_trials,
)
from projtrack.experiments.dma.plots import plot_fig9, plot_harder
from projtrack.experiments.dma.slotcar import (
    active_pixels,
    fit_slotcar,
    path_step,
    sensitivity_study,
    track_video,
    tracking_error_rows,
    tracking_error_table,
    tracking_study,
    training_background,
    training_summary,
)
from projtrack.experiments.dma.sphere import (
    H_SPHERE,
    SPHERE_CHAINS,
    SphereExample,
    accuracy_summary,
    kalman_sphere,
    make_sphere_example,
    noise_study,
    sphere_trials,
    with_centroids,
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
    "plot_fig9",
    "plot_harder",
    "path_step",
    "tracking_error_table",
    "training_summary",
    "training_background",
    "with_centroids",
    "accuracy_summary",
    "noise_study",
    "error_summary",
    "block_summary",
    "no_data_errors",
    "track_video",
    "tracking_study",
    "tracking_error_rows",
    "sensitivity_study",
    "clockwise_order",
    "other_moves",
    "speed_sensitivity",
]
