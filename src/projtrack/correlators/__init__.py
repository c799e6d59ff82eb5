"""Projection correlations: Casasent & Song (1988), chapter 2 of Casasent's 1989 report.

D. P. Casasent and J.-H. Song, "Optical projection correlations", Appl. Opt. 27,
4977-4984 (1988). Implemented here:

* :func:`project`: the projection ``p_theta(r)`` of an image at any angle, Eq. (1);
* :func:`projection_spectrum` and :func:`fourier_slice`: the two sides of the central
  slice theorem, Eq. (2);
* :func:`correlate1d`, :func:`correlate2d`: full bipolar (signed) cross-correlations by
  FFT; :func:`projection_correlation` (1-D correlation of two projections) and
  :func:`integrated_correlation` (projection of the 2-D correlation), equal by Eq. (3);
  :func:`circular_correlate`, the cyclic (FFT-plane) correlation of two equal-size frames,
  whose plane has the size of the frame (the "64 x 64 correlation plane" of Sec. III.A);
* :func:`psr`, :func:`snr`, :func:`peak_stats`: the measures of Eqs. (5a)-(5b) with the
  windows of Sec. III.A; :func:`zero_mean`, :func:`normalize_energy` (Sec. III.B-C);
* :class:`ProjectionCorrelationClassifier`: a bank of projection-correlation filters per
  class, scored by the sum of the largest peaks (Sec. III.C), and
  :class:`Correlation2DClassifier`, the same bank with full 2-D correlations;
* :func:`backprojection_min` and :func:`locate_objects`: several projections locating
  several objects (Sec. V, Fig. 10);
* :func:`space_integrating_correlator` and :func:`time_integrating_correlator`: numerical
  models of the multichannel acousto-optic correlators of Figs. 8 and 9 (Sec. IV).

Every name is importable from the package itself (``projtrack.correlators.project``).

.. rubric:: Modules

* ``projtrack.correlators.preprocess``: zero-mean and unit-energy images (Sec. III.B-C).
* ``projtrack.correlators.projections``: projections at any angle, their binning and
  coordinates, and the central slice theorem (Eqs. (1)-(2)).
* ``projtrack.correlators.correlation``: full, cyclic and projection correlations (Eq. (3)).
* ``projtrack.correlators.measures``: PSR, SNR and peak statistics of a correlation plane (Eq. (5)).
* ``projtrack.correlators.classifiers``: the 1-D projection and 2-D correlation filter banks.
* ``projtrack.correlators.objects``: backprojection of projection correlations to locate objects.
* ``projtrack.correlators.acousto_optic``: space- and time-integrating acousto-optic correlators.

Conventions
-----------
An image ``f[i, j]`` has rows ``i`` (0 at the top) and columns ``j``. Its coordinates are
measured from the **centre of the array**: ``x = j - (W - 1) / 2`` to the right and
``y = (H - 1) / 2 - i`` upwards. The projection axis is ``r = x cos(theta) + y sin(theta)``
(Eq. (1)), theta in degrees counter-clockwise from the x axis: ``theta = 0`` integrates
each column (the paper's *vertical* projection), ``theta = 90`` each row (the
*horizontal* projection). The binning of the projections is described in
``projtrack.correlators.projections``, the correlation plane and the accuracy of
Eq. (3) in ``projtrack.correlators.correlation``.
"""

from __future__ import annotations

from .acousto_optic import space_integrating_correlator, time_integrating_correlator
from .classifiers import Correlation2DClassifier, CorrelationFilterBank, ProjectionCorrelationClassifier
from .correlation import (circular_correlate, correlate1d, correlate2d, integrated_correlation,
                          projection_correlation)
from .measures import peak_stats, psr, snr, snr_db
from .objects import backprojection_min, locate_objects
from .preprocess import normalize_energy, zero_mean
from .projections import (fourier_slice, is_lattice_angle, project, project_stack, projection_axis,
                          projection_spectrum)

__all__ = [
    "zero_mean", "normalize_energy", "is_lattice_angle", "projection_axis", "project",
    "project_stack", "projection_spectrum", "fourier_slice", "correlate1d", "correlate2d",
    "projection_correlation", "integrated_correlation", "circular_correlate", "psr", "snr", "snr_db", "peak_stats",
    "CorrelationFilterBank", "ProjectionCorrelationClassifier", "Correlation2DClassifier", "backprojection_min",
    "locate_objects", "space_integrating_correlator", "time_integrating_correlator",
]
