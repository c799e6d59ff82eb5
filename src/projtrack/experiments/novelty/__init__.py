"""Experiments of the KL novelty chapter (Vermeulen & Casasent 1988).

Modules:

- :mod:`~projtrack.experiments.novelty.plots`: Fig. 1 (block diagram of Table 1) and the Figs. 2-3 frame panels (matplotlib).
"""
from __future__ import annotations

from .plots import plot_block_diagram, plot_frame_panels

__all__ = ["plot_block_diagram", "plot_frame_panels"]
