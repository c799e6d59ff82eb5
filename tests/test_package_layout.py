"""The package's layout: module sizes, the stable public names, and the import layers.

The layers themselves are checked by ``lint-imports`` (contracts in ``pyproject.toml``, run by
``make test``); here: every module stays short enough to read as one idea, every name the
topic packages exported before the split into subpackages is still importable from the
same place, and the algorithm packages load without the plotting or table libraries. The API
reference's pages are checked in ``tests/test_api_pages.py``.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "projtrack"
MAX_LINES = 600
PUBLIC_NAMES = json.loads((Path(__file__).with_name("public_names.json")).read_text())
TOPICS = ["ellipsoids", "dma", "correlators", "hough", "jpda", "neuralnet", "novelty"]


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_module_is_short(path):
    n = len(path.read_text().splitlines())
    assert n <= MAX_LINES, f"{path.relative_to(ROOT)} has {n} lines (at most {MAX_LINES}): split it by idea"


@pytest.mark.parametrize("topic", sorted(PUBLIC_NAMES))
def test_public_names_stay_importable(topic):
    entry = PUBLIC_NAMES[topic]
    mod = importlib.import_module(entry["module"])
    missing = [n for n in entry["names"] if not hasattr(mod, n)]
    assert not missing, f"{entry['module']} no longer exports {missing}"
    assert set(entry["names"]) <= set(mod.__all__), "public names must stay listed in __all__"


@pytest.mark.parametrize("topic", TOPICS)
def test_algorithms_load_without_plotting_or_tables(topic):
    code = (f"import sys; import projtrack.{topic}; "
            "bad = sorted(m for m in ('matplotlib', 'pandas', 'projtrack.scenes', 'projtrack.experiments') "
            "if m in sys.modules); print(','.join(bad))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"import projtrack.{topic} loads {out.stdout.strip()}"
