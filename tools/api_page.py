#!/usr/bin/env python3
"""Write book/api.md: the package's modules listed under their layers.

Usage: python tools/api_page.py [--check]

Each topic package is documented once with its public names (its ``__all__``, so a name is
documented where users import it: ``projtrack.jpda.beta``), followed by its modules, each with
its own one-paragraph docstring (``:no-members:``), so the page shows what lives where without
documenting a function twice. Private modules (a leading underscore) are left out, except
``projtrack._validation``, which contributors use. ``--check`` exits 1 when the committed page
differs from the generated one (``tests/test_package_layout.py`` runs it).
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "projtrack"
PAGE = ROOT / "book" / "api.md"
TOPICS = [("Part I: ellipsoids", "ellipsoids"), ("Part II: trajectory estimation on manifolds", "dma"),
          ("Part III: projection correlations", "correlators"), ("Part III: Hough track initiator", "hough"),
          ("Part III: fast JPDA", "jpda"), ("Part III: cubic-energy neural net", "neuralnet"),
          ("Part III: adaptive KL novelty filter", "novelty")]


def _modules(pkg: Path, dotted: str) -> list[str]:
    return [f"{dotted}.{p.stem}" for p in sorted(pkg.glob("*.py"))
            if not p.stem.startswith("_")]


def _block(lines: list[str]) -> list[str]:
    return ["```{eval-rst}", *lines, "```", ""]


def _package(dotted: str, pkg: Path) -> list[str]:
    out = [f".. automodule:: {dotted}", ""]
    for mod in _modules(pkg, dotted):
        out += [f".. automodule:: {mod}", "   :no-members:", ""]
    return _block(out[:-1])


def render() -> str:
    md = ["# API reference", "",
          "The shared package `projtrack`, generated from its docstrings, layer by layer (the",
          "README's *Layout* says what goes in each layer and the one rule of each). A topic",
          "package documents its public names where users import them (`projtrack.jpda.beta`);",
          "below it, each of its modules with what it holds.", "",
          "```{eval-rst}", ".. automodule:: projtrack", "   :no-members:", "```", ""]
    md += ["## Algorithms", ""]
    for title, topic in TOPICS:
        md += [f"### {title}", "", *_package(f"projtrack.{topic}", SRC / topic)]
    md += ["## Synthetic scenes", "",
           *_block([".. automodule:: projtrack.scenes", "   :no-members:", "",
                    *[line for m in _modules(SRC / "scenes", "projtrack.scenes")
                      for line in (f".. automodule:: {m}", "")][:-1]])]
    md += ["## Experiments: the papers' studies", "",
           *_block([".. automodule:: projtrack.experiments", "   :no-members:"])]
    for title, topic in TOPICS:
        pkg = SRC / "experiments" / topic
        if pkg.is_dir():
            md += [f"### {title}", "", *_package(f"projtrack.experiments.{topic}", pkg)]
    md += ["## Book helpers", "", *_block([".. automodule:: projtrack.figures", "",
                                           ".. automodule:: projtrack.scorecard", "",
                                           ".. automodule:: projtrack.inventory"])]
    md += ["## Shared utilities", "", *_block([".. automodule:: projtrack._validation", "",
                                               ".. automodule:: projtrack.montecarlo", "",
                                               ".. automodule:: projtrack.stable", "",
                                               ".. automodule:: projtrack.tolerance"])]
    return "\n".join(md).rstrip() + "\n"


def main(argv: list[str]) -> int:
    text = render()
    if "--check" in argv:
        if PAGE.read_text() != text:
            print(f"{PAGE.relative_to(ROOT)} is out of date: run python tools/api_page.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
