"""Hough-transform track initiation: Casasent & Slaski (1988).

Implements chapter 3 of Casasent's 1989 report (D. Casasent and J. Slaski, "Optical
track initiator for multitarget tracking", Appl. Opt. 27, 4546, 1988):

* the straight-line Hough transform (HT) in the normal parametrization,
  ``rho = x cos(theta) + y sin(theta)`` (Eq. (1)), as point voting
  (:func:`hough_transform`, :func:`hough_transform_image`) and as the integral of
  Eqs. (2)-(3), a projection of the image at every angle, computed numerically by
  rotating and integrating the image as the Dove-prism processor of Fig. 11 does
  (:func:`rotate_integrate_hough`);
* the thresholded HT of Sec. V (threshold every frame's HT, then sum:
  :func:`thresholded_hough_transform`);
* peaks: :func:`find_peaks` finds local maxima above a vote threshold by default
  (scikit-image's ``hough_line_peaks`` conventions), and the peak detector of Sec. VII
  with ``method="ratio"``: ratio of the exact HT to its 5 x 5 local average above 3,
  split peaks bridged at 1.5 provided one cell exceeds 3, adjacent peak cells grouped
  and their centroid taken (:func:`detect_peaks`), with a documented minimum-vote floor;
* track confirmation and state estimation of Sec. III: the strip of half-width
  ``drho`` along a detected line, its projection at increasing resolutions ``dx'``,
  the pulse correlation with empty samples set to -10, the 75 % rule, the position of
  Eq. (5), the velocity of Eqs. (6)-(7) (with ``P_D`` compensation) and a prediction
  ``k`` frames ahead (:func:`estimate_track`);
* the covariance approximations of Eqs. (8), (9), (12), (13) (:func:`track_covariance`);
* a :class:`TrackInitiator` chaining all of this over a stack of frames (its docstring
  gives the estimator's measured accuracy; ``refine=True`` re-estimates each confirmed
  track by least squares on its strip's points).

.. rubric:: Modules

* :mod:`~projtrack.hough.transform`: the HT by point voting, of a binary image, thresholded
  per frame, and by rotate-and-integrate; the plane's axes; the line through points.
* :mod:`~projtrack.hough.peaks`: the local average and the ratio/bridge peak detector
  with the theta wrap-around; lines sharing an averaging window.
* :mod:`~projtrack.hough.estimate`: strip projection, pulse correlation, the ``dx'``
  procedure, the covariances and the track estimate of Sec. III.
* :mod:`~projtrack.hough.initiator`: :class:`TrackInitiator`, the whole chain over a stack.
* ``projtrack.hough._checks``: argument checks only this package needs.

Scoring against ground truth (:func:`match_lines`, :func:`evaluate_initiation`) and the
Sec. VI accuracy experiment (:func:`accuracy_experiment`) live in
:mod:`projtrack.experiments.hough` (the experiment layer; this package imports neither it
nor the scenes).

Conventions
-----------
Points are ``(x, y)`` pixel coordinates in an image of ``shape = (height, width)``
with ``0 <= x < width`` and ``0 <= y < height`` (``x`` along columns, ``y`` along rows;
figures draw ``y`` upwards). ``rho`` is measured from the image centre
``(width / 2, height / 2)``, as in the paper (``rho`` over about +-180 for a 256 x 256
frame, ``theta`` over [0, 180) degrees); ``origin="corner"`` measures it from pixel
(0, 0) instead, which is the convention of :func:`skimage.transform.hough_line`.

The paper prints Eq. (4) as ``x' = x sin(theta) + y cos(theta)``,
``y' = -x cos(theta) + y sin(theta) - rho``, which is not consistent with Eq. (1) (the
``y'`` of a point on the line would not vanish). We use the rotation that is:
``y' = x cos(theta) + y sin(theta) - rho`` (signed distance to the line) and ``x'``
along the line, oriented in the direction of motion.
"""

from __future__ import annotations

from projtrack.hough.estimate import (PULSE_ZERO_VALUE, ProjectionResult, TrackEstimate, estimate_track,
                                      project_and_correlate, pulse_correlation, strip_projection,
                                      track_covariance)
from projtrack.hough.initiator import TrackInitiator
from projtrack.hough.peaks import HoughPeak, detect_peaks, find_peaks, local_average, window_neighbours
from projtrack.hough.transform import (hough_axes, hough_transform, hough_transform_image, line_through,
                                       rotate_integrate_hough, thresholded_hough_transform)

__all__ = [
    "hough_axes",
    "hough_transform",
    "hough_transform_image",
    "thresholded_hough_transform",
    "rotate_integrate_hough",
    "local_average",
    "HoughPeak",
    "detect_peaks",
    "find_peaks",
    "strip_projection",
    "pulse_correlation",
    "ProjectionResult",
    "project_and_correlate",
    "track_covariance",
    "TrackEstimate",
    "estimate_track",
    "TrackInitiator",
    "PULSE_ZERO_VALUE",
    "line_through",
    "window_neighbours",
]
