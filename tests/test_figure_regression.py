"""Figure regression: a fresh run of the notebooks must regenerate the committed figures/.

Every PNG is compared with :func:`matplotlib.testing.compare.compare_images` at an RMS
tolerance of :data:`TOL` (on the 0-255 scale); every CSV is compared cell by cell under the
tolerances declared where the table was made, which :func:`projtrack.figures.save_table` (and
:meth:`projtrack.scorecard.Scorecard.save`) write beside it in ``<name>.tolerance.json``
(:mod:`projtrack.tolerance`: integers and text exactly, numerical and statistical numbers
within their tolerance). The manifests themselves must equal the committed ones, so a
tolerance cannot change without a commit that shows it. A figure or table that is missing
from the fresh run, or one the fresh run makes that is not committed, fails. Outputs whose
stem ends in ``.timing`` depend on wall-clock time: only their presence is checked.
"""

from __future__ import annotations

import csv
from pathlib import Path

from matplotlib.testing.compare import compare_images

from projtrack.tolerance import MANIFEST_SUFFIX, read_manifest, table_differences

ROOT = Path(__file__).resolve().parents[1]
COMMITTED = ROOT / "figures"
TOL = 1.0


def _outputs(folder: Path) -> set[str]:
    return {
        p.relative_to(folder).as_posix()
        for p in folder.rglob("*")
        if (p.suffix in (".png", ".csv") or p.name.endswith(MANIFEST_SUFFIX)) and "-failed-diff" not in p.name
    }


def _is_timing(rel: str) -> bool:
    return Path(rel).stem.endswith(".timing")


def _rows(path: Path) -> list[list[str]]:
    with path.open(newline="", encoding="utf-8") as fh:
        return list(csv.reader(fh))


def csv_differences(expected: Path, actual: Path) -> list[str]:
    """Cells of ``actual`` that do not match ``expected`` under ``expected``'s manifest."""
    return table_differences(_rows(expected), _rows(actual), read_manifest(expected), limit=3)


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
        elif rel.endswith(MANIFEST_SUFFIX):
            if expected.read_text(encoding="utf-8") != actual.read_text(encoding="utf-8"):
                problems.append(f"{rel}: the declared tolerances changed (commit the new manifest)")
        else:
            diffs = csv_differences(expected, actual)
            if diffs:
                problems.append(f"{rel}: " + "; ".join(diffs[:3]))
    assert not problems, "regenerated outputs differ from figures/:\n" + "\n".join(problems)
