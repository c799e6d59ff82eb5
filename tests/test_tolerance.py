"""projtrack.tolerance, the manifests save_table and Scorecard.save write, and the regression
comparison that reads them: tolerances hold what one flipped decision moves, and a real change
still fails."""

from __future__ import annotations

import csv
import json
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from projtrack import figures
from projtrack.scorecard import Scorecard
from projtrack.tolerance import (
    EXACT,
    ROUNDING,
    Manifest,
    Tolerance,
    last_digit_unit,
    mean_over,
    moved_numbers,
    numerical,
    read_manifest,
    share,
    split_numbers,
    statistical,
    table_differences,
    text_matches,
)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_figure_regression import csv_differences  # noqa: E402

# The slot-car sensitivity row that broke `make test` on an AVX-512 CPU under the Sandybridge
# kernel: the decoded Viterbi path changed, moving the mean error over 593 frames.
SLOTCAR_HASWELL, SLOTCAR_SANDYBRIDGE = "0.6385", "0.6416"


# -- the kinds ---------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, err, match", [
    (dict(kind="approx"), ValueError, "kind must be one of"),
    (dict(kind="exact", atol=0.1), ValueError, "no tolerance"),
    (dict(kind="numerical"), ValueError, "atol > 0 or rtol > 0"),
    (dict(kind="numerical", rtol=1e-6), ValueError, "needs why="),
    (dict(kind="statistical", atol=-1.0, why="x"), ValueError, "atol must be finite and >= 0"),
    (dict(kind="statistical", rtol=1.5, why="x"), ValueError, "rtol must be below 1"),
    (dict(kind="statistical", atol="0.1", why="x"), TypeError, "atol must be a real number"),
    (dict(kind="statistical", atol=0.1, why=3), TypeError, "why must be a str"),
])
def test_bad_tolerances_are_refused(kwargs, err, match):
    with pytest.raises(err, match=match):
        Tolerance(**kwargs)


def test_exact_is_equality():
    assert EXACT.allows("3", "3") and not EXACT.allows("3", "4")
    assert EXACT.allows(0.5, 0.5) and not EXACT.allows(0.5, 0.5 + 1e-15)
    assert not EXACT.allows("0.6385", "0.6386")


def test_numerical_allows_its_tolerance_and_the_last_stored_digit():
    tol = numerical(rtol=1e-6, why="solver stops at 1e-9")
    assert tol.allows(1.0, 1.0 + 5e-7) and not tol.allows(1.0, 1.0 + 5e-6)
    # stored at 4 significant digits, a value on a rounding boundary flips the last digit
    assert tol.allows("0.1235", "0.1234") and not tol.allows("0.1235", "0.1233")


def test_nan_and_inf():
    tol = statistical(atol=0.1, why="x")
    assert tol.allows("nan", "nan") and not tol.allows("nan", "1")
    assert tol.allows("inf", "inf") and not tol.allows("inf", "1e308")


def test_share_and_mean_over_are_one_flip():
    assert share(200).atol == pytest.approx(0.005)
    assert share(8, flips=2, percent=True).atol == pytest.approx(25.0)
    assert "200 trials" in share(200).why
    assert mean_over(593, 2.0, what="frame").atol == pytest.approx(2.0 / 593)
    for bad in (0, -3, 2.5, True):
        with pytest.raises(ValueError):
            share(bad)
    with pytest.raises(ValueError):
        mean_over(10, 0.0)


def test_last_digit_unit():
    assert last_digit_unit("0.6385") == pytest.approx(1e-4)
    assert last_digit_unit("-12.07") == pytest.approx(1e-2)
    assert last_digit_unit("3e-05") == pytest.approx(1e-5)
    assert last_digit_unit("120") == 1.0
    with pytest.raises(ValueError):
        last_digit_unit("abc")


@given(st.floats(-1e6, 1e6), st.floats(0, 10), st.floats(0, 0.5))
def test_allows_is_symmetric_in_its_own_bound(x, atol, rtol):
    if atol == 0 and rtol == 0:
        return
    tol = statistical(atol=atol, rtol=rtol, why="x")
    bound = atol + rtol * abs(x)
    assert tol.allows(x, x + 0.99 * bound)
    assert not tol.allows(x, x + 1.01 * bound + 1e-9)


# -- text with numbers (scorecard rows) --------------------------------------------------------------

def test_split_numbers_keeps_ids_and_ranges_apart():
    skel, nums = split_numbers("DMA-F9: error 0.64-12.07 px over M in 2..16 (x2)")
    assert nums == ["0.64", "12.07", "2", "16"]
    assert skel[0] == "DMA-F9: error " and skel[-1] == " (x2)"


def test_text_matches_compares_numbers_under_the_rows_tolerance():
    tol = statistical(atol=0.01, why="one frame")
    a = "Viterbi error 0.64-12.07 px; 1.16 px at M = K = 8"
    assert text_matches(a, a.replace("0.64", "0.65"), tol)
    assert not text_matches(a, a.replace("0.64", "0.70"), tol)
    assert not text_matches(a, a.replace("px;", "pixels;"), tol)     # words are exact
    assert not text_matches(a, a.replace("0.64", "0.65"), EXACT)   # exact by default


