"""numba, optional: whether the compiled kernels run, and the switch that turns them off.

The package's two compiled kernels (:mod:`projtrack.hough._kernel`'s voting and
:mod:`projtrack.jpda._kernel`'s forward-backward sweep) each have a numpy path with the
same results. They use numba when it is importable and ``$PROJTRACK_NO_NUMBA`` is not
``1``; numba is imported only when a kernel is first compiled (importing it takes about a
second).
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["HAVE_NUMBA", "import_numba", "switched_on", "numpy_only"]

#: Whether numba can be imported here.
HAVE_NUMBA = importlib.util.find_spec("numba") is not None
_numba: Any = None


def import_numba() -> Any:
    """The numba module, imported on first use."""
    global _numba
    if _numba is None:
        import numba

        _numba = numba
    return _numba


def switched_on() -> bool:
    """False when ``$PROJTRACK_NO_NUMBA`` is ``1`` (the numpy paths are asked for)."""
    return os.environ.get("PROJTRACK_NO_NUMBA", "") != "1"


@contextmanager
def numpy_only() -> Iterator[None]:
    """Run the numpy paths inside the block (``PROJTRACK_NO_NUMBA=1``), e.g. to time them."""
    old = os.environ.get("PROJTRACK_NO_NUMBA")
    os.environ["PROJTRACK_NO_NUMBA"] = "1"
    try:
        yield
    finally:
        if old is None:
            del os.environ["PROJTRACK_NO_NUMBA"]
        else:
            os.environ["PROJTRACK_NO_NUMBA"] = old
