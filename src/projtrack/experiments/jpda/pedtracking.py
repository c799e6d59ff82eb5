"""Track management around the chapter's trackers, for sequences where people come and go.

:class:`projtrack.jpda.JPDATracker` and :class:`projtrack.jpda.GNNTracker` follow a
fixed set of targets started on known states (track initiation is chapter 3's job). On
real sequences people enter and leave, so :func:`track_sequence` wraps each tracker in
the same track management, identical for every tracker:

* **birth**: every detection outside the gate of every existing track starts a
  tentative track at the detection with zero velocity and covariance ``model.P0``;
* **confirmation**: a tentative track becomes confirmed after ``model.confirm_after``
  consecutive scans with at least one detection inside its gate, and is deleted at its
  first scan without one;
* **deletion**: a confirmed track is deleted after ``model.delete_after`` consecutive
  scans with no detection inside its gate, or when its position leaves the image;
  a track is deleted as a duplicate when its position cannot be told from an older
  track's (the track-to-track test ``(p_i - p_j)' (P_i + P_j)^-1 (p_i - p_j)`` inside
  the chi-square gate, on the updated positions);
* **output**: confirmed tracks report their updated position at every scan they live.

The gates (chi-square, probability ``model.gate_prob``) are evaluated on the predicted
measurements, which every tracker computes alike from its states, so the management
makes the same decisions for trackers whose states agree. Three trackers run inside it:

``"jpda"``
    the book's :class:`~projtrack.jpda.JPDATracker` (exact beta by
    :func:`projtrack.jpda.beta`);
``"gnn"``
    the book's :class:`~projtrack.jpda.GNNTracker` (global nearest neighbour);
``"stonesoup"``
    Stone Soup's tracker parts: ``KalmanPredictor``, ``PDAHypothesiser``, the exact
    ``JPDAwithEHM`` associator (efficient hypothesis management, Maskell et al. 2004)
    and the ``PDAUpdater``: the peer, with the same model.

The book's trackers keep a fixed list of ``filterpy`` Kalman filters; tracks are added and
removed here through that list (``tracker.bank.filters``: the tracker is built by its own
constructor on the first track, later filters are set up as its bank sets up its own),
because the trackers have no public way to add or drop a track.
"""

from __future__ import annotations

import datetime
import warnings
from dataclasses import dataclass, field

import numpy as np

from projtrack._validation import as_choice, as_int
from projtrack.jpda import GNNTracker, JPDATracker, gate_threshold, mahalanobis_sq

__all__ = ["TRACKERS", "PedestrianModel", "TrackRun", "track_sequence", "predicted_measurements"]

#: The trackers :func:`track_sequence` runs.
TRACKERS: tuple[str, ...] = ("jpda", "gnn", "stonesoup")

_T0 = datetime.datetime(2000, 1, 1)


@dataclass(frozen=True)
class PedestrianModel:
    """Everything a tracker and the track management use (built by
    :func:`projtrack.experiments.jpda.pedestrian_model` from the data's statistics).

    ``F, Q, H, R`` are the constant-velocity model in state ``(x, vx, y, vy)`` (pixels,
    one frame per step); ``q`` the per-axis white-acceleration densities that make ``Q``
    (Stone Soup's ``ConstantVelocity`` uses them); ``P0`` the covariance of a new track.
    """

    F: np.ndarray
    Q: np.ndarray
    H: np.ndarray
    R: np.ndarray
    P0: np.ndarray
    q: tuple[float, float]
    p_detect: float
    clutter_density: float
    gate_prob: float
    confirm_after: int
    delete_after: int
    image_size: tuple[int, int]


@dataclass
class TrackRun:
    """The output of :func:`track_sequence`.

    ``frame``, ``ident``, ``point``: one row per reported (confirmed) track and frame.
    ``problems``: with ``record=True``, the association problem of each scan that had
    tracks, ``(z, zp, S)`` (detections, predicted measurements, innovation covariances).
    """

    tracker: str
    frame: np.ndarray
    ident: np.ndarray
    point: np.ndarray
    n_tracks_started: int
    problems: list = field(default_factory=list)


def predicted_measurements(x: np.ndarray, P: np.ndarray, model: PedestrianModel):
    """Predicted measurements ``(T, 2)`` and innovation covariances ``(T, 2, 2)`` of states
    ``x (T, 4)`` with covariances ``P (T, 4, 4)``."""
    F, Q, H, R = model.F, model.Q, model.H, model.R
    xp = x @ F.T
    Pp = F @ P @ F.T + Q
    return xp @ H.T, H @ Pp @ H.T + R


