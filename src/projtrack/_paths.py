"""Where the project's outputs live (internal helper)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["project_root", "figures_root"]

_ENV_VAR = "PROJTRACK_FIGURES_DIR"


def _looks_like_root(path: Path) -> bool:
    return (path / "pyproject.toml").is_file() and (path / "book").is_dir()


def project_root() -> Path:
    """Return the repository root (the folder holding ``pyproject.toml`` and ``book/``).

    The package is normally installed in editable mode from the repository, so the
    root is found from the package's own location; failing that, from the current
    working directory and its parents.

    Raises
    ------
    FileNotFoundError
        If no such folder can be found.
    """
    here = Path(__file__).resolve()
    for candidate in [*here.parents, Path.cwd().resolve(), *Path.cwd().resolve().parents]:
        if _looks_like_root(candidate):
            return candidate
    raise FileNotFoundError(
        "cannot find the projtrack repository root (a folder with pyproject.toml and book/); "
        f"set {_ENV_VAR} to choose where figures are written"
    )


def figures_root() -> Path:
    """Return the folder figures and tables are written to.

    ``$PROJTRACK_FIGURES_DIR`` when set and non-empty, otherwise ``figures/`` at the
    repository root.
    """
    env = os.environ.get(_ENV_VAR, "").strip()
    if env:
        return Path(env).expanduser().resolve()
    return project_root() / "figures"
