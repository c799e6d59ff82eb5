"""projtrack.figures: deterministic saving, the output root and bad names."""

import hashlib

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

from projtrack import figures
from projtrack.tolerance import ROUNDING


def _plot():
    fig, ax = plt.subplots(figsize=(3, 2))
    x = np.linspace(0, 1, 50)
    ax.plot(x, x**2, label="$x^2$")
    ax.set_title("a title")
    ax.legend()
    return fig


def test_save_writes_under_env_root_and_is_deterministic(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    saved = figures.save(_plot(), "part/curve")
    path = tmp_path / "part" / "curve.png"
    assert saved.path == path and path.is_file()
    assert repr(saved) == "figures/part/curve.png"
    assert saved._repr_png_() == path.read_bytes()
    first = hashlib.sha256(path.read_bytes()).hexdigest()
    figures.save(_plot(), "part/curve")
    assert hashlib.sha256(path.read_bytes()).hexdigest() == first


def test_saved_png_has_no_software_or_date_metadata(tmp_path, monkeypatch):
    from PIL import Image

    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    figures.save(_plot(), "part/meta")
    info = Image.open(tmp_path / "part" / "meta.png").info
    assert "Software" not in info and "Creation Time" not in info
    assert round(info["dpi"][0]) == figures.DPI


def test_save_closes_the_figure_unless_asked(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    fig = _plot()
    figures.save(fig, "part/a")
    assert not plt.fignum_exists(fig.number)
    fig = _plot()
    figures.save(fig, "part/b", close=False)
    assert plt.fignum_exists(fig.number)
    plt.close(fig)


def test_style_uses_bundled_stix_fonts():
    from matplotlib import font_manager

    assert figures.STYLE["mathtext.fontset"] == "stix"
    path = font_manager.findfont(font_manager.FontProperties(family="STIXGeneral"), fallback_to_default=False)
    assert "STIX" in path


def test_save_table_writes_csv(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    df = pd.DataFrame({"a": [1, 2], "b": [0.123456789, 2.0]})
    path = figures.save_table(df, "part/tab", float_format="%.4g", tolerance=ROUNDING).path
    assert path.read_text() == "a,b\n1,0.1235\n2,2\n"
    named = df.set_index(pd.Index([5, 6], name="k"))
    assert figures.save_table(named, "part/tab2", tolerance=ROUNDING).path.read_text().splitlines()[0] == "k,a,b"


@pytest.mark.parametrize("bad", ["noslash", "/abs", "a/b.png", "a/../b", "a b/c", ""])
def test_bad_names_are_rejected(bad, tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    with pytest.raises(ValueError, match="part/name"):
        figures.save(_plot(), bad)


def test_bad_types_are_rejected(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    with pytest.raises(TypeError, match="Figure"):
        figures.save("not a figure", "part/x")
    with pytest.raises(TypeError, match="str"):
        figures.output_path(3, ".png")
    with pytest.raises(TypeError, match="DataFrame"):
        figures.save_table([[1, 2]], "part/x")


def test_default_root_is_repository_figures(monkeypatch):
    monkeypatch.delenv("PROJTRACK_FIGURES_DIR", raising=False)
    root = figures.output_path("part/x", ".png").parents[1]
    assert root.name == "figures" and (root.parent / "pyproject.toml").is_file()


def test_legibility_check_refuses_small_text_and_crowded_rows(tmp_path, monkeypatch):
    monkeypatch.setenv("PROJTRACK_FIGURES_DIR", str(tmp_path))
    monkeypatch.delenv("PROJTRACK_LEGIBILITY", raising=False)
    fig, ax = plt.subplots(figsize=(6.4, 3.0))
    ax.plot([0, 1], [0, 1], label="line")
    ax.legend(fontsize=6)                      # 6 pt at full size: 7.5 CSS pt on the page
    with pytest.raises(ValueError, match="would show below 9 pt"):
        figures.save(fig, "part/small")
    assert not (tmp_path / "part" / "small.png").exists()
    fig, axes = plt.subplots(1, 4, figsize=(6.4, 2.0))
    for a in axes:
        a.plot([0, 1])
    assert any("4 panels side by side" in p for p in figures.legibility_problems(fig))
    plt.close(fig)
    # a wide figure is shrunk to the column: its 9-pt ticks become too small
    fig, ax = plt.subplots(figsize=(12.0, 3.0))
    ax.plot([0, 1])
    assert any("shown at" in p for p in figures.legibility_problems(fig))
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6.4, 3.0))
    im = ax.imshow(np.eye(3))
    fig.colorbar(im)                           # a colour bar is not a panel
    ax.set_title("fine")
    assert figures.legibility_problems(fig) == []
    figures.save(fig, "part/fine")