class _BookEngine:
    """The book's JPDA or GNN tracker; tracks are filters of its ``bank``."""

    def __init__(self, model: PedestrianModel, kind: str):
        self.model, self.kind = model, kind
        self.tracker = None

    def add(self, x, P, ts):
        m = self.model
        if self.tracker is None:  # the tracker, built by its own constructor on the first track
            args = (x[None], P, m.F, m.Q, m.H, m.R)
            self.tracker = (JPDATracker(*args, p_detect=m.p_detect, clutter_density=m.clutter_density,
                                        gate_prob=m.gate_prob) if self.kind == "jpda"
                            else GNNTracker(*args, gate_prob=m.gate_prob))
            return
        # later tracks: a filter set up as the tracker's bank sets up its own
        from filterpy.kalman import KalmanFilter

        kf = KalmanFilter(dim_x=4, dim_z=2)
        kf.x, kf.P = x.reshape(4, 1).copy(), P.copy()
        kf.F, kf.Q, kf.H, kf.R = m.F.copy(), m.Q.copy(), m.H.copy(), m.R.copy()
        self.tracker.bank.filters.append(kf)

    def keep(self, mask):
        if self.tracker is not None:
            self.tracker.bank.filters[:] = [f for f, k in zip(self.tracker.bank.filters, mask) if k]

    def states(self):
        if self.tracker is None or not self.tracker.bank.filters:
            return np.zeros((0, 4)), np.zeros((0, 4, 4))
        fs = self.tracker.bank.filters
        return np.array([f.x.ravel() for f in fs]), np.array([f.P for f in fs])

    def step(self, z, ts):
        self.tracker.step(z)


class _StoneSoupEngine:
    """Stone Soup's predictor, PDA hypothesiser, JPDA with EHM and PDA updater."""

    def __init__(self, model: PedestrianModel):
        from stonesoup.dataassociator.probability import JPDAwithEHM
        from stonesoup.hypothesiser.probability import PDAHypothesiser
        from stonesoup.models.measurement.linear import LinearGaussian
        from stonesoup.models.transition.linear import (CombinedLinearGaussianTransitionModel,
                                                        ConstantVelocity)
        from stonesoup.predictor.kalman import KalmanPredictor
        from stonesoup.updater.kalman import KalmanUpdater
        from stonesoup.updater.probability import PDAUpdater

        self.model = model
        trans = CombinedLinearGaussianTransitionModel([ConstantVelocity(model.q[0]),
                                                       ConstantVelocity(model.q[1])])
        self.meas = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=model.R)
        hyp = PDAHypothesiser(KalmanPredictor(trans), KalmanUpdater(self.meas),
                              clutter_spatial_density=model.clutter_density,
                              prob_detect=model.p_detect, prob_gate=model.gate_prob)
        self.assoc = JPDAwithEHM(hyp)
        self.updater = PDAUpdater(self.meas)
        self.tracks: list = []

    def add(self, x, P, ts):
        from stonesoup.types.state import GaussianState
        from stonesoup.types.track import Track

        self.tracks.append(Track([GaussianState(x.reshape(4, 1), P.copy(), timestamp=ts)]))

    def keep(self, mask):
        self.tracks = [t for t, k in zip(self.tracks, mask) if k]

    def states(self):
        if not self.tracks:
            return np.zeros((0, 4)), np.zeros((0, 4, 4))
        return (np.array([np.asarray(t.state_vector, float).ravel() for t in self.tracks]),
                np.array([np.asarray(t.covar, float) for t in self.tracks]))

    def step(self, z, ts):
        from stonesoup.types.detection import Detection

        dets = {Detection(zj.reshape(2, 1), timestamp=ts, measurement_model=self.meas) for zj in z}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # Stone Soup warns about its Probability arithmetic
            out = self.assoc.associate(set(self.tracks), dets, ts)
            for t in self.tracks:
                t.append(self.updater.update(out[t]))


