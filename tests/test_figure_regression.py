"""Figure regression: a fresh run of the notebooks must regenerate the committed figures/.

Every PNG is compared with :func:`matplotlib.testing.compare.compare_images` at an RMS
tolerance of :data:`TOL` (on the 0-255 scale); every CSV is compared cell by cell: text and
integers exactly, other numbers within :data:`CSV_RTOL` relative or :data:`CSV_ATOL` absolute
(so a table does not fail on the last bits of another CPU's BLAS kernel, while any change a
reader could see in a printed digit still fails). A figure or table that is missing from the fresh run,
or one the fresh run makes that is not committed, fails. Outputs whose stem ends in
``.timing`` depend on wall-clock time: only their presence is checked.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import pytest
from matplotlib.testing.compare import compare_images

ROOT = Path(__file__).resolve().parents[1]
COMMITTED = ROOT / "figures"
TOL = 1.0
#: Relative and absolute tolerances for non-integer numbers in the committed CSVs.
CSV_RTOL = 1e-6
CSV_ATOL = 1e-9
_INT = re.compile(r"^[+-]?\d+$")


def _outputs(folder: Path) -> set[str]:
    return {
        p.relative_to(folder).as_posix()
        for p in folder.rglob("*")
        if p.suffix in (".png", ".csv") and "-failed-diff" not in p.name
    }


def _is_timing(rel: str) -> bool:
    return Path(rel).stem.endswith(".timing")


def _cells_equal(a: str, b: str) -> bool:
    if a == b:
        return True
    if _INT.match(a) or _INT.match(b):
        return False  # integers (counts, indices) must be equal as text
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return math.isclose(x, y, rel_tol=CSV_RTOL, abs_tol=CSV_ATOL) or (math.isnan(x) and math.isnan(y))


def _csv_differences(expected: Path, actual: Path) -> list[str]:
    with expected.open(newline="") as fe, actual.open(newline="") as fa:
        e_rows, a_rows = list(csv.reader(fe)), list(csv.reader(fa))
    if len(e_rows) != len(a_rows):
        return [f"{len(a_rows)} rows instead of {len(e_rows)}"]
    diffs = []
    for i, (er, ar) in enumerate(zip(e_rows, a_rows)):
        if len(er) != len(ar) or not all(_cells_equal(x, y) for x, y in zip(er, ar)):
            diffs.append(f"row {i}: {ar} instead of {er}")
    return diffs


def test_same_set_of_figures_and_tables(regenerated_figures: Path) -> None:
    committed, fresh = _outputs(COMMITTED), _outputs(regenerated_figures)
    assert fresh, "the fresh run wrote no figure or table at all"
    missing, extra = sorted(committed - fresh), sorted(fresh - committed)
    assert not missing and not extra, (
        f"figures/ is out of date (run `make figures`).\n"
        f"committed but not regenerated: {missing}\nregenerated but not committed: {extra}"
    )


def test_figures_and_tables_match(regenerated_figures: Path) -> None:
    problems = []
    for rel in sorted(_outputs(COMMITTED) & _outputs(regenerated_figures)):
        if _is_timing(rel):
            continue
        expected, actual = COMMITTED / rel, regenerated_figures / rel
        if rel.endswith(".png"):
            result = compare_images(str(expected), str(actual), tol=TOL)
            if result is not None:
                problems.append(f"{rel}: {result}")
        else:
            diffs = _csv_differences(expected, actual)
            if diffs:
                problems.append(f"{rel}: " + "; ".join(diffs[:3]))
    assert not problems, "regenerated outputs differ from figures/:\n" + "\n".join(problems)