# -- stored tables ------------------------------------------------------------------------------------

def _viterbi_manifest() -> Manifest:
    # what the slot-car sensitivity table declares: a changed path segment of a few frames,
    # each off by up to a centroid spacing, over 593 frames
    return Manifest({"viterbi error [px]": mean_over(593, 2.0, flips=3, what="frame")})


def test_the_slotcar_acceptance_case_passes_because_of_its_tolerance():
    header = ["regions", "centroids", "viterbi error [px]"]
    committed = [header, ["16", "256", SLOTCAR_HASWELL]]
    sandybridge = [header, ["16", "256", SLOTCAR_SANDYBRIDGE]]
    assert table_differences(committed, sandybridge, Manifest()) != []      # compared as exact: fails
    assert table_differences(committed, sandybridge, _viterbi_manifest()) == []


@pytest.mark.parametrize("cell, value", [
    (2, "0.70"),      # a real change of the statistical column
    (0, "17"),        # an integer is exact
    (1, "257"),
])
def test_a_real_change_still_fails(cell, value):
    header = ["regions", "centroids", "viterbi error [px]"]
    committed = [header, ["16", "256", SLOTCAR_HASWELL]]
    changed = [header, ["16", "256", SLOTCAR_HASWELL]]
    changed[1][cell] = value
    assert table_differences(committed, changed, _viterbi_manifest())


def test_shape_and_header_changes_fail():
    m = _viterbi_manifest()
    assert table_differences([["a"], ["1"]], [["b"], ["1"]], m)
    assert table_differences([["a"], ["1"]], [["a"], ["1"], ["2"]], m)


def test_moved_numbers_lists_changes_within_tolerance_too():
    header = ["regions", "viterbi error [px]", "note"]
    a = [header, ["16", SLOTCAR_HASWELL, "best 0.64 px"]]
    b = [header, ["16", SLOTCAR_SANDYBRIDGE, "best 0.64 px"]]
    moves = moved_numbers(a, b, _viterbi_manifest())
    assert len(moves) == 1 and moves[0]["ok"] and moves[0]["delta"] == pytest.approx(0.0031)
    assert 0 < moves[0]["delta"] < moves[0]["allowed"]
    assert moved_numbers(a, a, _viterbi_manifest()) == []


# -- save_table and the manifest ------------------------------------------------------------------------