def _drop_duplicates(x: np.ndarray, P: np.ndarray, H: np.ndarray, keep: np.ndarray, gate: float) -> list:
    """``keep`` with every track removed whose position cannot be told from an older kept
    track's: ``(p_i - p_j)' (P_i + P_j)^-1 (p_i - p_j) <= gate`` on the position parts
    (tracks are in order of age, oldest first)."""
    if len(x) < 2:
        return keep.tolist()
    p = x @ H.T
    C = H @ P @ H.T
    d = p[:, None, :] - p[None, :, :]
    Cs = C[:, None] + C[None, :]
    det = Cs[..., 0, 0] * Cs[..., 1, 1] - Cs[..., 0, 1] * Cs[..., 1, 0]
    d2 = (Cs[..., 1, 1] * d[..., 0] ** 2 - (Cs[..., 0, 1] + Cs[..., 1, 0]) * d[..., 0] * d[..., 1]
          + Cs[..., 0, 0] * d[..., 1] ** 2) / det
    close = d2 <= gate
    for j in range(1, len(x)):
        if keep[j] and np.any(close[j, :j] & keep[:j]):
            keep[j] = False
    return keep.tolist()


def track_sequence(scans: list, model: PedestrianModel, tracker: str = "jpda", *,
                   record: bool = False) -> TrackRun:
    """Track a sequence of scans with one tracker inside the shared track management.

    Parameters
    ----------
    scans : list of ndarray, each (m_k, 2)
        The detections of frames ``1, 2, ...`` (box centres, pixels).
    model : PedestrianModel
    tracker : {"jpda", "gnn", "stonesoup"}
        See the module docstring.
    record : bool
        Keep every scan's association problem ``(z, zp, S)`` (:class:`TrackRun`).

    Returns
    -------
    TrackRun
    """
    tracker = as_choice(tracker, "tracker", TRACKERS)
    if not isinstance(model, PedestrianModel):
        raise TypeError(f"model must be a PedestrianModel, got {type(model).__name__}")
    engine = _StoneSoupEngine(model) if tracker == "stonesoup" else _BookEngine(model, tracker)
    gate = gate_threshold(model.gate_prob, 2)
    width, height = model.image_size
    ids, hits, misses, confirmed = [], [], [], []
    next_id = 1
    out_f, out_i, out_p, problems = [], [], [], []
    for k, z in enumerate(scans, start=1):
        z = np.asarray(z, float).reshape(-1, 2)
        ts = _T0 + datetime.timedelta(seconds=k)
        x, P = engine.states()
        if len(x):
            zp, S = predicted_measurements(x, P, model)
            inside = mahalanobis_sq(z, zp, S) <= gate if len(z) else np.zeros((0, len(x)), bool)
            if record:
                problems.append((z.copy(), zp, S))
            engine.step(z, ts)
            x, P = engine.states()
            hit = inside.any(axis=0)
            used = inside.any(axis=1)
        else:
            hit = np.zeros(0, bool)
            used = np.zeros(len(z), bool)
        hits = [h + 1 if g else 0 for h, g in zip(hits, hit)]
        misses = [0 if g else mi + 1 for mi, g in zip(misses, hit)]
        confirmed = [c or h >= model.confirm_after for c, h in zip(confirmed, hits)]
        inside_image = (x[:, 0] >= 0) & (x[:, 0] <= width) & (x[:, 2] >= 0) & (x[:, 2] <= height)
        keep = [img and (mi == 0 or (c and mi < model.delete_after))
                for img, mi, c in zip(inside_image, misses, confirmed)]
        keep = _drop_duplicates(x, P, model.H, np.array(keep, bool), gate)
        for t in np.flatnonzero(keep):
            if confirmed[t]:
                out_f.append(k)
                out_i.append(ids[t])
                out_p.append(x[t, [0, 2]])
        engine.keep(keep)
        ids = [v for v, kk in zip(ids, keep) if kk]
        hits = [v for v, kk in zip(hits, keep) if kk]
        misses = [v for v, kk in zip(misses, keep) if kk]
        confirmed = [v for v, kk in zip(confirmed, keep) if kk]
        for zj in z[~used]:
            engine.add(np.array([zj[0], 0.0, zj[1], 0.0]), model.P0, ts)
            ids.append(next_id)
            next_id += 1
            hits.append(1)
            misses.append(0)
            confirmed.append(model.confirm_after <= 1)
    return TrackRun(tracker=tracker, frame=np.array(out_f, dtype=np.int64), ident=np.array(out_i, dtype=np.int64),
                    point=np.array(out_p, float).reshape(-1, 2), n_tracks_started=next_id - 1,
                    problems=problems)
