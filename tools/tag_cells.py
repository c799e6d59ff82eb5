"""Collapse the set-up, helper, figure-making and scorecard cells of the book's notebooks.

A page of the book should read like the paper it reproduces: the claim, the figures, the
analysis that matters and the scorecard, with the code that only sets things up one click
away. This script gives such cells the MyST-NB tag ``hide-input`` (the input is collapsed
behind a toggle, the output stays visible). Only cell metadata changes: sources, outputs and
cell ids are untouched, so stored outputs stay valid.

A code cell is collapsed when :func:`kind` classifies it as

``setup``
    a cell that starts with imports and whose statements are mostly imports, constants,
    style calls, the page's ``Scorecard``/random generator and function definitions (the
    first cells of a page);
``helper``
    only function or class definitions (with constants);
``figure``
    a cell that draws a figure (``plt.subplots``/``plt.figure``/``figures.save``), is
    longer than :data:`LONG` lines and mostly draws (:data:`DRAWING_SHARE` of its lines):
    the figure is what the reader needs, not its styling;
``scorecard``
    a cell whose statements are mostly calls on the page's scorecard (``card.add(...)``);
``wide``
    a cell with a line longer than :data:`WIDE` characters, which would not fit the
    book's column as visible code.

Cells already tagged ``remove-input``, ``hide-input`` or ``hide-cell`` are left alone.

Usage::

    python tools/tag_cells.py            # tag every notebook of book/_toc.yml in place
    python tools/tag_cells.py --check    # exit 1 listing cells that should be collapsed
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from run_notebooks import toc_notebooks  # noqa: E402

#: Figure-making cells longer than this many non-blank lines are collapsed.
LONG = 12
#: ... and when at least this share of their lines draw (use ``ax``, ``fig``, ``plt``):
#: a long cell that mostly computes (a Monte Carlo study that ends with its plot) stays visible.
DRAWING_SHARE = 0.5
_DRAWING = re.compile(r"\b(ax\w*|fig\w*|plt|figures)\b")
#: Tags that already hide a cell's input.
#: The longest code line shown as visible code (longer ones would not fit the column).
WIDE = 76

HIDING = ("hide-input", "remove-input", "hide-cell", "remove-cell")
_STYLE_CALLS = ("apply_style", "set_printoptions", "filterwarnings", "simplefilter", "seed", "threadpool_limits")
#: Calls whose result may be assigned in a set-up cell (a scorecard, a random generator).
_SETUP_CALLS = ("Scorecard", "default_rng", "Path", "project_root")


def _call_name(call: ast.AST) -> str:
    func = call.func if isinstance(call, ast.Call) else None
    if isinstance(func, ast.Attribute):
        return func.attr
    return getattr(func, "id", "")


def _on_card(node: ast.AST) -> bool:
    """A statement ``card.add(...)``, ``card.show()`` or ``x = card.something(...)``."""
    value = node.value if isinstance(node, (ast.Expr, ast.Assign)) else None
    if not isinstance(value, ast.Call) or not isinstance(value.func, ast.Attribute):
        return False
    owner = value.func.value
    return isinstance(owner, ast.Name) and owner.id.lower().endswith("card")


def _is_constant(node: ast.AST) -> bool:
    """An assignment whose value is built from literals, names and attribute lookups only."""
    if not isinstance(node, (ast.Assign, ast.AnnAssign)):
        return False
    value = node.value
    if value is None:
        return True
    if isinstance(value, ast.Call) and _call_name(value) in _SETUP_CALLS:
        return True
    allowed = (ast.Constant, ast.Name, ast.Attribute, ast.Tuple, ast.List, ast.Dict, ast.Set,
               ast.Load, ast.UnaryOp, ast.USub, ast.UAdd, ast.BinOp, ast.operator, ast.keyword)
    return all(isinstance(n, allowed) for n in ast.walk(value))


def _is_style_call(node: ast.AST) -> bool:
    if not (isinstance(node, ast.Expr) and isinstance(node.value, ast.Call)):
        return False
    func = node.value.func
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
    return name in _STYLE_CALLS


def kind(source: str) -> str | None:
    """Classify one code cell's source: ``setup``, ``helper``, ``figure``, ``scorecard``, ``wide`` or None.

    Parameters
    ----------
    source : str
        The cell's Python source (IPython magics are ignored).

    Returns
    -------
    str or None
        The reason to collapse the cell (``setup``, ``helper``, ``figure``, ``scorecard`` or
        ``wide``), or ``None`` for an analysis cell that stays visible.
    """
    if not isinstance(source, str):
        raise TypeError(f"source must be a str, got {type(source).__name__}")
    code = "\n".join(line for line in source.splitlines() if not line.lstrip().startswith(("%", "!")))
    try:
        tree = ast.parse(code)
    except SyntaxError:
        return None
    body = tree.body
    if not body:
        return None
    if sum(_on_card(n) for n in body) * 2 > len(body):
        return "scorecard"
    imports = [n for n in body if isinstance(n, (ast.Import, ast.ImportFrom))]
    defs = [n for n in body if isinstance(n, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef))]
    rest = [n for n in body if n not in imports and n not in defs
            and not _is_constant(n) and not _is_style_call(n)
            and not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
    if imports and isinstance(body[0], (ast.Import, ast.ImportFrom)) and len(rest) * 2 < len(body):
        return "setup"
    if not rest and defs:
        return "helper"
    lines = [line for line in code.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    draws = any(s in code for s in ("plt.subplots(", "plt.figure(", "figures.save(", "fig.add_subplot("))
    drawing = sum(bool(_DRAWING.search(line)) for line in lines)
    if draws and len(lines) > LONG and drawing >= DRAWING_SHARE * len(lines):
        return "figure"
    if max(len(line) for line in source.splitlines()) > WIDE:
        return "wide"
    return None


def to_collapse(path: Path) -> list[tuple[int, str, str]]:
    """Return ``(cell index, cell id, reason)`` for the cells of ``path`` that should be collapsed."""
    nb = nbformat.read(path, as_version=4)
    out = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code" or any(t in HIDING for t in cell.metadata.get("tags", [])):
            continue
        reason = kind(cell.source)
        if reason:
            out.append((i, cell.get("id", ""), reason))
    return out


def tag(path: Path) -> int:
    """Tag the cells of :func:`to_collapse` with ``hide-input`` in place; return how many."""
    todo = {i for i, _, _ in to_collapse(path)}
    if not todo:
        return 0
    nb = nbformat.read(path, as_version=4)
    for i in todo:
        tags = list(nb.cells[i].metadata.get("tags", []))
        nb.cells[i].metadata["tags"] = [*tags, "hide-input"]
    nbformat.write(nb, path)
    return len(todo)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("notebooks", nargs="*", type=Path, help="default: every notebook of book/_toc.yml")
    parser.add_argument("--check", action="store_true", help="list cells to collapse, change nothing")
    args = parser.parse_args(argv)
    paths = args.notebooks or toc_notebooks()
    bad = 0
    for p in paths:
        if args.check:
            for i, cid, reason in to_collapse(p):
                print(f"{p}: cell {i} ({cid}) is a {reason} cell without hide-input")
                bad += 1
        else:
            n = tag(p)
            if n:
                print(f"{p}: {n} cells collapsed")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
