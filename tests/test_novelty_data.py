"""Tests of the KL chapter's data: the plaza excerpt, its window rule, and Fig. 1's drawing."""
from __future__ import annotations

import importlib.util
import pathlib

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from projtrack import novelty as nv  # noqa: E402
from projtrack.experiments.novelty.plots import plot_block_diagram  # noqa: E402
from projtrack.scenes.sequences import load_plaza_excerpt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _fetch_module():
    spec = importlib.util.spec_from_file_location("fetch_plaza_video",
                                                  ROOT / "tools" / "fetch_plaza_video.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_plaza_excerpt_matches_its_description():
    e = load_plaza_excerpt()
    assert e.frames.shape == (24, 128, 128) and e.frames.dtype == np.uint8
    # one frame per second of a 10-fps video
    np.testing.assert_array_equal(np.diff(e.source_frame_index), 10)
    assert e.entry_position == 7
    assert "opencv-doc" in e.source
    assert 20 < e.frames.mean() < 235 and e.frames.std() > 10
    size = (ROOT / "src" / "projtrack" / "data" / "plaza-excerpt.npz").stat().st_size
    assert size < 500_000


def test_window_rule_on_a_synthetic_entry():
    fetch = _fetch_module()
    rng = np.random.default_rng(0)
    frames = np.tile(rng.integers(60, 200, (1, 128, 128)), (60, 1, 1)).astype(np.uint8)
    frames[20:36, 100:120, 10:40] = 0          # something in the lower half for t = 20..35
    start, entry = fetch.choose_window(frames)
    assert (start, entry) == (20 - fetch.ENTRY_INDEX, 20)
    # activity in the upper half only never triggers the rule
    quiet = np.tile(rng.integers(60, 200, (1, 128, 128)), (60, 1, 1)).astype(np.uint8)
    quiet[20:36, 5:40, 10:60] = 0
    with pytest.raises(SystemExit):
        fetch.choose_window(quiet)


def test_block_diagram_has_every_step():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    plot_block_diagram(ax)
    texts = [t.get_text() for t in ax.texts]
    for step, _ in nv.TABLE1_STEPS:
        assert any(t.startswith(f"{step}. ") for t in texts)
    assert {"novel", "not novel", "more images"} <= set(texts)
    assert len(ax.patches) == len(nv.TABLE1_STEPS) + 1
    plt.close(fig)
    # every transition links known steps
    known = {s for s, _ in nv.TABLE1_STEPS} | {0}
    assert all(a in known and b in known for a, b, _ in nv.TABLE1_FLOW)
