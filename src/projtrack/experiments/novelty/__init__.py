"""Experiments of the KL novelty chapter (Vermeulen & Casasent 1988).

Modules:

- :mod:`~projtrack.experiments.novelty.routes`: the KL algorithms against exact oracles (VIP vs large matrix, recursion vs batch, near-duplicate frames) and streaming baselines.
- :mod:`~projtrack.experiments.novelty.street`: the street-scene study of Figs. 2-3 (readings per frame, synthetic Monte Carlo draws, ghost areas, jitter sensitivity, novel pixels vs ground truth).
- :mod:`~projtrack.experiments.novelty.summaries`: tables of the street-scene study over the synthetic draws and the real video (Fig. 2 summary, ghost areas, T_f sensitivity) and the seen-on-both verdict rule.
- :mod:`~projtrack.experiments.novelty.printed`: the report's printed Fig. 2 numbers (V_2, F_4, F_8) recomputed from its printed novelties.
- :mod:`~projtrack.experiments.novelty.realvideo`: readings of the real plaza video (residual location, contrast calibration, rank margin, energy kept).
- :mod:`~projtrack.experiments.novelty.aircraft`: Table 2 and the rank claim on rendered aircraft (novelty table, mean-image baseline, recognition by m eigenimages, noise studies).
- :mod:`~projtrack.experiments.novelty.plots`: Fig. 1 (block diagram of Table 1) and the Figs. 2-3 frame panels (matplotlib).
"""
from __future__ import annotations

from .aircraft import (classifier_noise_draw, effective_rank, info_rank, mean_image_correct,
                       noise_rate_draws, noisy_rates, novelty_table, rank_claim_table, recognized)
from .plots import plot_block_diagram, plot_frame_panels
from .printed import (PRINTED_V1, PRINTED_V2, frame4_table, frame8_table, frame_pair,
                      novelty_from_vip, second_fraction)
from .realvideo import (calibrate_contrast, contrast_scaled, energy_kept_table, fig2_pattern,
                        first_novelty, max_second_fraction, median_background, rank_margin,
                        residual_location, rms_ratio)
from .routes import near_duplicate_study, route_errors, streaming_comparison, vip_vs_large
from .street import (FIG2_SETTINGS, FIG3_SETTINGS, PIXEL_THRESHOLD, entry_marked, fig2_stats,
                     ghost_area, ghost_study, jitter_draw, jitter_sensitivity, novel_pixel_scores,
                     order_2_4, record_table, synthetic_draw, synthetic_draws)
from .summaries import (cleaner_fraction, draw_verdict, fig2_fractions, fig2_seed_summary,
                        fractions_text, ghost_table, quartiles, threshold_sensitivity, verdict_note)

__all__ = [
    # routes
    "vip_vs_large", "route_errors", "near_duplicate_study", "streaming_comparison",
    # street
    "FIG2_SETTINGS", "FIG3_SETTINGS", "PIXEL_THRESHOLD", "ghost_area", "ghost_study", "order_2_4",
    "entry_marked", "fig2_stats", "synthetic_draw", "synthetic_draws", "record_table",
    "jitter_draw", "jitter_sensitivity", "novel_pixel_scores",
    # summaries
    "quartiles", "fractions_text", "fig2_fractions", "fig2_seed_summary", "ghost_table",
    "cleaner_fraction", "threshold_sensitivity", "draw_verdict", "verdict_note",
    # printed
    "PRINTED_V1", "PRINTED_V2", "frame_pair", "second_fraction", "novelty_from_vip",
    "frame4_table", "frame8_table",
    # realvideo
    "median_background", "residual_location", "contrast_scaled", "first_novelty",
    "calibrate_contrast", "fig2_pattern", "max_second_fraction", "rank_margin",
    "energy_kept_table", "rms_ratio",
    # aircraft
    "novelty_table", "mean_image_correct", "recognized", "rank_claim_table", "noisy_rates",
    "noise_rate_draws", "effective_rank", "info_rank", "classifier_noise_draw",
    # plots
    "plot_block_diagram", "plot_frame_panels",
]
