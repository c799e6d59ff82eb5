"""Tests of the synthetic scenes of the KL chapter (aircraft renderer, walking sequence)."""
from __future__ import annotations

import numpy as np
import pytest

from projtrack.scenes import aircraft as ac
from projtrack.scenes import sequences as sq


@pytest.mark.parametrize("name", ac.AIRCRAFT)
def test_render_basic(name):
    img = ac.render(name, 0.0, size=32)
    assert img.shape == (32, 32) and img.dtype == np.uint8
    assert img[0, 0] == 0 and img.max() > 100          # black background, lit aircraft
    # roll 0 shows the planform: wider (in y) than at roll 90 (side view)
    side = ac.render(name, 90.0, size=32)
    assert (img > 0).any(axis=1).sum() > (side > 0).any(axis=1).sum()


def test_roll_symmetry_and_periodicity():
    a = ac.render("Mirage", 30.0, size=32)
    np.testing.assert_array_equal(a, ac.render("Mirage", 390.0, size=32))
    # a roll of -phi mirrors the silhouette about the fuselage axis (symmetric aircraft)
    b = ac.render("Mirage", -30.0, size=32)
    np.testing.assert_array_equal(a > 0, (b > 0)[::-1])


def test_aircraft_differ():
    imgs = np.stack([ac.render(n, 0.0, size=32).astype(float).ravel() for n in ac.AIRCRAFT])
    d = np.linalg.norm(imgs[:, None] - imgs[None], axis=-1)
    assert np.all(d[~np.eye(5, dtype=bool)] > 100)


def test_render_rolls_and_bad_inputs():
    r = ac.render_rolls("Mig", [0, 10, 20], size=16)
    assert r.shape == (3, 16, 16)
    with pytest.raises(ValueError, match="name"):
        ac.aircraft_model("Concorde")
    with pytest.raises(ValueError, match="roll_deg"):
        ac.render("Mig", np.nan)
    with pytest.raises(ValueError, match="size"):
        ac.render("Mig", 0.0, size=4)
    with pytest.raises(TypeError):
        ac.render(3, 0.0)


def test_walking_sequence_ground_truth():
    s = sq.walking_sequence(np.random.default_rng(0), n_frames=12, shape=(64, 64), entry_frame=5)
    assert s.frames.shape == (12, 64, 64) and s.frames.dtype == np.uint8
    assert not s.foreground_masks[:4].any() and s.foreground_masks[4].any()
    assert np.all(s.masks >= s.foreground_masks)
    # outside the figures the frame is the background up to jitter and noise
    err = np.abs(s.frames[0].astype(float) - s.background)[~s.masks[0]]
    assert np.median(err) < 10
    s2 = sq.walking_sequence(np.random.default_rng(0), n_frames=12, shape=(64, 64), entry_frame=5)
    np.testing.assert_array_equal(s.frames, s2.frames)


def test_walking_sequence_prefix_knobs_and_sync():
    kw = dict(shape=(32, 32), entry_frame=3, background_height=8.0, foreground_height=16.0)
    long = sq.walking_sequence(np.random.default_rng(4), n_frames=8, **kw)
    short = sq.walking_sequence(np.random.default_rng(4), n_frames=3, **kw)
    np.testing.assert_array_equal(long.frames[:3], short.frames)      # drawn frame by frame
    dark = sq.walking_sequence(np.random.default_rng(4), n_frames=8, gain=0.5, noise_std=0.0, jitter=0.0, **kw)
    flat = sq.walking_sequence(np.random.default_rng(4), n_frames=8, people_contrast=0.0, noise_std=0.0,
                               jitter=0.0, **kw)
    assert np.array_equal(flat.frames[0], flat.frames[1])             # no walkers, no shift, no noise
    ref = sq.walking_sequence(np.random.default_rng(4), n_frames=8, noise_std=0.0, jitter=0.0, **kw)
    assert np.abs(dark.frames.astype(float) - 0.5 * ref.frames).max() <= 1.0
    synced = sq.walking_sequence(np.random.default_rng(4), n_frames=8, jitter_frames=(2,), **kw)
    assert synced.offsets[1].any() and not synced.offsets[[0, 2, 3]].any()
    fg_only = sq.walking_sequence(np.random.default_rng(4), n_frames=8, people_contrast=0.0,
                                  foreground_contrast=1.0, noise_std=0.0, jitter=0.0, **kw)
    assert np.array_equal(fg_only.frames[0], flat.frames[0]) and not np.array_equal(fg_only.frames[5], flat.frames[5])


def test_walking_sequence_bad_inputs():
    rng = np.random.default_rng(0)
    with pytest.raises(TypeError, match="rng"):
        sq.walking_sequence(0)
    with pytest.raises(ValueError, match="shape"):
        sq.walking_sequence(rng, shape=(8, 8))
    with pytest.raises(ValueError, match="n_frames"):
        sq.walking_sequence(rng, n_frames=0)
    with pytest.raises(ValueError, match="jitter"):
        sq.walking_sequence(rng, jitter=-1.0)
    with pytest.raises(ValueError, match="gain"):
        sq.walking_sequence(rng, gain=-0.5)
    with pytest.raises(ValueError, match="jitter_frames"):
        sq.walking_sequence(rng, jitter_frames=(0,))
    with pytest.raises(ValueError, match="jitter_frames"):
        sq.walking_sequence(rng, jitter_frames=2)
    with pytest.raises(ValueError, match="contrast"):
        sq.textured_background((32, 32), rng, contrast=np.inf)
