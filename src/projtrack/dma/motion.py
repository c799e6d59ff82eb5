"""Motion models on prototypes (Sec. 3.2 of Marques et al., 2002).

The global transition matrix ``A`` of eq. (13), made of local blocks ``A_ii`` (eq. (11))
and cross-region blocks ``A_ij`` (eq. (12)), estimated by relative frequencies of
prototype transitions (eq. (10)) and kept as a :mod:`scipy.sparse` matrix
(:func:`estimate_transitions`, smoothed on an optional :func:`neighbor_graph`), the
initial-state probabilities (:func:`estimate_start`), or a chain built from a known
velocity field as in Example 1 (:func:`transitions_from_velocity_field`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_array, as_bool, as_int, as_real

__all__ = ["estimate_transitions", "estimate_start", "neighbor_graph", "transitions_from_velocity_field"]


def _check_sequences(sequences: object, n_states: int) -> list[np.ndarray]:
    if isinstance(sequences, np.ndarray) and sequences.ndim == 1:
        sequences = [sequences]
    try:
        seqs = [np.asarray(s) for s in sequences]  # type: ignore[union-attr]
    except TypeError as exc:
        raise TypeError("sequences must be a list of 1-D int arrays") from exc
    if not seqs:
        raise ValueError("sequences is empty: the motion model needs training sequences")
    for s in seqs:
        if s.ndim != 1 or not (np.issubdtype(s.dtype, np.integer) or s.size == 0):
            raise ValueError("sequences must be 1-D int arrays of state indices")
        if s.size and ((s < 0).any() or (s >= n_states).any()):
            raise ValueError(f"sequences contain states outside [0, {n_states})")
    if sum(s.size for s in seqs) == 0:
        raise ValueError("sequences are all empty")
    return seqs


def estimate_transitions(
    sequences: object,
    n_states: int,
    *,
    alpha: float = 1e-3,
    neighbors: object | None = None,
) -> sp.csr_array:
    """Transition matrix :math:`A` (equation (13)) by relative frequencies, sparse.

    ``a_kl = P(u(t) = u_k | u(t-1) = u_l)`` (eqs. (10)-(12); here stored row ``l``,
    column ``k``, so rows sum to one) is the number of observed ``l -> k`` transitions
    divided by the number of transitions out of ``l``.

    **Smoothing.** A state never left in training would give an all-zero row (and a
    state never seen, an empty one), which breaks retrieval. A pseudo-count ``alpha``
    is added to every self-transition and to every entry of the optional ``neighbors``
    pattern (e.g. :func:`neighbor_graph`) before normalising. With the default
    ``alpha = 1e-3`` and no neighbours, rows seen in training are changed by less than
    ``alpha / count`` and unseen states become absorbing (stay put). The result is
    sparse: only observed transitions, self-loops and neighbour entries are stored.

    Parameters
    ----------
    sequences : list of 1-D int arrays
        Training state (prototype) sequences.
    n_states : int
        Number of states ``S``.
    alpha : float, default 1e-3
        Pseudo-count (> 0).
    neighbors : scipy.sparse matrix or array, shape (S, S), optional
        Pattern of extra allowed transitions (non-zero = allowed).

    Returns
    -------
    scipy.sparse.csr_array, shape (S, S)
        Row-stochastic transition probabilities.
    """
    S = as_int(n_states, "n_states", minimum=1)
    seqs = _check_sequences(sequences, S)
    alpha = as_real(alpha, "alpha", 0, low_open=True)
    src = np.concatenate([s[:-1] for s in seqs]).astype(np.int64)
    dst = np.concatenate([s[1:] for s in seqs]).astype(np.int64)
    C = sp.coo_array((np.ones(src.size), (src, dst)), shape=(S, S)).tocsr()
    C = C + alpha * sp.eye_array(S, format="csr")
    if neighbors is not None:
        if neighbors.shape != (S, S):
            raise ValueError(f"neighbors must have shape ({S}, {S}), got {neighbors.shape}")
        Nb = sp.csr_array(neighbors, dtype=float)
        Nb.data = np.ones_like(Nb.data)
        Nb.eliminate_zeros()
        C = C + alpha * Nb
    C = sp.csr_array(C)
    C.sum_duplicates()
    rows = np.asarray(C.sum(axis=1)).ravel()
    C = sp.csr_array(sp.diags_array(1.0 / rows) @ C)
    C.sort_indices()
    return C


def estimate_start(sequences: object, n_states: int, *, alpha: float = 1.0) -> np.ndarray:
    """Initial-state probabilities: state frequencies of the training sequences plus a
    pseudo-count ``alpha`` per state (so that every state may start a trajectory).

    Parameters
    ----------
    sequences : sequence of array_like of int
        Training state sequences (prototype indices).
    n_states : int
        Number of states.
    alpha : float, keyword-only, default 1
        Pseudo-count per state (> 0).

    Returns
    -------
    numpy.ndarray, shape (n_states,)
        Probabilities summing to 1.
    """
    S = as_int(n_states, "n_states", minimum=1)
    seqs = _check_sequences(sequences, S)
    alpha = as_real(alpha, "alpha", 0, low_open=True)
    counts = np.bincount(np.concatenate(seqs).astype(np.int64), minlength=S) + alpha
    return counts / counts.sum()


def neighbor_graph(points: object, radius: float) -> sp.csr_array:
    """Sparse 0/1 pattern of prototype pairs closer than ``radius`` (self excluded),
    for smoothing in :func:`estimate_transitions`.

    Parameters
    ----------
    points : array_like, shape (K, n)
        The prototypes.
    radius : float
        Distance below which two prototypes are neighbours (> 0).

    Returns
    -------
    scipy.sparse.csr_array, shape (K, K)
    """
    from scipy.spatial import cKDTree

    P = as_array(points, "points", ndim=2)
    radius = as_real(radius, "radius", 0, low_open=True)
    pairs = cKDTree(P).query_pairs(radius, output_type="ndarray")
    S = len(P)
    i = np.concatenate([pairs[:, 0], pairs[:, 1]])
    j = np.concatenate([pairs[:, 1], pairs[:, 0]])
    return sp.csr_array((np.ones(i.size), (i, j)), shape=(S, S))


def transitions_from_velocity_field(
    points: object,
    velocity: object,
    dt: float,
    *,
    n_next: int = 2,
    project: object | None = None,
    exclude_self: bool = False,
    width: float | None = None,
) -> sp.csr_array:
    """Markov chain on prototypes from a known velocity field (Example 1, Figure 6a).

    From each prototype ``u_l`` the point moves to ``p_l = u_l + dt * v(u_l)`` (then
    mapped by ``project``, e.g. back onto the sphere). The allowed transitions go to the
    ``n_next`` prototypes nearest to ``p_l`` (with ``n_next = 2``, "transitions to one
    of two consecutive states" as in Fig. 3), with probabilities proportional to
    ``exp(-d^2 / (2 s^2))``, ``d`` the distance to ``p_l`` and ``s`` the weight width
    (``width``; by default the median nearest-neighbour spacing of the prototypes).

    With ``exclude_self`` the prototype ``u_l`` itself is never a successor (no
    self-loops: the point always moves). ``n_next = 1, exclude_self = True`` gives the
    *deterministic* chain "each centroid to the nearest other centroid along the field"
    (one arrow per centroid).

    Parameters
    ----------
    points : array_like, shape (S, n)
        Prototypes on the manifold.
    velocity : callable
        ``velocity(points) -> (S, n)`` velocity field.
    dt : float
        Time step (> 0).
    n_next : int
        Number of successors per state.
    project : callable, optional
        ``project(points) -> points`` applied to the predicted points.
    exclude_self : bool, default False
        Leave each prototype out of its own successors.
    width : float, optional
        Width ``s`` of the Gaussian weights (> 0); default the median nearest-neighbour
        spacing of ``points``.

    Returns
    -------
    scipy.sparse.csr_array, shape (S, S)
        Row-stochastic transition probabilities.
    """
    from scipy.spatial import cKDTree

    P = as_array(points, "points", ndim=2, finite=False)
    S = len(P)
    k = as_int(n_next, "n_next", minimum=1)
    as_bool(exclude_self, "exclude_self")
    if k > S - int(exclude_self):
        raise ValueError(f"n_next must be <= the number of candidate successors ({S - int(exclude_self)})")
    if not callable(velocity):
        raise TypeError("velocity must be callable: velocity(points) -> array of the same shape")
    dt = as_real(dt, "dt", 0, low_open=True)
    V = np.asarray(velocity(P), dtype=float)
    if V.shape != P.shape or not np.isfinite(V).all():
        raise ValueError(f"velocity(points) must return finite values of shape {P.shape}")
    pred = P + dt * V
    if project is not None:
        pred = np.asarray(project(pred), dtype=float)
    tree = cKDTree(P)
    spacing = float(np.median(tree.query(P, k=2)[0][:, 1])) if width is None else as_real(width, "width", 0,
                                                                                             low_open=True)
    if exclude_self:
        d, idx = tree.query(pred, k=k + 1)
        d, idx = d.reshape(S, k + 1), idx.reshape(S, k + 1)
        keep = idx != np.arange(S)[:, None]
        # drop the point itself if it is among the k + 1 nearest, else the farthest one
        keep[keep.all(axis=1), -1] = False
        d, idx = d[keep].reshape(S, k), idx[keep].reshape(S, k)
    else:
        d, idx = tree.query(pred, k=k)
        d, idx = d.reshape(S, k), idx.reshape(S, k)
    w = np.exp(-0.5 * (d / spacing) ** 2)
    w = np.where(w.sum(axis=1, keepdims=True) > 0, w, 1.0)
    w = w / w.sum(axis=1, keepdims=True)
    A = sp.csr_array((w.ravel(), (np.repeat(np.arange(S), k), idx.ravel())), shape=(S, S))
    A.sum_duplicates()
    A.sort_indices()
    return A
