"""Experiments of the Hough track-initiation chapter (Casasent & Slaski 1988).

* :mod:`~projtrack.experiments.hough.scoring`: which target a detected line belongs to,
  and the scorecard of one initiator run on a scene with ground truth.
* :mod:`~projtrack.experiments.hough.accuracy`: the Sec. VI accuracy experiment (errors
  of position and velocity against the predicted standard deviations).
"""

from __future__ import annotations

from projtrack.experiments.hough.accuracy import accuracy_experiment
from projtrack.experiments.hough.scoring import evaluate_initiation, match_lines

__all__ = ["match_lines", "evaluate_initiation", "accuracy_experiment"]
