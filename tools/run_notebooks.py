"""Execute notebooks top to bottom in a fresh kernel and store their outputs in place.

Usage: ``python tools/run_notebooks.py [NOTEBOOK ...]`` (default: every notebook listed
in ``book/_toc.yml``). Each notebook runs with its own folder as working directory, in
a fresh ``python3`` kernel of the current environment, with a per-cell timeout. The
first error stops the run with a non-zero exit status and the notebook is not written.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError, CellTimeoutError
from jupyter_client.manager import KernelManager

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"


def toc_notebooks() -> list[Path]:
    """Return the notebooks of ``book/_toc.yml`` in book order."""
    import yaml

    toc = yaml.safe_load((BOOK / "_toc.yml").read_text())
    found: list[Path] = []

    def walk(node: object) -> None:
        if isinstance(node, dict):
            f = node.get("file") or node.get("root")
            if isinstance(f, str):
                p = BOOK / (f if f.endswith(".ipynb") else f + ".ipynb")
                if p.is_file():
                    found.append(p)
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)

    walk(toc)
    return found


#: Pages that read the committed scorecards of every chapter: run after the chapters.
SUMMARIES = ("intro.ipynb", "summary.ipynb")


def run_order(notebooks: list[Path]) -> list[Path]:
    """The notebooks in toc order, with the pages that summarize the scorecards last."""
    return [p for p in notebooks if p.name not in SUMMARIES] + [p for p in notebooks if p.name in SUMMARIES]


def execute(path: Path, timeout: int) -> float:
    nb = nbformat.read(path, as_version=4)
    with tempfile.TemporaryDirectory(prefix="projtrack-kernel-") as sockets:
        # A local kernel talks over Unix sockets: no TCP ports, no transport warning.
        km = KernelManager(kernel_name="python3", transport="ipc", ip=os.path.join(sockets, "kernel"))
        client = NotebookClient(
            nb, km=km, timeout=timeout, kernel_name="python3", allow_errors=False,
            resources={"metadata": {"path": str(path.parent)}},
        )
        start = time.perf_counter()
        client.execute()
    elapsed = time.perf_counter() - start
    # Drop kernel/execution metadata that changes from run to run.
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
    nbformat.write(nb, path)
    return elapsed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("notebooks", nargs="*", type=Path)
    parser.add_argument("--timeout", type=int, default=int(os.environ.get("PROJTRACK_CELL_TIMEOUT", "600")),
                        help="per-cell timeout in seconds (default 600)")
    args = parser.parse_args(argv)
    notebooks = run_order([p.resolve() for p in args.notebooks] or toc_notebooks())
    if not notebooks:
        print("run_notebooks: no notebooks to execute", file=sys.stderr)
        return 1
    total = 0.0
    for i, path in enumerate(notebooks, 1):
        rel = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
        print(f"[{i}/{len(notebooks)}] executing {rel} ...", flush=True)
        try:
            elapsed = execute(path, args.timeout)
        except (CellExecutionError, CellTimeoutError) as exc:
            print(f"\nFAILED: {rel}\n{exc}", file=sys.stderr)
            return 1
        total += elapsed
        print(f"      done in {elapsed:.1f} s", flush=True)
    print(f"executed {len(notebooks)} notebooks in {total:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
