"""The project's copy of the reproduction inventory.

``projtrack/data/inventory.csv`` lists every figure, table, algorithm and claim of the
three source documents that the book reproduces, with the parameters the papers give
and the values they report. It is a copy made once from the project's planning notes;
the build and the tests read only this copy.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

__all__ = ["InventoryItem", "load_inventory", "inventory_ids", "PARTS"]

#: Inventory-id prefix -> (book part, chapter title), in book order.
PARTS: dict[str, tuple[str, str]] = {
    "KVW": ("Part I", "Reconstructing ellipsoids from projections (Karl, Verghese & Willsky 1994)"),
    "DMA": ("Part II", "Trajectory estimation on manifolds (Marques et al. 2002)"),
    "PC": ("Part III", "Optical projection correlations (Casasent & Song)"),
    "HT": ("Part III", "Hough-transform track initiator (Casasent & Slaski)"),
    "JPDA": ("Part III", "Fast JPDA (Fisher & Casasent)"),
    "NN": ("Part III", "Cubic-energy neural net (Barnard & Casasent)"),
    "KL": ("Part III", "KL novelty detector and filter (Vermeulen & Casasent)"),
}


@dataclass(frozen=True)
class InventoryItem:
    """One row of the inventory."""

    id: str
    source: str
    section: str
    kind: str
    item: str
    parameters: str
    paper_reports: str

    @property
    def prefix(self) -> str:
        """The id's prefix (``"JPDA"`` for ``"JPDA-T1"``)."""
        return self.id.split("-", 1)[0]


@lru_cache(maxsize=1)
def load_inventory() -> tuple[InventoryItem, ...]:
    """Return the inventory rows in file order."""
    text = resources.files("projtrack").joinpath("data/inventory.csv").read_text(encoding="utf-8")
    rows = csv.DictReader(text.splitlines())
    return tuple(InventoryItem(**{k: (v or "") for k, v in row.items()}) for row in rows)


def inventory_ids() -> tuple[str, ...]:
    """Return every inventory id, in file order."""
    return tuple(item.id for item in load_inventory())
