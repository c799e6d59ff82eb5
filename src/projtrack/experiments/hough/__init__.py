"""Experiments of the Hough track-initiation chapter (Casasent & Slaski 1988).

* :mod:`~projtrack.experiments.hough.scoring`: which target a detected line belongs to,
  and the scorecard of one initiator run on a scene with ground truth.
* :mod:`~projtrack.experiments.hough.salvo`: the six-launch scenes of Figs. 2-3 and
  their Monte Carlo trials (counts, why targets are missed, speeds at ``P_D = 0.9``), and
  the crossing and closely spaced tracks of Sec. V.
* :mod:`~projtrack.experiments.hough.thresholded`: the plain against the thresholded HT
  on noisy scenes (Figs. 5-6 and the operating curves), and how far the ratio-3 peak rule
  reaches on a biased plane, checked against simulation.
* :mod:`~projtrack.experiments.hough.optical`: the transform itself: its parameters (Sec. II.B),
  Eq. (4), the optical (rotate-and-integrate) HT of Fig. 11 against point voting, the work of
  each stage (Sec. IV), and our HT and peak rules against skimage's.
* :mod:`~projtrack.experiments.hough.continuous`: the 120-s run of Fig. 4 in 5-s segments.
* :mod:`~projtrack.experiments.hough.accuracy`: the Sec. VI accuracy experiment (errors
  of position and velocity against the predicted standard deviations).
* :mod:`~projtrack.experiments.hough.plots`: drawing a composite with its tracks (Figs. 2-3).
"""

from __future__ import annotations

from projtrack.experiments.hough.accuracy import (ROUND_VAR, STOPS, accuracy_experiment, accuracy_sweep, accuracy_target,
                                                  baseline_within, closest_margin, readings_table, within_counts)
from projtrack.experiments.hough.continuous import (POSSIBLE_READINGS, continuous_run, never_detected,
                                                    possible_detections, run_outcome)
from projtrack.experiments.hough.optical import (EQ4_READINGS, OPT_PLANES, SKIMAGE_RULES, composite_image,
                                                 eq4_strip_counts, exact_hough, geometry_trial, match_peaks,
                                                 optics_trial, peer_trial, plateau_trial, plateau_width,
                                                 skimage_cells, skimage_trial, stage_costs)
from projtrack.experiments.hough.salvo import (PAIR_KINDS, SALVO_TIMES, clutter_summary, pair_scene, pair_summary,
                                               pair_trial, reading_trial, salvo_scene, salvo_trial, speeds_by_target)
from projtrack.experiments.hough.scoring import (evaluate_initiation, fraction_needed, match_lines, mean_field_ratio,
                                                 rate_ci)
from projtrack.experiments.hough.thresholded import (bound_tables, floor_tradeoff, noise_plane, noisy_scene,
                                                     perfect_line_trial, plain_and_thresholded, reading_counts,
                                                     rule_counts, rule_summary, target_peaks, tradeoff_tables)

__all__ = [
    "match_lines",
    "evaluate_initiation",
    "accuracy_target",
    "accuracy_experiment",
    "STOPS",
    "ROUND_VAR",
    "accuracy_sweep",
    "within_counts",
    "readings_table",
    "baseline_within",
    "closest_margin",
    "SALVO_TIMES",
    "salvo_scene",
    "speeds_by_target",
    "salvo_trial",
    "reading_trial",
    "continuous_run",
    "never_detected",
    "POSSIBLE_READINGS",
    "possible_detections",
    "run_outcome",
    "PAIR_KINDS",
    "pair_scene",
    "pair_trial",
    "pair_summary",
    "clutter_summary",
    "rate_ci",
    "floor_tradeoff",
    "tradeoff_tables",
    "mean_field_ratio",
    "fraction_needed",
    "perfect_line_trial",
    "reading_counts",
    "bound_tables",
    "EQ4_READINGS",
    "eq4_strip_counts",
    "geometry_trial",
    "plateau_width",
    "plateau_trial",
    "stage_costs",
    "noisy_scene",
    "plain_and_thresholded",
    "noise_plane",
    "target_peaks",
    "rule_counts",
    "rule_summary",
    "composite_image",
    "exact_hough",
    "match_peaks",
    "OPT_PLANES",
    "optics_trial",
    "skimage_cells",
    "skimage_trial",
    "SKIMAGE_RULES",
    "peer_trial",
]
