"""Fig. 5: a numerical model of the frequency-multiplexed vector-inner-product processor (Sec. IV).

:func:`optical_vip_schedule` lays out one stage of inner products as (time slot, laser
diode, AO1 cell, detector) events; :func:`optical_vip_stage` simulates the detectors.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_int, as_real, as_rng

from .paper import mu_words

__all__ = ["optical_vip_schedule", "optical_vip_stage"]


def optical_vip_schedule(m: int, T: int, q: int) -> np.ndarray:
    """Time schedule of the Figure 5 processor for one stage (vector :math:`q + 1` to
    :math:`q`).

    Every product ``p_j * t_n`` of a stage is one (time slot, laser diode, AO1 cell,
    detector) event: at each time slot the laser diodes (P1) of the old vector
    elements ``t_n`` are pulsed, AO1 (P2) holds the MVM column ``p``, and the LFM
    chirp in AO2 (P3) steers the product to the detector of the new element. Time
    slot ``s`` handles the products with AO1 cell ``s`` (``p_s``), so each detector
    receives at most one product per slot and accumulates (integrates) over slots.

    Returns an int array with columns ``(slot, diode, ao1_cell, detector)`` where
    diode/detector index the old/new word lists of :func:`mu_words` with bit counts
    ``>= m - q - 1`` / ``>= m - q``.

    Parameters
    ----------
    m : int
        Number of measurements, ``1..20``.
    T : int
        Number of targets, ``>= 3`` (with fewer targets there is no stage).
    q : int
        Stage index as in :func:`beta_paper` (0-based target columns): the vector of
        column ``q + 1`` becomes that of column ``q``, ``1 <= q <= T - 2`` (column
        ``T - 1`` is the starting vector, column 0 is eq. (6)).
    """
    m = as_int(m, "m", minimum=1, maximum=20)
    T = as_int(T, "T", minimum=0)
    q = as_int(q, "q", minimum=0)
    if T < 3:
        raise ValueError(f"T must be >= 3 for a stage of inner products to exist, got {T}")
    if not 1 <= q <= T - 2:
        raise ValueError(f"q must lie in 1..T-2 = 1..{T - 2} (stage from column q + 1 to q), got {q}")
    new_words = mu_words(m, max(0, m - q))
    old_words = mu_words(m, max(0, m - q - 1))
    pos = np.full(2**m, -1, dtype=np.int64)
    pos[old_words] = np.arange(len(old_words))
    rows = [np.column_stack([np.zeros(len(new_words), dtype=np.int64), pos[new_words],
                             np.zeros(len(new_words), dtype=np.int64), np.arange(len(new_words))])]
    for j in range(1, m + 1):
        bit = 1 << (j - 1)
        det = np.flatnonzero(new_words & bit)
        rows.append(np.column_stack([np.full(len(det), j), pos[new_words[det] ^ bit],
                                     np.full(len(det), j), det]))
    return np.vstack(rows)


def optical_vip_stage(vec: np.ndarray, column: np.ndarray, schedule: np.ndarray,
                      n_out: int, *, noise_std: float = 0.0,
                      rng: np.random.Generator | None = None) -> np.ndarray:
    """Simulate Figure 5: space-integrated products time-integrated on the P3 detectors.

    Each schedule row multiplies the laser-diode amplitude ``vec[diode]`` (P1) by the
    AO1 transmittance ``column[cell]`` (P2), and the chirp routes the product to
    ``detector``; detectors integrate over the time slots. With ``noise_std > 0``
    each detector reading gets additive Gaussian noise (analog accuracy), drawn from
    ``rng``.

    Parameters
    ----------
    vec : numpy.ndarray
        The old vector (laser-diode amplitudes at P1).
    column : numpy.ndarray
        The MVM column ``(p_0, ..., p_m)`` written on AO1.
    schedule : numpy.ndarray of int, shape (k, 4)
        From :func:`optical_vip_schedule`.
    n_out : int
        Number of detectors (elements of the new vector).
    noise_std : float, keyword-only, default 0
        Standard deviation of the additive detector noise.
    rng : numpy.random.Generator, keyword-only
        Needed when ``noise_std > 0``.

    Returns
    -------
    numpy.ndarray, shape (n_out,)
        The detector readings: the new vector.
    """
    vec = as_array(vec, "vec", ndim=1)
    column = as_array(column, "column", ndim=1)
    n_out = as_int(n_out, "n_out", minimum=0)
    sch = np.asarray(schedule)
    if sch.ndim != 2 or sch.shape[1] != 4:
        raise ValueError("schedule must be an (n, 4) array of (slot, diode, ao1_cell, detector) "
                         f"rows, got shape {sch.shape}")
    if sch.size and not np.issubdtype(sch.dtype, np.integer):
        raise TypeError(f"schedule must hold integers, got dtype {sch.dtype}")
    schedule = sch.astype(np.int64)
    if np.any(schedule < 0):
        raise ValueError("schedule entries must be >= 0")
    for col, name, size in ((1, "vec", len(vec)), (2, "column", len(column)), (3, "n_out", n_out)):
        if len(schedule) and schedule[:, col].max() >= size:
            what = ("diode", "AO1 cell", "detector")[col - 1]
            raise ValueError(f"schedule uses {what} {schedule[:, col].max()} but {name} has "
                             f"only {size} {'detectors' if col == 3 else 'elements'}")
    noise_std = as_real(noise_std, "noise_std", 0.0)
    out = np.zeros(n_out)
    for s in np.unique(schedule[:, 0]):
        r = schedule[schedule[:, 0] == s]
        # within one slot every detector receives at most one product
        out[r[:, 3]] += vec[r[:, 1]] * column[r[:, 2]]
    if noise_std > 0:
        if rng is None:
            raise ValueError("rng (a numpy.random.Generator) is required when noise_std > 0")
        rng = as_rng(rng)
        out = out + rng.normal(0.0, noise_std, n_out)
    return out
