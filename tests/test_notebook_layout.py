"""The book reads like a paper: set-up, helper, long figure-making and scorecard cells are
collapsed (``hide-input``) on every page, analysis cells stay visible (tools/tag_cells.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import tag_cells  # noqa: E402


@pytest.mark.parametrize(("source", "expected"), [
    ("import numpy as np\nfrom projtrack import figures\n", "setup"),
    ("import numpy as np\ncard = Scorecard('kvw', 'x.ipynb')\nrng = np.random.default_rng(1)\nN = 20\n", "setup"),
    ("def f(x):\n    return x + 1\n\nclass A:\n    pass\n", "helper"),
    ("card.add('KVW-F1', 'c', 'p', 'r', 'reproduced')\ncard.add('KVW-F2', 'c', 'p', 'r', 'qualitative')\ncard.show()", "scorecard"),
    ("fig, ax = plt.subplots()\n" + "ax.plot([1, 2])\n" * 14 + "figures.save(fig, 'kvw/x')\n", "figure"),
    ("fig, ax = plt.subplots()\nax.plot([1, 2])\n", None),          # a short figure cell stays visible
    ("res = run(trials)\n" + "err = np.median(res) + 1\n" * 14 + "fig, ax = plt.subplots()\nax.plot(res)\n", None),
    # a long cell that mostly computes (a study ending with its plot) stays visible
    ("x = np.linalg.solve(A, b)\nprint(x)\n", None),                  # analysis stays visible
    ("err = run(trials)\nimport numpy as np\n", None),                # does not start with imports
    ("%matplotlib inline\nimport numpy as np\n", "setup"),            # magics are ignored
    ("def broken(:\n", None),
    ("", None),
])
def test_kind(source, expected):
    assert tag_cells.kind(source) == expected


def test_kind_rejects_non_text():
    with pytest.raises(TypeError, match="source must be a str"):
        tag_cells.kind(None)


def test_tag_is_idempotent_and_touches_only_metadata(tmp_path):
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("import numpy as np\n"), nbformat.v4.new_code_cell("x = 1 + np.pi\nprint(x)")]
    nb.cells[1].outputs = [nbformat.v4.new_output("stream", text="4.14\n")]
    path = tmp_path / "nb.ipynb"
    nbformat.write(nb, path)
    assert tag_cells.tag(path) == 1
    assert tag_cells.tag(path) == 0
    again = nbformat.read(path, as_version=4)
    assert again.cells[0].metadata["tags"] == ["hide-input"]
    assert "tags" not in again.cells[1].metadata
    assert [c.source for c in again.cells] == [c.source for c in nb.cells]
    assert again.cells[1].outputs == nb.cells[1].outputs


@pytest.mark.parametrize("notebook", tag_cells.toc_notebooks(), ids=lambda p: p.relative_to(ROOT / "book").as_posix())
def test_book_pages_collapse_setup_cells(notebook):
    todo = tag_cells.to_collapse(notebook)
    assert not todo, (f"{len(todo)} cells should be collapsed (run `python tools/tag_cells.py`): "
                      + ", ".join(f"cell {i} ({reason})" for i, _, reason in todo))
