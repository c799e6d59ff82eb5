"""Experiments of Part I (Karl, Verghese & Willsky 1994): the studies the ellipsoid notebooks run.

* :mod:`~projtrack.experiments.ellipsoids.static` - Secs. 3-5 and 7.1: shown draws, the three estimates, interval and noise readings, LS-not-PSD frequencies, the rank, C~, projector-form and eq. (22) checks;
* :mod:`~projtrack.experiments.ellipsoids.dynamic` - Secs. 6 and 7.2: PSD-constrained batch estimates (also at other times, eq. 24), the noise study of Fig. 12, drive sensitivity, imperfect model, Kalman;
* :mod:`~projtrack.experiments.ellipsoids.baselines` - the trivial baselines of Fig. 12 (no data, one frame) and the settling criterion against them;
* :mod:`~projtrack.experiments.ellipsoids.beyond` - Algorithm 1 against the SDP, 3-D silhouettes, condition (19);
* :mod:`~projtrack.experiments.ellipsoids.selection` - how a figure's draw is picked (median of a stated error) and the settling step of Sec. 7.2;
* :mod:`~projtrack.experiments.ellipsoids.plots` - drawing helpers shared by the cells of the ellipsoid pages.
"""

from __future__ import annotations

from .baselines import (best_constant_error, fig12_readings, fig13_baselines, one_frame_guess, threshold_table,
                        trivial_baselines, versus_baseline)
from .beyond import (alg1_sdp_summary, compare_alg1_sdp, condition19_study, condition19_trial, constraint_violation,
                     random_interval_draw, random_interval_problems, silhouette_trial, silhouettes_3d_study)
from .dynamic import (ESTIMATORS, constant_baseline_error, estimator_table, fig12_noise_study, first_measure_table,
                      imperfect_model_study, kalman_vs_batch, model_error_scan, model_trial, no_data_estimate,
                      psd_batch_estimates, psd_project_2x2, relative_errors, settling_study,
                      time_k_psd_estimates, time_k_study)
from . import plots
from .selection import median_draw, settling_step
from .static import (constraints_inactive, ctilde_identity_study, ctilde_identity_trial, demo_interval, describe_estimates,
                     hyperplane_rank_trial, hyperplane_ranks, ideal_supports, interval_bound_study,
                     interval_readings, ls_estimates, ls_psd_frequency, non_psd_pool_study, projector_form_study,
                     projector_form_trial, shaping_family_study, shown_static_draw, snr_readings, support_perturbation,
                     three_estimates)

__all__ = [
    "demo_interval", "interval_readings", "ideal_supports", "support_perturbation", "ls_estimates", "shown_static_draw",
    "three_estimates", "describe_estimates", "non_psd_pool_study", "constraints_inactive", "interval_bound_study",
    "ls_psd_frequency",
    "snr_readings", "hyperplane_rank_trial", "hyperplane_ranks", "ctilde_identity_trial", "ctilde_identity_study",
    "projector_form_trial", "projector_form_study",
    "relative_errors", "no_data_estimate", "psd_project_2x2", "psd_batch_estimates", "time_k_psd_estimates",
    "ESTIMATORS", "fig12_noise_study", "estimator_table", "time_k_study", "settling_study",
    "constant_baseline_error", "model_trial", "imperfect_model_study", "first_measure_table", "model_error_scan",
    "kalman_vs_batch",
    "shaping_family_study",
    "random_interval_draw", "random_interval_problems", "constraint_violation", "compare_alg1_sdp", "alg1_sdp_summary",
    "silhouette_trial", "silhouettes_3d_study",
    "condition19_trial", "condition19_study", "median_draw", "settling_step", "plots",
    "best_constant_error", "fig12_readings", "one_frame_guess", "trivial_baselines", "versus_baseline", "threshold_table",
    "fig13_baselines",
]
