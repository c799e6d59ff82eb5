"""projtrack.scorecard and projtrack.inventory."""

import csv

import pytest

from projtrack.inventory import PARTS, inventory_ids, load_inventory
from projtrack.scorecard import COLUMNS, VERDICTS, Scorecard, id_verdict, read_scorecards, summary


def test_inventory_has_96_unique_ids_with_known_prefixes():
    ids = inventory_ids()
    assert len(ids) == 96 and len(set(ids)) == 96
    assert {item.prefix for item in load_inventory()} == set(PARTS)
    assert "JPDA-T1" in ids and "KVW-F1" in ids


def test_verdicts_are_exactly_the_conventions():
    assert VERDICTS == ("reproduced", "within-tolerance", "qualitative", "misprint", "differs",
                        "not-reproducible", "beyond")


@pytest.mark.parametrize("verdicts, expected", [
    (["reproduced", "qualitative"], "qualitative"),
    (["reproduced", "misprint"], "misprint"),
    (["misprint", "differs"], "differs"),
    (["reproduced", "beyond"], "reproduced"),   # beyond rows do not judge the id
    (["beyond", "beyond"], "beyond"),
    ([], ""),
])
def test_id_verdict_combines_sub_rows(verdicts, expected):
    rows = [{"item": f"KVW-F6.s{i}", "verdict": v} for i, v in enumerate(verdicts)]
    assert id_verdict("KVW-F6", rows) == expected


def test_an_id_never_looks_better_than_its_sub_rows():
    rows = [{"item": "KVW-F6", "verdict": "reproduced"}, {"item": "KVW-F6.x", "verdict": "differs"}]
    assert id_verdict("KVW-F6", rows) == "differs"
    rows = [{"item": "KVW-OBS", "verdict": "reproduced"}, {"item": "KVW-OBS.a", "verdict": "misprint"}]
    assert id_verdict("KVW-OBS", rows) == "misprint"


def test_summary_counts_beyond_rows_apart(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    card = _card()
    card.add("JPDA-T1.a", "c", "p", "r", "reproduced")
    card.add("JPDA-T1.b", "c", "p", "r", "beyond", "a baseline")
    card.add("JPDA-T2", "c", "p", "r", "misprint", "Table VI gives 3, not 4")
    card.save()
    items, counts = summary(tmp_path)
    t1 = items.set_index("id").loc["JPDA-T1"]
    assert t1["verdict"] == "reproduced" and t1["rows"] == 2 and t1["beyond rows"] == 1
    assert items.set_index("id").loc["JPDA-T2", "verdict"] == "misprint"
    by = counts.set_index("verdict")["inventory ids"]
    assert by["reproduced"] == 1 and by["misprint"] == 1 and by["not yet covered"] == 94


def _card(nb="part3/x.ipynb", part="jpda"):
    return Scorecard(part, nb)


def test_add_and_save_writes_the_csv(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    card = _card()
    card.add("JPDA-T2", "claim b", "paper b", 0.5, "qualitative")
    card.add("JPDA-T1", "claim a", "paper a", "obtained a", "reproduced", "exact")
    card.add("JPDA-T1.sub", "claim c", "p", "r", "differs", "the glyphs differ")
    path = card.save()
    assert path == tmp_path / "jpda" / "scorecard.csv"
    rows = list(csv.DictReader(path.open()))
    assert tuple(rows[0]) == COLUMNS
    assert [r["item"] for r in rows] == ["JPDA-T1", "JPDA-T1.sub", "JPDA-T2"]  # inventory order
    assert rows[2]["reproduced"] == "0.5"
    assert "<table" in card._repr_html_() and "JPDA-T1.sub" in card._repr_html_()
    assert list(card.to_frame().columns) == list(COLUMNS)


def test_notebooks_merge_into_one_part_file(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    a = _card("a.ipynb")
    a.add("JPDA-T1", "c", "p", "r", "reproduced")
    a.save()
    b = _card("b.ipynb")
    b.add("JPDA-F1", "c", "p", "r", "qualitative")
    b.save()
    a2 = _card("a.ipynb")  # re-running notebook a replaces only its own rows
    a2.add("JPDA-T2", "c", "p", "r2", "reproduced")
    a2.save()
    rows = read_scorecards(tmp_path)
    assert [(r["item"], r["notebook"], r["part"]) for r in rows] == [
        ("JPDA-F1", "b.ipynb", "jpda"), ("JPDA-T2", "a.ipynb", "jpda")]
    clash = _card("c.ipynb")
    clash.add("JPDA-F1", "c", "p", "r", "reproduced")
    with pytest.raises(ValueError, match="another notebook"):
        clash.save()


def test_bad_rows_are_rejected():
    card = _card()
    with pytest.raises(ValueError, match="not an id"):
        card.add("XYZ-1", "c", "p", "r", "reproduced")
    with pytest.raises(ValueError, match="verdict must be one of"):
        card.add("JPDA-T1", "c", "p", "r", "matches")
    for verdict in ("differs", "not-reproducible", "misprint", "beyond"):
        with pytest.raises(ValueError, match="needs a note"):
            card.add("JPDA-T1", "c", "p", "r", verdict)
    with pytest.raises(TypeError, match="claim"):
        card.add("JPDA-T1", None, "p", "r", "reproduced")
    with pytest.raises(ValueError, match="single line"):
        card.add("JPDA-T1", "two\nlines", "p", "r", "reproduced")
    card.add("JPDA-T1", "c", "p", "r", "reproduced")
    with pytest.raises(ValueError, match="already"):
        card.add("JPDA-T1", "c", "p", "r", "reproduced")
    with pytest.raises(ValueError, match="suffix"):
        card.add("JPDA-T2.bad suffix", "c", "p", "r", "reproduced")


def test_bad_construction_and_empty_save(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    with pytest.raises(ValueError, match="part"):
        Scorecard("../x", "a.ipynb")
    with pytest.raises(ValueError, match="notebook"):
        Scorecard("jpda", "a.py")
    with pytest.raises(ValueError, match="no rows"):
        _card().save()
