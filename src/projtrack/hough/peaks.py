"""Peak detection in the Hough plane (Sec. VII).

The ``5 x 5`` local average (the defocused HT, :func:`local_average`), the ratio rule
with bridging of split peaks and the wrap-around of ``theta`` at 0/180 degrees joined
by union-find (:func:`detect_peaks`, :func:`find_peaks`), and which lines share an
averaging window (:func:`window_neighbours`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from projtrack._validation import as_choice, as_int, as_odd_window, as_real, only_value_errors
from projtrack.hough._checks import _check_plane

__all__ = [
    "local_average",
    "HoughPeak",
    "detect_peaks",
    "find_peaks",
    "window_neighbours",
]


def _wraps(rhos: np.ndarray, thetas: np.ndarray) -> bool:
    """True when theta covers [0, 180) uniformly and rho is symmetric: the plane wraps."""
    dt = thetas[1] - thetas[0]
    return (abs(thetas[0]) < 1e-9 and abs(thetas[-1] + dt - 180.0) < 1e-6
            and np.allclose(np.diff(thetas), dt) and np.allclose(rhos, -rhos[::-1]))


def local_average(H: object, size: int = 5, *, rhos: object | None = None,
                  thetas_deg: object | None = None, exclude_ridge: int | None = None) -> np.ndarray:
    """The ``size x size`` local average of the Hough plane (the defocused HT of Section
    VII).

    Outside the plane ``rho`` is padded with zeros; ``theta`` wraps around with
    ``(rho, theta + 180) = (-rho, theta)`` when ``rhos`` and ``thetas_deg`` show that the
    plane covers [0, 180) with a symmetric ``rho`` axis, and is zero-padded otherwise.

    Parameters
    ----------
    H : array_like, 2-D
        Hough plane, ``rho`` along axis 0 and ``theta`` along axis 1.
    size : int, default 5
        Odd side of the window.
    rhos, thetas_deg : array_like, keyword-only, optional
        The plane's axes (used only to decide the wrap-around in ``theta``).
    exclude_ridge : int or None, keyword-only
        ``None`` (default, the paper's defocused HT): the mean over the whole window.
        An int ``r >= 0`` with ``2 r + 1 < size``: the mean over the window without the
        ``2 r + 1`` rows of ``rho`` bins centred on the cell, i.e. without the ridge
        that a line's own votes form along ``theta`` at its ``rho`` (every point of a
        line votes in each ``theta`` column of the window, close to the line's ``rho``).
        What remains measures the background bias of the plane, not the line itself.
        Not the paper's rule; see :func:`detect_peaks`.
    """
    Hf = np.asarray(H, dtype=float)
    if Hf.ndim != 2:
        raise ValueError(f"H must be 2-D, got shape {Hf.shape}")
    size = only_value_errors(as_odd_window, size, "size")
    k = size // 2
    if exclude_ridge is not None:
        exclude_ridge = only_value_errors(as_int, exclude_ridge, "exclude_ridge", minimum=0)
        if 2 * exclude_ridge + 1 >= size:
            raise ValueError(f"exclude_ridge must be None or an int r >= 0 with 2 r + 1 < size ({size}), "
                             f"got {exclude_ridge!r}")
    wrap = False
    if rhos is not None and thetas_deg is not None:
        _, r, t = _check_plane(Hf, rhos, thetas_deg)
        wrap = _wraps(r, t)
    if wrap and k > 0:
        left, right = Hf[::-1, -k:], Hf[::-1, :k]
        padded = np.concatenate([left, Hf, right], axis=1)
    else:
        padded = np.pad(Hf, ((0, 0), (k, k)))
    padded = np.pad(padded, ((k, k), (0, 0)))
    avg = ndimage.uniform_filter(padded, size=size, mode="constant", cval=0.0)
    if exclude_ridge is None:
        return avg[k:k + Hf.shape[0], k:k + Hf.shape[1]]
    r = int(exclude_ridge)
    ridge = ndimage.uniform_filter(padded, size=(2 * r + 1, size), mode="constant", cval=0.0)
    total = avg * size * size - ridge * (2 * r + 1) * size
    out = total / ((size - 2 * r - 1) * size)
    out = out[k:k + Hf.shape[0], k:k + Hf.shape[1]]
    return np.where(np.abs(out) < 1e-9 * max(1.0, float(np.abs(Hf).max(initial=0.0))), 0.0, out)


@dataclass(frozen=True)
class HoughPeak:
    """One detected line: the centroid of a group of peak cells.

    Attributes
    ----------
    rho, theta_deg : float
        Centroid of the group (weighted by the votes), the line's parameters.
    votes : float
        Largest cell value of the group.
    ratio : float
        Largest ratio of exact to averaged HT in the group.
    n_cells : int
        Number of cells in the group.
    """

    rho: float
    theta_deg: float
    votes: float
    ratio: float
    n_cells: int


def detect_peaks(H: object, rhos: object, thetas_deg: object, *, ratio: float = 3.0,
                 bridge: float = 1.5, min_votes: float = 3.0, size: int = 5,
                 exclude_ridge: int | None = None) -> list[HoughPeak]:
    """Peak detector of Section VII with a minimum-vote floor; see :func:`find_peaks`.

    ``exclude_ridge`` (default ``None``, the paper's rule) is passed to
    :func:`local_average`: with ``exclude_ridge=1`` the ratio compares a cell with the
    mean of its ``5 x 5`` window without the three ``rho`` rows through it, i.e. with the
    background of the plane rather than with the line's own ridge. For an ideal line of
    ``N`` votes on a bias ``b`` (false pixels vote in the line's own cell too) the paper's
    ratio is ``(N + b) / (N/5 + b) < 5``, the ridge-free one ``(N + b) / b``.

    Parameters
    ----------
    H : array_like, shape (len(rhos), len(thetas_deg))
        Non-negative Hough plane.
    rhos, thetas_deg : array_like
        Its axes, strictly increasing.
    ratio, bridge : float, keyword-only, default 3 and 1.5
        The paper's thresholds on the ratio of a cell to its local average
        (``bridge <= ratio``).
    min_votes : float, keyword-only, default 3
        Cells with fewer votes are never peak cells.
    size : int, keyword-only, default 5
        Odd side of the averaging window.
    exclude_ridge : int or None, keyword-only
        See above and :func:`local_average`.

    Returns
    -------
    list of HoughPeak
        Sorted by decreasing ``votes`` (then ``ratio``).
    """
    Hf, r, t = _check_plane(H, rhos, thetas_deg)
    ratio = as_real(ratio, "ratio", 0, low_open=True)
    bridge = as_real(bridge, "bridge", 0, low_open=True)
    if bridge > ratio:
        raise ValueError(f"bridge ({bridge}) must not exceed ratio ({ratio})")
    min_votes = only_value_errors(as_real, min_votes, "min_votes", 0)
    avg = local_average(Hf, size, rhos=r, thetas_deg=t, exclude_ridge=exclude_ridge)
    with np.errstate(divide="ignore", invalid="ignore"):
        # an empty neighbourhood (possible only with exclude_ridge) under a voted cell: infinite ratio
        R = np.where(avg > 0, Hf / np.where(avg > 0, avg, 1.0), np.where(Hf > 0, np.inf, 0.0))
    ok = Hf >= max(float(min_votes), np.finfo(float).tiny)
    strong = (R > ratio) & ok
    weak = (R > bridge) & ok
    labels, n = ndimage.label(weak, structure=np.ones((3, 3), dtype=bool))
    if n == 0:
        return []
    wrap = _wraps(r, t)
    seam = np.zeros(n + 1, dtype=bool)
    if wrap:  # join groups across theta = 0 / 180, where (rho, 180) is (-rho, 0)
        parent = np.arange(n + 1)

        def root(a: int) -> int:
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a

        first, last = labels[:, 0], labels[::-1, -1]  # last column mirrored in rho
        for k in (-1, 0, 1):
            a = first[max(0, k):first.size + min(0, k)]
            b = last[max(0, -k):last.size + min(0, -k)]
            for u, v in zip(a[(a > 0) & (b > 0)], b[(a > 0) & (b > 0)]):
                ru, rv = root(int(u)), root(int(v))
                if ru != rv:
                    parent[max(ru, rv)] = min(ru, rv)
                seam[ru] = seam[rv] = True
        roots = np.array([root(a) for a in range(n + 1)])
        seam = seam[roots]
        labels = roots[labels]
    ii, jj = np.nonzero(labels)
    lab = labels[ii, jj]
    h, rr, tt, rat = Hf[ii, jj], r[ii], t[jj], R[ii, jj]
    if wrap and seam.any():  # express seam groups on theta in (-90, 90)
        flip = seam[lab] & (tt > 90.0)
        rr = np.where(flip, -rr, rr)
        tt = np.where(flip, tt - 180.0, tt)
    sc = strong[ii, jj]
    has_strong = np.bincount(lab, weights=sc, minlength=n + 1) > 0
    # The centroid is taken over the peak points (ratio above 3) of the group; the
    # bridging cells (ratio above 1.5) only join split peaks into one group.
    hs = h * sc
    wsum = np.bincount(lab, weights=hs, minlength=n + 1)
    rho_c = np.bincount(lab, weights=hs * rr, minlength=n + 1)
    th_c = np.bincount(lab, weights=hs * tt, minlength=n + 1)
    ncell = np.bincount(lab, minlength=n + 1)
    vmax = np.zeros(n + 1)
    np.maximum.at(vmax, lab, h)
    rmax = np.zeros(n + 1)
    np.maximum.at(rmax, lab, rat)
    keep = np.flatnonzero(has_strong & (wsum > 0))
    if keep.size == 0:
        return []
    peaks = []
    for k in keep:
        rho_k, th_k = rho_c[k] / wsum[k], th_c[k] / wsum[k]
        if th_k < 0:
            rho_k, th_k = -rho_k, th_k + 180.0
        peaks.append(HoughPeak(float(rho_k), float(th_k), float(vmax[k]), float(rmax[k]), int(ncell[k])))
    peaks.sort(key=lambda p: (-p.votes, -p.ratio, p.theta_deg, p.rho))
    if wrap:  # one line seen at both ends of the theta axis: keep the stronger group
        dr, dt = r[1] - r[0], t[1] - t[0]
        kept: list[HoughPeak] = []
        for p in peaks:
            dup = any(abs(abs(p.theta_deg - q.theta_deg) - 180.0) <= 2 * dt and abs(p.rho + q.rho) <= 2 * dr
                      for q in kept)
            if not dup:
                kept.append(p)
        peaks = kept
    return peaks


def find_peaks(H: object, rhos: object, thetas_deg: object, *, method: str = "local-max",
               threshold: float | None = None, min_distance: int = 9, min_angle: int = 10,
               num_peaks: int | None = None, ratio: float = 3.0, bridge: float = 1.5,
               min_votes: float = 3.0, size: int = 5) -> list[tuple[float, float]]:
    r"""Lines of a Hough plane: local maxima above a vote threshold, or the paper's ratio rule.

    ``method="local-max"`` (default) follows the conventions of scikit-image's
    ``hough_line_peaks``: a cell is a peak when it holds at least ``threshold`` votes
    (default half the plane's maximum, and never fewer than ``min_votes``) and is the
    largest in its neighbourhood of :math:`\pm` ``min_distance`` ``rho`` bins and
    :math:`\pm` ``min_angle`` ``theta`` bins; peaks are then taken strongest first,
    each suppressing the weaker ones in that neighbourhood, up to ``num_peaks``. When
    the plane covers [0, 180) degrees with a symmetric ``rho`` axis, the neighbourhood
    wraps around in ``theta`` (the cell :math:`(\rho, \theta + 180)` is
    :math:`(-\rho, \theta)`). Each peak is reported at its cell's ``(rho, theta)``, or
    at the centre of its flat top when adjacent cells hold the same votes.

    ``method="ratio"`` is the rule of Sec. VII of the paper (the book uses it): a cell
    is a peak cell when the ratio of the exact HT to its ``size x size`` local average
    (:func:`local_average`, the optically defocused HT) exceeds ``ratio`` (3). Peaks
    that split are bridged: the cells whose ratio exceeds ``bridge`` (1.5) are grouped
    by 8-adjacency and a group is kept when at least one of its cells exceeds ``ratio``.
    Each group gives one line at its vote-weighted centroid (:func:`detect_peaks` returns
    the groups with their votes and ratios). For an ideal line of :math:`N` votes on a
    plane without background the ratio is below 5 only by the line's own ridge, so the
    rule finds isolated lines, but on a sparse plane it also flags cells of two or three
    chance votes and on a busy one it misses lines: the book's chapter on the Hough
    initiator shows where it works.

    The minimum-vote floor (both methods): any two points define a line, so a cell
    with two votes is no evidence of collinearity; the default floor ``min_votes = 3``
    is the smallest count that is. :class:`TrackInitiator` raises it to a quarter of
    the number of frames of the composite.

    Parameters
    ----------
    H : array_like, shape (len(rhos), len(thetas_deg))
        Non-negative Hough plane (e.g. from :func:`hough_transform`).
    rhos, thetas_deg : array_like
        Its axes, strictly increasing.
    method : {"local-max", "ratio"}, keyword-only, default "local-max"
        The peak rule (above).
    threshold : float or None, keyword-only
        ``"local-max"``: the vote threshold; ``None`` means half the largest cell.
    min_distance, min_angle : int, keyword-only, default 9 and 10
        ``"local-max"``: half-sizes of the suppression neighbourhood, in ``rho`` and
        ``theta`` bins (scikit-image's defaults).
    num_peaks : int or None, keyword-only
        ``"local-max"``: the largest number of peaks returned (``None``: all).
    ratio, bridge : float, keyword-only, default 3 and 1.5
        ``"ratio"``: the paper's thresholds.
    min_votes : float, keyword-only, default 3
        Cells with fewer votes are never peaks.
    size : int, keyword-only, default 5
        ``"ratio"``: side of the averaging window.

    Returns
    -------
    list of (rho, theta_deg)
        One pair of floats per detected line, strongest first.

    Examples
    --------
    Three lines of 40 points among 200 uniform noise points:

    >>> import numpy as np
    >>> from projtrack.hough import find_peaks, hough_transform
    >>> rng = np.random.default_rng(0)
    >>> t = np.linspace(-60, 60, 40)
    >>> lines = [np.c_[t, 0.5 * t], np.c_[t, -t + 20], np.c_[30 + 0 * t, t]]
    >>> noise = rng.uniform(-100, 100, (200, 2))
    >>> pts = np.vstack(lines + [noise]) + 128           # (x, y) pixels
    >>> H, rhos, thetas = hough_transform(pts, (256, 256))
    >>> peaks = find_peaks(H, rhos, thetas)
    >>> len(peaks)
    3
    >>> sorted(round(th) for _, th in peaks)
    [0, 45, 116]
    """
    as_choice(method, "method", ("local-max", "ratio"))
    if method == "ratio":
        return [(p.rho, p.theta_deg) for p in detect_peaks(H, rhos, thetas_deg, ratio=ratio, bridge=bridge,
                                                           min_votes=min_votes, size=size)]
    Hf, r, t = _check_plane(H, rhos, thetas_deg)
    min_votes = only_value_errors(as_real, min_votes, "min_votes", 0)
    md = as_int(min_distance, "min_distance", minimum=0)
    ma = as_int(min_angle, "min_angle", minimum=0)
    if num_peaks is not None:
        num_peaks = as_int(num_peaks, "num_peaks", minimum=1)
    top = float(Hf.max(initial=0.0))
    thr = 0.5 * top if threshold is None else as_real(threshold, "threshold", 0)
    thr = max(thr, float(min_votes), np.finfo(float).tiny)
    wrap = _wraps(r, t) if t.size > 1 else False
    nr, nt = Hf.shape
    if wrap and ma > 0:  # theta neighbours across 0 / 180 are (-rho, theta -+ 180)
        k = min(ma, nt)
        padded = np.concatenate([Hf[::-1, -k:], Hf, Hf[::-1, :k]], axis=1)
    else:
        k = ma
        padded = np.pad(Hf, ((0, 0), (k, k)))
    local = ndimage.maximum_filter(padded, size=(2 * md + 1, 2 * ma + 1), mode="constant",
                                   cval=0.0)[:, k:k + nt]
    cand = np.flatnonzero(((Hf >= thr) & (Hf >= local)).ravel())
    order = cand[np.lexsort((cand, -Hf.ravel()[cand]))]  # strongest first, then by cell index
    taken: list[tuple[int, int]] = []
    for c in order:
        i, j = divmod(int(c), nt)
        close = False
        for a, b in taken:
            if abs(i - a) <= md and abs(j - b) <= ma:
                close = True
            elif wrap and abs(abs(j - b) - nt) <= ma and abs(i - (nr - 1 - a)) <= md:
                close = True
            if close:
                break
        if not close:
            taken.append((i, j))
            if num_peaks is not None and len(taken) >= num_peaks:
                break
    out = []
    for i, j in taken:  # a flat top (equal votes in adjacent cells) is reported at its centre
        i0, i1, j0, j1 = max(0, i - md), min(nr, i + md + 1), max(0, j - ma), min(nt, j + ma + 1)
        lab, _ = ndimage.label(Hf[i0:i1, j0:j1] == Hf[i, j], structure=np.ones((3, 3), dtype=bool))
        ii, jj = np.nonzero(lab == lab[i - i0, j - j0])
        out.append((float(r[ii + i0].mean()), float(t[jj + j0].mean())))
    return out


def window_neighbours(lines: Sequence[tuple[float, float]], *, drho: float = 2.0, dtheta_deg: float = 1.0,
                      size: int = 5) -> np.ndarray:
    """For each line, whether another line falls inside its ``size x size`` averaging window.

    Two lines share a window when ``|rho_1 - rho_2| <= (size // 2) drho`` and their angles
    differ by at most ``(size // 2) dtheta`` (taking ``(rho, theta + 180) = (-rho, theta)``
    into account): the second line then raises the local average of the first's peak.

    Parameters
    ----------
    lines : sequence of (rho, theta_deg)
        The lines.
    drho, dtheta_deg : float, keyword-only, default 2 and 1
        Resolutions of the Hough plane.
    size : int, keyword-only, default 5
        Side of the averaging window.

    Returns
    -------
    numpy.ndarray of bool, shape (len(lines),)
    """
    k = size // 2
    L = np.asarray(lines, dtype=float).reshape(-1, 2)
    out = np.zeros(len(L), dtype=bool)
    for a in range(len(L)):
        for b in range(len(L)):
            if a == b:
                continue
            (r1, t1), (r2, t2) = L[a], L[b]
            direct = abs(r1 - r2) <= k * drho and abs(t1 - t2) <= k * dtheta_deg
            wrapped = abs(r1 + r2) <= k * drho and abs(abs(t1 - t2) - 180.0) <= k * dtheta_deg
            out[a] |= bool(direct or wrapped)
    return out
