"""Tests of projtrack.experiments.neuralnet (the Sec. VI experiment of Barnard & Casasent)."""

import numpy as np
import pytest

from projtrack import neuralnet as nn
from projtrack.experiments.neuralnet import simulate
from projtrack.scenes.tracks3d import make_tracks


def test_simulate_small_is_deterministic():
    a = simulate(np.random.default_rng(2), 3, 2, 0.0)
    b = simulate(np.random.default_rng(2), 3, 2, 0.0)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    assert a["correct"].shape == (6,) and a["optimal_correct"].shape == (3,)
    np.testing.assert_array_equal(a["dataset"], [0, 0, 1, 1, 2, 2])


def test_simulate_scores_runs_against_the_scenes_it_draws():
    # the same draws by hand: data sets first, then the starts, then one batch of nets
    rng = np.random.default_rng(8)
    scenes = [make_tracks(rng, 4, 5, noise_percent=0.0) for _ in range(2)]
    D = nn.distance_tensor(np.stack([s.positions for s in scenes]) / 256.0)
    X0 = nn.initial_states(rng, 6, 4, 4, 5)
    res = nn.run_net(np.repeat(D, 3, axis=0), X0)
    want = [res.status[k] == "converged" and
            nn.is_correct_assignment(nn.states_to_assignment(res.states[k]), scenes[k // 3].labels)
            for k in range(6)]
    out = simulate(np.random.default_rng(8), 2, 3, 0.0)
    np.testing.assert_array_equal(out["correct"], want)
    np.testing.assert_array_equal(out["iterations"], res.iterations)
    # noise-free straight tracks: the exact optimum is the truth and costs nothing
    np.testing.assert_array_equal(out["optimal_correct"], [1.0, 1.0])
    np.testing.assert_allclose(out["true_cost"], 0.0, atol=1e-12)
    assert np.all(out["optimal_cost"] <= out["true_cost"] + 1e-12)


def test_simulate_without_references_and_beyond_the_exact_size():
    out = simulate(np.random.default_rng(5), 3, 1, 2.5, noise_law="coordinate", references=False)
    assert set(out) == {"dataset", "status", "iterations", "converged", "correct"}
    again = simulate(np.random.default_rng(5), 3, 1, 2.5, noise_law="coordinate", references=False)
    np.testing.assert_array_equal(out["iterations"], again["iterations"])
    big = simulate(np.random.default_rng(1), 1, 1, 0.0, n_targets=5, exact_max_targets=4, max_iter=2)
    assert np.isnan(big["optimal_correct"][0]) and np.isnan(big["optimal_cost"][0])


def test_simulate_validates_its_arguments():
    rng = np.random.default_rng(4)
    with pytest.raises(ValueError, match="noise_percent"):
        simulate(rng, 1, 1, -1.0)
    with pytest.raises(ValueError, match="noise_percent"):
        simulate(rng, 1, 1, float("nan"))
    with pytest.raises(TypeError, match="noise_percent"):
        simulate(rng, 1, 1, "5")
    with pytest.raises(ValueError, match="noise_law"):
        simulate(rng, 1, 1, 1.0, noise_law="Ball")
    with pytest.raises(TypeError, match="rng"):
        simulate(42, 1, 1, 0.0)
    with pytest.raises(ValueError, match="n_datasets"):
        simulate(rng, 0, 1, 0.0)
    with pytest.raises(TypeError, match="n_starts"):
        simulate(rng, 1, 1.5, 0.0)
    with pytest.raises(ValueError, match="unit"):
        simulate(rng, 1, 1, 0.0, unit=0.0)

