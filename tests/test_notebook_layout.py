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
    ("table = study(trials, noise_levels=LEVELS, readings=READINGS, seed=SEED, chunk=25)  # x\n", "wide"),
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


# -- how a page reads (CONTRIBUTING, "How a page reads") ---------------------------------------------

import json  # noqa: E402

#: Visible code cells hold at most this many non-blank lines; longer ones are collapsed or move
#: to projtrack.experiments.
MAX_VISIBLE_CODE_LINES = 8
#: Printed lines wider than this run off the column.
MAX_PRINTED_WIDTH = 90
_MARKER = "# NBVAL_IGNORE_OUTPUT"


def _cells(notebook):
    return json.loads(notebook.read_text(encoding="utf-8"))["cells"]


def _hidden_input(cell) -> bool:
    return any(t in cell.get("metadata", {}).get("tags", []) for t in tag_cells.HIDING)


def _content_pages():
    return [p for p in tag_cells.toc_notebooks() if p.name != "summary.ipynb"]


def _paper_pages():
    """The pages that judge a paper's claims (the landing page answers for the whole book)."""
    return [p for p in _content_pages() if p.relative_to(ROOT / "book").as_posix() != "intro.ipynb"]


_IDS = dict(ids=lambda p: p.relative_to(ROOT / "book").as_posix())


@pytest.mark.parametrize("notebook", tag_cells.toc_notebooks(), **_IDS)
def test_cells_left_out_of_nbval_say_why(notebook):
    """A cell whose output nbval does not compare carries '# NBVAL_IGNORE_OUTPUT' and, on the
    next line, a comment saying why (which file compares its numbers, or why they vary)."""
    bad = []
    for i, cell in enumerate(_cells(notebook)):
        if cell["cell_type"] != "code":
            continue
        tags = cell.get("metadata", {}).get("tags", [])
        if "nbval-ignore-output" in tags or "nbval-skip" in tags:
            bad.append(f"cell {i}: use the '{_MARKER}' comment with a reason, not a tag")
        lines = [ln.strip() for ln in "".join(cell["source"]).splitlines()]
        if _MARKER in lines:
            nxt = lines[lines.index(_MARKER) + 1] if lines.index(_MARKER) + 1 < len(lines) else ""
            if not (nxt.startswith("#") and len(nxt.lstrip("# ").split()) >= 4):
                bad.append(f"cell {i}: '{_MARKER}' without a reason comment on the next line")
    assert not bad, "; ".join(bad)


@pytest.mark.parametrize("notebook", _content_pages(), **_IDS)
def test_visible_code_is_short_and_outputs_fit_the_column(notebook):
    bad = []
    for i, cell in enumerate(_cells(notebook)):
        if cell["cell_type"] != "code":
            continue
        tags = cell.get("metadata", {}).get("tags", [])
        n = sum(1 for ln in "".join(cell["source"]).splitlines() if ln.strip())
        if not _hidden_input(cell) and n > MAX_VISIBLE_CODE_LINES:
            bad.append(f"cell {i}: {n} visible code lines (at most {MAX_VISIBLE_CODE_LINES}: collapse it "
                       "with hide-input or move the code to projtrack.experiments)")
        if "hide-output" in tags or "remove-output" in tags:
            continue
        for o in cell.get("outputs", []):
            if o.get("output_type") == "stream":
                wide = [ln for ln in "".join(o.get("text", "")).splitlines() if len(ln) > MAX_PRINTED_WIDTH]
                if wide:
                    bad.append(f"cell {i}: {len(wide)} printed lines wider than {MAX_PRINTED_WIDTH} characters "
                               f"(e.g. {wide[0][:60]!r}...): show a table or glue the numbers into the text")
    assert not bad, "; ".join(bad)


@pytest.mark.parametrize("notebook", _paper_pages(), **_IDS)
def test_page_opens_with_the_claim_and_the_result_at_a_glance(notebook):
    """The first cell is the title and the paper's claim, and shows the page's result at a glance
    (glued by Scorecard.publish); the last code cell publishes the scorecard."""
    cells = _cells(notebook)
    first = "".join(cells[0]["source"])
    assert cells[0]["cell_type"] == "markdown" and first.lstrip().startswith("# "), "the first cell is the title"
    assert "{glue:} glance" in first or "{glue} glance" in first, \
        "the first cell shows the result at a glance ({glue:} glance, glued by card.publish())"
    code = [c for c in cells if c["cell_type"] == "code"]
    assert code and ".publish(" in "".join(code[-1]["source"]), "the last code cell calls card.publish(...)"