@pytest.fixture
def figdir(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    return tmp_path


def test_save_table_writes_the_manifest_beside_the_csv(figdir):
    df = pd.DataFrame({"regions": [2, 16], "method": ["a", "b"], "error": [12.07, 0.6385]})
    tol = mean_over(593, 2.0, flips=3, what="frame")
    saved = figures.save_table(df, "dma/sens", tolerance={"error": tol}, float_format="%.4g")
    manifest = json.loads((figdir / "dma" / "sens.tolerance.json").read_text())
    assert manifest["columns"]["regions"] == {"kind": "exact"}
    assert manifest["columns"]["method"] == {"kind": "exact"}
    assert manifest["columns"]["error"]["kind"] == "statistical"
    assert read_manifest(saved.path).columns["error"].atol == pytest.approx(tol.atol, rel=1e-2)


def test_save_table_refuses_undeclared_floats(figdir):
    df = pd.DataFrame({"n": [1, 2], "x": [0.5, 0.25]})
    with pytest.raises(ValueError, match=r"\['x'\] hold non-integer numbers"):
        figures.save_table(df, "p/t")
    figures.save_table(df, "p/t", tolerance=ROUNDING)                       # one for all float columns
    figures.save_table(df, "p/t", tolerance={"*": ROUNDING})


@pytest.mark.parametrize("tolerance, err, match", [
    ({"n": statistical(atol=1, why="one trial")}, ValueError, "compared exactly"),
    ({"missing": ROUNDING}, ValueError, "does not have"),
    ({"x": 0.1}, TypeError, "must be a projtrack.tolerance.Tolerance"),
    ("0.1", TypeError, "tolerance must be"),
])
def test_save_table_bad_tolerances(figdir, tolerance, err, match):
    df = pd.DataFrame({"n": [1, 2], "x": [0.5, 0.25]})
    with pytest.raises(err, match=match):
        figures.save_table(df, "p/t", tolerance=tolerance)


def test_saved_table_shows_without_index_and_is_hidden_from_nbval(figdir):
    df = pd.DataFrame({"case": ["a", "b"], "x": [0.5, np.nan], "n": [3, 4]})
    saved = figures.save_table(df, "p/t", tolerance=ROUNDING)
    html = saved._repr_html_()
    assert html.startswith('<div class="pt-compared" data-file="figures/p/t.csv">')
    assert "—" in html and "0.50" in html and ">0<" not in html        # no index column
    assert repr(saved) == "figures/p/t.csv"
    cfg = (Path(__file__).parent / "nbval_sanitize.cfg").read_text()
    import re
    regex = cfg.split("[compared-tables]")[1].split("regex:")[1].split("\n")[0].strip()
    assert re.sub(regex, "X", html + "<p>after</p>") == "X<p>after</p>"


def test_regression_comparison_reads_the_committed_manifest(tmp_path):
    committed, fresh = tmp_path / "c", tmp_path / "f"
    for folder, value in ((committed, SLOTCAR_HASWELL), (fresh, SLOTCAR_SANDYBRIDGE)):
        folder.mkdir()
        with (folder / "t.csv").open("w", newline="") as fh:
            csv.writer(fh, lineterminator="\n").writerows([["regions", "viterbi error [px]"], ["16", value]])
    assert csv_differences(committed / "t.csv", fresh / "t.csv")            # no manifest: exact
    (committed / "t.tolerance.json").write_text(json.dumps(_viterbi_manifest().as_dict()))
    assert csv_differences(committed / "t.csv", fresh / "t.csv") == []


# -- scorecard rows ------------------------------------------------------------------------------------

def test_scorecard_rows_carry_their_tolerance_into_the_manifest(figdir):
    card = Scorecard("dma", "dma/x.ipynb")
    card.add("DMA-F9", "c", "p", "hidden-frame error 1.61 px", "qualitative", "criterion < 3 px",
             tolerance=mean_over(205, 5.0, flips=2, what="frame"))
    card.add("DMA-F3", "c", "p", "r", "reproduced")
    path = card.save()
    m = read_manifest(path)
    assert set(m.rows) == {"DMA-F9"} and m.row_key == "item" and m.row_columns == ("reproduced", "note")
    header, row9 = ["item", "claim", "paper", "reproduced", "verdict", "note"], None
    rows = list(csv.reader(path.open()))
    moved = [r[:] for r in rows]
    i9 = [r[0] for r in rows].index("DMA-F9")
    moved[i9][3] = "hidden-frame error 1.63 px"
    assert table_differences(rows, moved, m) == []
    moved[i9][4] = "differs"                                               # verdicts are exact
    assert table_differences(rows, moved, m)
    with pytest.raises(TypeError, match="tolerance must be"):
        card.add("DMA-F6", "c", "p", "r", "reproduced", tolerance=0.1)
    assert header == rows[0] and row9 is None


def test_scorecard_manifest_keeps_other_notebooks_rows(figdir):
    a = Scorecard("dma", "dma/a.ipynb")
    a.add("DMA-F9", "c", "p", "1.0", "qualitative", "n", tolerance=statistical(atol=0.1, why="x"))
    a.save()
    b = Scorecard("dma", "dma/b.ipynb")
    b.add("DMA-F3", "c", "p", "2.0", "qualitative", "n", tolerance=statistical(atol=0.2, why="y"))
    path = b.save()
    assert set(read_manifest(path).rows) == {"DMA-F9", "DMA-F3"}
    b.save()
    a2 = Scorecard("dma", "dma/a.ipynb")
    a2.add("DMA-F9", "c", "p", "1.0", "qualitative", "n")                  # now exact
    a2.save()
    assert set(read_manifest(path).rows) == {"DMA-F3"}


def test_glance_and_scorecard_html(figdir):
    card = Scorecard("dma", "dma/x.ipynb")
    card.add("DMA-F9", "tracking through the occlusion", "figure only", "1.61 px", "qualitative",
             "criterion: hidden-frame error < 3 px. The per-frame detector fails it.")
    card.add("DMA-F9.sensitivity", "vs regions", "not reported", "0.64-12.07 px", "beyond", "a sensitivity study")
    html = card._repr_html_()
    assert "<details>" in html and "criterion: hidden-frame error &lt; 3 px." in html
    assert 'data-file="figures/dma/scorecard.csv"' in html
    glance = card.glance()
    assert [r.item for r in glance.rows] == ["DMA-F9"]                     # beyond rows left out
    assert "qualitative" in glance._repr_html_() and math.isfinite(len(repr(glance)))


def test_glued_figures_are_left_to_the_figure_regression():
    # a glued figure is stored as base64 PNG; nbval replaces the whole of it (its pixels are
    # compared by test_figure_regression.py), and nothing around it
    import base64
    import io
    import re

    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1, 1))
    ax.plot([0, 1], [0, 1])
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    b64 = base64.b64encode(buf.getvalue()).decode()
    cfg = (Path(__file__).parent / "nbval_sanitize.cfg").read_text()
    regex = cfg.split("[glued-figures]")[1].split("regex:")[1].split("\n")[0].strip()
    assert re.sub(regex, "X", b64 + "\n") == "X" and re.sub(regex, "X", "a " + b64[:40]) == "a X"
    assert re.sub(regex, "X", "figures/jpda/table1.csv 0.5") == "figures/jpda/table1.csv 0.5"
