"""Table 1 of Vermeulen & Casasent (the adaptive recursive SVD) as data: its steps and flow.

Fig. 1, the block diagram, is drawn from these two tuples (by
:func:`projtrack.experiments.novelty.plot_block_diagram`).
"""
from __future__ import annotations

__all__ = ["TABLE1_STEPS", "TABLE1_FLOW"]

#: The steps of Table 1 (the adaptive recursive SVD algorithm), as implemented by
#: :meth:`NoveltyFilter.partial_fit`; Fig. 1 (the block diagram) is drawn from this list.
TABLE1_STEPS: tuple[tuple[int, str], ...] = (
    (1, "Initialize iteration counter i = 1 and sequence counter j = 1"),
    (2, "Initialize rank estimate K_1 = 1"),
    (3, "Read first image x_1: first eigenimage, eigenvalue |x_1|^2"),
    (4, "Increment iteration counter i"),
    (5, "Increment rank estimate K_i = K_{i-1} + 1"),
    (6, "Increment j, read next image x_j"),
    (7, "Form K_i x K_i VIP matrix V_i (Eqs. 4-5)"),
    (8, "Novel? n_i > T_d (Eqs. 6-8); if not, go to step 6"),
    (9, "Eigen-decompose V_i, new eigenimages (Eq. 9)"),
    (10, "Fractions F (Eq. 10), rank estimate (Eq. 11), discard excess"),
    (11, "More images? go to step 4"),
)

#: The control flow of Table 1: (from step, to step, condition); step 0 is the end.
TABLE1_FLOW: tuple[tuple[int, int, str], ...] = (
    (1, 2, ""), (2, 3, ""), (3, 4, ""), (4, 5, ""), (5, 6, ""), (6, 7, ""), (7, 8, ""),
    (8, 6, "not novel"), (8, 9, "novel"), (9, 10, ""), (10, 11, ""),
    (11, 4, "more images"), (11, 0, "done"),
)
