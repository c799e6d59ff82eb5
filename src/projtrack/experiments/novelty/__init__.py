"""Experiments of the KL novelty chapter (Vermeulen & Casasent 1988).

Modules:

- :mod:`~projtrack.experiments.novelty.routes`: the KL algorithms against exact oracles (VIP vs large matrix, recursion vs batch, near-duplicate frames, Eq. (12)'s two printed forms, the ranks of R and C) and streaming baselines.
- :mod:`~projtrack.experiments.novelty.street`: the rules of Figs. 2-3 (the order of frames 2-4, the entry, the visible-ghost area), the synthetic street scene calibrated on the printed V_1, n_2 and n_8 with its readings of what the text leaves open, and what every claim reads on one sequence.
- :mod:`~projtrack.experiments.novelty.summaries`: the street-scene claims judged over the readings (shares of draws, the verdict rule and its tolerance).
- :mod:`~projtrack.experiments.novelty.printed`: the report's printed Fig. 2 numbers (V_2, F_4, F_8) recomputed from its printed novelties, and the bound that pins frame 8's update count.
- :mod:`~projtrack.experiments.novelty.realvideo`: the real plaza video (residual location, calibration to the printed brightness and contrast, rank margin, energy kept).
- :mod:`~projtrack.experiments.novelty.aircraft`: Table 2 and the rank claim on rendered aircraft (novelty table, mean-image baseline, recognition by m eigenimages, noise studies, the T_d sweep).
- :mod:`~projtrack.experiments.novelty.plots`: Fig. 1 (block diagram of Table 1) and the Figs. 2-3 panels (matplotlib).
"""
from __future__ import annotations

from .aircraft import (centred_eigenvalues, classifier_noise_draw, effective_rank, effective_rank_curve, info_rank,
                       mean_image_correct, noise_rate_draws, noisy_rates, novelty_table,
                       rank_claim_table, recognized, threshold_sweep as aircraft_threshold_sweep)
from .plots import plot_block_diagram, plot_fig2_panels, plot_fig3_panels
from .printed import (PRINTED_V1, PRINTED_V2, energy_ratios_needed, frame4_table, frame8_table,
                      frame_pair, local_change_novelty, local_change_novelty_bound, min_energy_share,
                      novelty_from_vip, second_fraction, second_fraction_closed_form)
from .realvideo import (calibrate_real, contrast_scaled, energy_kept_table, max_second_fraction,
                        median_background, rank_margin, residual_location)
from .routes import (eq12_forms, mean_outside_span, near_duplicate_study, route_errors, streaming_comparison, vip_ranks,
                     vip_vs_large)
from .street import (CONTRARY_READINGS, FIG2_SETTINGS, FIG3_SETTINGS, NOISE_STD, PIXEL_THRESHOLD,
                     PRINTED_RMS, READINGS, VISIBILITY_THRESHOLDS, calibrate_contrast, calibrate_gain,
                     calibrate_person, calibrate_readings, entry_marked, frame2_quiet, ghost_area, ghost_decay, ghost_rms,
                     memory_updates, novel_pixel_quality, novelty_against_first, order_2_4, reading_draw,
                     reading_draws, record_table, sequence_readings, threshold_sweep)
from .summaries import (CLAIMS, claim_shares, claim_table, medians, real_claims, real_table, share_tolerance,
                        shares_text, verdict)

__all__ = [
    # routes and equations
    "vip_vs_large", "route_errors", "near_duplicate_study", "streaming_comparison",
    "eq12_forms", "vip_ranks", "mean_outside_span",
    # street rules
    "FIG2_SETTINGS", "FIG3_SETTINGS", "PIXEL_THRESHOLD", "ghost_area", "order_2_4", "entry_marked",
    "record_table",
    # printed numbers
    "PRINTED_V1", "PRINTED_V2", "frame_pair", "second_fraction", "second_fraction_closed_form",
    "novelty_from_vip", "frame4_table", "frame8_table", "energy_ratios_needed",
    "local_change_novelty_bound", "local_change_novelty", "min_energy_share",
    # calibrated scene and readings
    "PRINTED_RMS", "NOISE_STD", "READINGS", "CONTRARY_READINGS", "VISIBILITY_THRESHOLDS", "novelty_against_first",
    "calibrate_gain", "calibrate_contrast", "calibrate_person", "calibrate_readings", "frame2_quiet", "ghost_rms",
    "memory_updates", "novel_pixel_quality", "sequence_readings", "reading_draw", "reading_draws",
    "threshold_sweep", "ghost_decay",
    "CLAIMS", "claim_shares", "claim_table", "medians", "real_claims", "real_table", "shares_text", "verdict",
    "share_tolerance",
    # real video
    "median_background", "residual_location", "contrast_scaled", "calibrate_real",
    "max_second_fraction", "rank_margin", "energy_kept_table",
    # aircraft
    "novelty_table", "mean_image_correct", "recognized", "rank_claim_table", "noisy_rates",
    "noise_rate_draws", "effective_rank", "effective_rank_curve", "info_rank", "centred_eigenvalues",
    "classifier_noise_draw", "aircraft_threshold_sweep",
    # plots
    "plot_block_diagram", "plot_fig2_panels", "plot_fig3_panels",
]
