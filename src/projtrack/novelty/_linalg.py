"""Small linear-algebra helpers shared by the batch and recursive KL routes."""
from __future__ import annotations

import numpy as np


def _sign_fix(images: np.ndarray) -> np.ndarray:
    """Deterministic sign: each eigenimage (row) has a non-negative pixel sum."""
    s = images.sum(axis=1)
    flip = np.where(s < 0, -1.0, 1.0)
    return images * flip[:, None]


def _eigh_desc(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (descending) and eigenvectors (columns) of a small symmetric matrix."""
    g, th = np.linalg.eigh((v + v.T) / 2.0)
    return g[::-1], th[:, ::-1]

