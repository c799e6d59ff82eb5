"""The weights ``A1``-``A4`` of eq. (8) and the paper's values of them and of the offset."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from projtrack._validation import as_real

__all__ = ["Coefficients", "PAPER_COEFFICIENTS", "PAPER_OFFSET"]


@dataclass(frozen=True)
class Coefficients:
    r"""The positive weights :math:`A_1, \dots, A_4` of equation (8).

    Parameters
    ----------
    A1, A2, A3, A4 : float, default 15, 15, 15 and 1.8
        The weights of the four terms of eq. (8) (the paper's values), each >= 0.
    """

    A1: float = 15.0
    A2: float = 15.0
    A3: float = 15.0
    A4: float = 1.8

    def __post_init__(self) -> None:
        for name in ("A1", "A2", "A3", "A4"):
            as_real(getattr(self, name), f"coefficient {name}", 0)


#: Sec. VI: A1 = A2 = A3 = 15, A4 = 1.8.
PAPER_COEFFICIENTS = Coefficients(15.0, 15.0, 15.0, 1.8)
#: Sec. VI: the threshold 2 A3 N_T is raised by 0.035.
PAPER_OFFSET = 0.035


def _as_coefficients(coefficients: object) -> Coefficients:
    if coefficients is None:
        return PAPER_COEFFICIENTS
    if isinstance(coefficients, Coefficients):
        return coefficients
    if isinstance(coefficients, (tuple, list, np.ndarray)) and len(coefficients) == 4:
        return Coefficients(*[float(c) for c in coefficients])
    raise TypeError("coefficients must be a Coefficients or a sequence (A1, A2, A3, A4)")
