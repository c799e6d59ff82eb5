"""pytest configuration shared by the unit tests, nbval and the figure-regression test.

It lives at the repository root so that it applies to every pytest run, including
``pytest --nbval book/<folder>`` on a single chapter: nbval's kernels then never write
into the committed ``figures/``.

When pytest runs with ``--nbval``, every notebook kernel inherits
``PROJTRACK_FIGURES_DIR`` pointing to a fresh temporary folder, so nbval's re-execution of
the notebooks regenerates every figure and table there without touching the committed
``figures/``; ``tests/test_figure_regression.py`` then compares the two folders. The
regression test is moved after all notebook items so the comparison sees a complete run.

For the cross-check (``tools/crosscheck.py``), ``PROJTRACK_CROSSCHECK_DIR`` names a folder
that keeps what one configuration produced: the regenerated figures and tables in
``<dir>/figures`` and the text outputs of every notebook cell nbval ran in
``<dir>/outputs.json`` (including cells whose outputs nbval does not compare), so the
report can list every number that moved between configurations.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

ROOT = Path(__file__).resolve().parent

settings.register_profile(
    "projtrack", deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("projtrack")


def pytest_configure(config: pytest.Config) -> None:
    config._projtrack_regen_dir = None  # type: ignore[attr-defined]
    config._projtrack_outputs = {}  # type: ignore[attr-defined]
    if getattr(config.option, "nbval", False):
        keep = os.environ.get("PROJTRACK_CROSSCHECK_DIR")
        if keep:
            regen = Path(keep).resolve() / "figures"
            shutil.rmtree(regen, ignore_errors=True)
            regen.mkdir(parents=True)
        else:
            regen = Path(tempfile.mkdtemp(prefix="projtrack-figures-"))
        os.environ["PROJTRACK_FIGURES_DIR"] = str(regen)
        config._projtrack_regen_dir = regen  # type: ignore[attr-defined]


def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list) -> None:
    last = [it for it in items if it.nodeid.startswith("tests/test_figure_regression.py")]
    first = [it for it in items if it not in last]
    items[:] = first + last


def _text_of(output: dict) -> str:
    if output.get("output_type") == "stream":
        return output.get("text", "")
    data = output.get("data", {})
    return data.get("text/plain", "") if isinstance(data, dict) else ""


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    yield
    outs = getattr(item, "test_outputs", None)
    if call.when == "call" and outs is not None and hasattr(item, "cell_num"):
        nb = Path(str(item.fspath)).resolve()
        try:
            key = nb.relative_to(ROOT).as_posix()
        except ValueError:
            key = nb.as_posix()
        texts = ["".join(t) if isinstance(t, list) else str(t) for t in (_text_of(o) for o in outs)]
        item.config._projtrack_outputs.setdefault(key, {})[str(item.cell_num)] = {
            "checked": bool(item.options.get("check")), "outputs": texts}


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    keep = os.environ.get("PROJTRACK_CROSSCHECK_DIR")
    outputs = getattr(session.config, "_projtrack_outputs", None)
    if keep and outputs:
        path = Path(keep).resolve() / "outputs.json"
        path.write_text(json.dumps(outputs, indent=1, sort_keys=True), encoding="utf-8")


@pytest.fixture(scope="session")
def regenerated_figures(request: pytest.FixtureRequest) -> Path:
    """Folder holding the figures and tables of a fresh execution of every notebook.

    Under ``--nbval`` it is the folder nbval's kernels wrote to. Otherwise the notebooks of
    ``book/_toc.yml`` are executed here (in memory, their files untouched) into a
    temporary folder.
    """
    regen = request.config._projtrack_regen_dir  # type: ignore[attr-defined]
    if regen is not None:
        return regen
    import sys

    sys.path.insert(0, str(ROOT / "tools"))
    import nbformat
    from nbclient import NotebookClient
    from run_notebooks import toc_notebooks

    out = Path(tempfile.mkdtemp(prefix="projtrack-figures-"))
    old = os.environ.get("PROJTRACK_FIGURES_DIR")
    os.environ["PROJTRACK_FIGURES_DIR"] = str(out)
    try:
        for nb_path in toc_notebooks():
            nb = nbformat.read(nb_path, as_version=4)
            NotebookClient(nb, timeout=600, kernel_name="python3",
                           resources={"metadata": {"path": str(nb_path.parent)}}).execute()
    finally:
        if old is None:
            os.environ.pop("PROJTRACK_FIGURES_DIR", None)
        else:
            os.environ["PROJTRACK_FIGURES_DIR"] = old
    return out
