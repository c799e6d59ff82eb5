"""Experiments of the projection-correlation chapter (Casasent & Song 1988): the studies its notebooks run.

.. rubric:: Modules

* ``projtrack.experiments.correlators.theorems``: numerical checks of the central slice
  theorem (Eq. (2)) and of Eq. (3).
* ``projtrack.experiments.correlators.scoring``: printed values against our draws, and
  the plausibility of the paper's error counts.
* ``projtrack.experiments.correlators.autocorrelation``: peaks, PSR and SNR of a letter's
  correlations, clean and noisy (Figs. 3-5).
* ``projtrack.experiments.correlators.discrimination``: one filter against the true and a
  wrong letter, clean and noisy (Figs. 6-7).
* ``projtrack.experiments.correlators.recognition``: the 26-letter recognition test as
  Monte Carlo noise sweeps (noise level, extent and law).
* ``projtrack.experiments.correlators.snr``: output SNR of 2-D and projection correlations
  under white noise (Sec. II.C).
* ``projtrack.experiments.correlators.detectors``: the summed-output detector rule of the
  multichannel correlator against the sum of peaks (Fig. 8).
* ``projtrack.experiments.correlators.objects``: several objects located by projection
  correlations: scenes, matching to the truth, random-scene and ideal-detector studies.
* ``projtrack.experiments.correlators.plots``: plotting helpers (matplotlib).
"""

from __future__ import annotations

from .autocorrelation import (NOISY_QUANTITIES, in_frame, noisy_measures, noisy_study, peak_at_centre_study,
                              peak_measures, psr_as_row)
from .detectors import detector_rule_study
from .discrimination import correlation_peak, noisy_pair_study, unit_image
from .objects import (IDEAL_KEYS, energy_count, ideal_detector_study, ideal_ghosts, match_positions,
                      place_objects, random_positions, random_scene_study, switching_pair,
                      unique_from_projections)
from .plots import DIAGONAL_PANELS, auto_cross_figure
from .recognition import noise_extent_study, noise_sweep, predictor_accuracy
from .scoring import counts_consistent, error_count_pmf, inside_widened, last_perfect
from .snr import output_snr_study, snr_signals
from .theorems import central_slice_errors, eq3_errors, eq3_random_pairs

__all__ = [
    "central_slice_errors", "eq3_errors", "eq3_random_pairs",
    "inside_widened", "error_count_pmf", "counts_consistent", "last_perfect",
    "in_frame", "peak_measures", "psr_as_row", "NOISY_QUANTITIES", "noisy_measures", "noisy_study",
    "peak_at_centre_study",
    "unit_image", "correlation_peak", "noisy_pair_study",
    "noise_sweep", "noise_extent_study", "predictor_accuracy",
    "snr_signals", "output_snr_study",
    "detector_rule_study",
    "place_objects", "energy_count", "match_positions", "random_positions", "random_scene_study",
    "switching_pair", "ideal_ghosts", "unique_from_projections", "ideal_detector_study", "IDEAL_KEYS",
    "DIAGONAL_PANELS", "auto_cross_figure",
]
