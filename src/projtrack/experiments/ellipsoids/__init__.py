"""Experiments of Part I (Karl, Verghese & Willsky 1994): the studies the ellipsoid notebooks run.

* :mod:`~projtrack.experiments.ellipsoids.static` - Sec. 7.1: shown draws, the three estimates, LS-not-PSD frequencies, the rank and C~ checks;
* :mod:`~projtrack.experiments.ellipsoids.dynamic` - Sec. 7.2: noise study of Fig. 12, drive sensitivity, imperfect model, Kalman;
* :mod:`~projtrack.experiments.ellipsoids.beyond` - Algorithm 1 against the SDP, 3-D silhouettes, condition (19);
* :mod:`~projtrack.experiments.ellipsoids.selection` - how a figure's draw is picked (median of a stated error) and the settling step of Sec. 7.2;
* :mod:`~projtrack.experiments.ellipsoids.plots` - drawing helpers shared by the cells of the ellipsoid pages.
"""

from __future__ import annotations

from .beyond import (compare_alg1_sdp, condition19_study, condition19_trial, constraint_violation,
                     random_interval_draw, random_interval_problems, silhouette_trial, silhouettes_3d_study)
from .dynamic import (fig12_noise_study, imperfect_model_study, kalman_vs_batch, model_trial, no_data_estimate,
                      relative_errors, settling_study)
from . import plots
from .selection import median_draw, settling_step
from .static import (ctilde_identity_study, ctilde_identity_trial, demo_interval, describe_estimates,
                     hyperplane_rank_trial, hyperplane_ranks, ideal_supports, ls_estimates, ls_psd_frequency,
                     noise_reading_study, non_psd_pool_study, shown_static_draw, three_estimates)

__all__ = [
    "demo_interval", "ideal_supports", "ls_estimates", "shown_static_draw", "three_estimates",
    "describe_estimates", "non_psd_pool_study", "ls_psd_frequency", "noise_reading_study",
    "hyperplane_rank_trial", "hyperplane_ranks", "ctilde_identity_trial", "ctilde_identity_study",
    "relative_errors", "no_data_estimate", "fig12_noise_study", "settling_study", "model_trial",
    "imperfect_model_study", "kalman_vs_batch",
    "random_interval_draw", "random_interval_problems", "constraint_violation", "compare_alg1_sdp",
    "silhouette_trial", "silhouettes_3d_study",
    "condition19_trial", "condition19_study", "median_draw", "settling_step", "plots",
]
