"""Experiments of the projection-correlation chapter (Casasent & Song 1988): the studies its notebooks run.

.. rubric:: Modules

* ``projtrack.experiments.correlators.theorems``: numerical checks of the central slice
  theorem (Eq. (2)) and of Eq. (3).
* ``projtrack.experiments.correlators.scoring``: printed values against our draws, the
  plausibility of the paper's error counts, and the letter numbers over an ensemble of glyph
  sets that all give the printed 43-pixel C.
* ``projtrack.experiments.correlators.autocorrelation``: peaks, PSR and SNR of a letter's
  correlations, clean and noisy (Figs. 3-5), and the chapter's noise reading.
* ``projtrack.experiments.correlators.discrimination``: one filter against the true and a
  wrong letter, clean and noisy (Figs. 6-7), binary against zero-mean data.
* ``projtrack.experiments.correlators.recognition``: the 26-letter recognition test as
  Monte Carlo studies (noise level, glyph set, noise law, classification rule, margins).
* ``projtrack.experiments.correlators.snr``: output and input SNR of 2-D, projection and
  1-D signal correlations under white noise (Sec. II.C).
* ``projtrack.experiments.correlators.detectors``: the summed-output detector rule of the
  multichannel correlator against the sum of peaks (Fig. 8).
* ``projtrack.experiments.correlators.objects``: several objects located by projection
  correlations: scenes, matching to the truth, random-scene and ideal-detector studies,
  object counts from correlation energy.
* ``projtrack.experiments.correlators.plots``: plotting helpers (matplotlib).
"""

from __future__ import annotations

from .autocorrelation import (NOISE_EXTENT, NOISY_QUANTITIES, PLANES, calibrated_extent, in_frame, noisy_measures,
                              noisy_study, peak_at_centre_study, peak_measures, psr_as_row, snr_by_extent,
                              zero_mean_psr)
from .detectors import detector_rule_study
from .discrimination import binary_vs_zero_mean, correlation_peak, magnitude_mismatch, noisy_pair_study, unit_image
from .objects import (IDEAL_KEYS, LINE_KEYS, energy_count, energy_count_study, ideal_count_study,
                      ideal_detector_study, ideal_ghosts, lines_ghost_free, match_positions, place_objects,
                      random_positions, random_scene_study, switching_pair, unique_from_lines,
                      unique_from_projections)
from .plots import DIAGONAL_PANELS, auto_cross_figure
from .recognition import DETECTIONS, RULES, detection_study, margin_study, noise_sweep, predictor_accuracy, recognition_study
from .scoring import (FIG6_KINDS, close_to_printed, compare_printed, counts_consistent, counts_consistent_mc,
                      ensemble_numbers, ensemble_table, error_count_pmf, glyph_verdict, inside_share, inside_widened,
                      last_perfect,
                      letter_numbers, member_alphabet, share_within, summarize_draws)
from .snr import (combine_study, input_snr_ratio, loss_closed_form, output_snr_study, signal_1d_study, snr_signals,
                  texture_losses)
from .theorems import central_slice_errors, eq3_errors, eq3_random_pairs, eq3_wrong_angle

__all__ = [
    "central_slice_errors", "eq3_errors", "eq3_random_pairs", "eq3_wrong_angle",
    "inside_widened", "inside_share", "error_count_pmf", "counts_consistent", "counts_consistent_mc", "last_perfect",
    "summarize_draws",
    "in_frame", "peak_measures", "psr_as_row", "zero_mean_psr", "NOISY_QUANTITIES", "noisy_measures", "noisy_study",
    "PLANES", "NOISE_EXTENT", "snr_by_extent", "calibrated_extent", "peak_at_centre_study",
    "FIG6_KINDS", "ensemble_table", "member_alphabet", "letter_numbers", "ensemble_numbers", "share_within",
    "close_to_printed", "compare_printed", "glyph_verdict",
    "unit_image", "correlation_peak", "noisy_pair_study", "binary_vs_zero_mean", "magnitude_mismatch",
    "noise_sweep", "recognition_study", "RULES", "margin_study", "predictor_accuracy", "DETECTIONS", "detection_study",
    "snr_signals", "output_snr_study", "loss_closed_form", "input_snr_ratio", "texture_losses", "signal_1d_study",
    "combine_study",
    "detector_rule_study",
    "place_objects", "energy_count", "match_positions", "random_positions", "random_scene_study",
    "switching_pair", "ideal_ghosts", "unique_from_projections", "ideal_detector_study", "IDEAL_KEYS",
    "LINE_KEYS", "lines_ghost_free", "unique_from_lines", "ideal_count_study", "energy_count_study",
    "DIAGONAL_PANELS", "auto_cross_figure",
]
