"""The experiments of the manifold chapter (Marques et al., 2002): the paper's three examples.

* :mod:`~projtrack.experiments.dma.curve`: Figs. 2-3, the clockwise chain learned on a closed curve and its speed sensitivity; eq. (9) on the points and the convergence of the relative-frequency estimate of A.
* :mod:`~projtrack.experiments.dma.decoding`: Viterbi, smoothed and filtered paths of one sequence.
* :mod:`~projtrack.experiments.dma.sphere`: Example 1, the sphere chain, its Monte Carlo and readings, the Kalman baseline.
* :mod:`~projtrack.experiments.dma.roads`: Example 2, roads and a range radar, its Monte Carlo and readings, the EKF baseline.
* :mod:`~projtrack.experiments.dma.slotcar`: Example 3, background subtraction, training, the tracking and sensitivity studies, two trackers without the manifold.
* :mod:`~projtrack.experiments.dma.plots`: the Example 3 figures (Fig. 9 and the harder condition).

Every Monte Carlo study (:func:`sphere_trials`, :func:`baseline_trials`, :func:`road_trials`,
:func:`reading_study`, :func:`no_data_errors`, :func:`tracking_study`, :func:`transition_convergence`)
runs through
:func:`projtrack.montecarlo.run`.
"""

from projtrack.experiments.dma.curve import (
    clockwise_order,
    eq9_table,
    other_moves,
    predicted_frobenius,
    responsibilities,
    sample_path,
    speed_sensitivity,
    stationary,
    transition_convergence,
)
from projtrack.experiments.dma.decoding import decode_all
from projtrack.experiments.dma.roads import (
    ROAD_NOISE,
    ROAD_STATES,
    RoadExample,
    block_summary,
    ekf_range,
    error_summary,
    lost_drives,
    make_road_example,
    median_shift_bound,
    no_data_errors,
    reading_study,
    road_trials,
)
from projtrack.experiments.dma.plots import plot_fig9, plot_harder
from projtrack.experiments.dma.slotcar import (
    GridHMM,
    MapFree,
    active_pixels,
    box_counts,
    detect_and_interpolate,
    detector_threshold,
    fit_grid_hmm,
    longest_gap,
    map_free_table,
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
    baseline_trials,
    chain_process_std,
    chain_sensitivity,
    chain_stats,
    field_smoother,
    kalman_sphere,
    make_sphere_example,
    noise_study,
    rate_spread,
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
    "chain_stats",
    "chain_sensitivity",
    "chain_process_std",
    "field_smoother",
    "baseline_trials",
    "rate_spread",
    "ROAD_STATES",
    "ROAD_NOISE",
    "median_shift_bound",
    "reading_study",
    "box_counts",
    "detector_threshold",
    "detect_and_interpolate",
    "longest_gap",
    "GridHMM",
    "fit_grid_hmm",
    "MapFree",
    "map_free_table",
    "responsibilities",
    "eq9_table",
    "stationary",
    "sample_path",
    "predicted_frobenius",
    "transition_convergence",
]
