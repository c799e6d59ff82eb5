"""Real pedestrians: the shipped MOTChallenge loader, CLEAR MOT scoring, track management, peers."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from projtrack import datasets
from projtrack.datasets import MOTBoxes, load_mot_sequence
from projtrack.experiments.jpda import motscore, pedestrians as ped, pedtiming
from projtrack.experiments.jpda.pedtracking import PedestrianModel, track_sequence

pytest.importorskip("motmetrics")


# -- the loader ------------------------------------------------------------------------------

@pytest.mark.parametrize("name,source,frames,people,boxes", [
    ("TUD-Campus", "gt", 71, 8, 359), ("TUD-Campus", "test", 71, 13, 222),
    ("TUD-Stadtmitte", "gt", 179, 10, 1156), ("TUD-Stadtmitte", "test", 179, 12, 749),
])
def test_loader_counts(name, source, frames, people, boxes):
    seq = load_mot_sequence(name, source)
    assert (seq.n_frames, len(seq.identities), len(seq.frame)) == (frames, people, boxes)
    assert np.all(np.diff(seq.frame) >= 0) and seq.frame.min() >= 1 and seq.frame.max() <= frames
    assert seq.image_size == (640, 480) and np.all(seq.box[:, 2:] > 0)


def test_loader_matches_motmetrics_reader():
    mm = pytest.importorskip("motmetrics")
    seq = load_mot_sequence("TUD-Campus")
    df = mm.io.loadtxt(str(datasets.mot_data_file("TUD-Campus", "gt")), fmt="mot15-2D")
    np.testing.assert_array_equal(df.index.get_level_values(0), seq.frame)
    np.testing.assert_array_equal(df.index.get_level_values(1), seq.ident)
    np.testing.assert_allclose(df[["X", "Y", "Width", "Height"]].to_numpy(float), seq.box)
    k = seq.in_frame(1)
    assert len(k) == 6 and np.all(seq.frame[k] == 1)


def test_loader_bad_inputs_and_missing_package(monkeypatch):
    with pytest.raises(ValueError, match="name"):
        load_mot_sequence("MOT17-02")
    with pytest.raises(ValueError, match="source"):
        load_mot_sequence("TUD-Campus", "det")
    monkeypatch.setitem(sys.modules, "motmetrics", None)
    with pytest.raises(ImportError, match="pip install motmetrics"):
        load_mot_sequence("TUD-Campus")


# -- scoring with motmetrics -------------------------------------------------------------------

def _two_people() -> MOTBoxes:
    """Two people of 30 x 90 px, standing still at x = 100 and 300, over three frames."""
    frame = np.array([1, 1, 2, 2, 3, 3])
    ident = np.array([1, 2, 1, 2, 1, 2])
    box = np.array([[85.0, 55.0, 30.0, 90.0], [285.0, 55.0, 30.0, 90.0]] * 3)
    return MOTBoxes("TUD-Campus", "gt", frame, ident, box, 3)


def test_score_perfect_tracks():
    gt = _two_people()
    s = motscore.score_points(gt, gt.frame, gt.ident + 10, gt.centres)
    assert (s["mota"], s["idf1"], s["motp"], s["num_switches"]) == (1.0, 1.0, 0.0, 0)


def test_score_hand_made_sequence_has_known_mota():
    # frame 1: both matched; frame 2: person 2 missed and a hypothesis far away (FP);
    # frame 3: the two hypotheses exchange people (2 switches). MOTA = 1 - (1 + 1 + 2) / 6.
    gt = _two_people()
    frame = np.array([1, 1, 2, 2, 3, 3])
    ident = np.array([10, 11, 10, 12, 10, 11])
    pts = np.array([[100, 100], [300, 100], [102, 100], [500, 300], [300, 100], [100, 100]], float)
    s = motscore.score_points(gt, frame, ident, pts)
    assert (s["num_misses"], s["num_false_positives"], s["num_switches"]) == (1, 1, 2)
    assert s["mota"] == pytest.approx(1 - 4 / 6)
    # MOTP: mean 1 - IoU over the 5 matches (3 kept, 2 switched), one of them offset by 2 px (IoU 28 * 90 / (2*2700 - 28*90))
    iou = 28 * 90 / (2 * 2700 - 28 * 90)
    assert s["num_matches"] + s["num_switches"] == 5 and s["motp"] == pytest.approx((1 - iou) / 5)


def test_centred_overlap_and_box_iou():
    ov = motscore.centred_overlap([[0, 0, 30, 90]], [[15, 45], [25, 45], [15, 75], [60, 45]])
    np.testing.assert_allclose(ov, [[1.0, 0.5, 0.5, 0.0]])
    iou = motscore.box_iou([[0, 0, 2, 2]], [[1, 0, 2, 2], [0, 0, 2, 2], [5, 5, 1, 1]])
    np.testing.assert_allclose(iou, [[2 / 6, 1.0, 0.0]])
    with pytest.raises(ValueError, match="widths"):
        motscore.box_iou([[0, 0, 0, 2]], [[0, 0, 1, 1]])


def test_score_arrays_counts_a_swap():
    t = np.arange(4.0)
    truth = np.zeros((4, 2, 4))
    truth[:, 0, 0], truth[:, 1, 0] = t, t + 10
    est = truth.copy()
    est[2:, [0, 1]] = est[2:, [1, 0]]  # the tracks exchange targets at step 2
    s = motscore.score_arrays(est, truth, max_distance=1.0)
    assert s["num_switches"] == 2 and s["mota"] == pytest.approx(1 - 2 / 8)
    assert motscore.score_arrays(truth, truth, 1.0)["mota"] == 1.0


# -- data statistics and detections ------------------------------------------------------------

def test_motion_statistics_recover_a_simulated_model():
    """The method of moments on simulated constant-velocity tracks plus white jitter."""
    rng = np.random.default_rng(5)
    q, s = np.array([2.0, 0.5]), np.array([3.0, 1.0])
    F, Q, _ = ped.cv_matrices(q, np.eye(2))
    frames, ids, boxes = [], [], []
    for i in range(40):
        x = np.array([100.0, 1.0, 200.0, 0.0])
        for k in range(1, 201):
            x = F @ x + rng.multivariate_normal(np.zeros(4), Q)
            c = x[[0, 2]] + np.sqrt(s) * rng.standard_normal(2)
            frames.append(k), ids.append(i + 1), boxes.append([c[0] - 10, c[1] - 30, 20, 60])
    order = np.lexsort((ids, frames))
    gt = MOTBoxes("TUD-Campus", "gt", np.array(frames)[order], np.array(ids)[order], np.array(boxes)[order], 200)
    st = ped.motion_statistics(gt)
    np.testing.assert_allclose(st["q"], q, rtol=0.15)
    np.testing.assert_allclose(st["jitter"], s, rtol=0.1)
    assert not st["clipped"].any()


def test_detector_statistics_of_the_annotations_themselves():
    gt = load_mot_sequence("TUD-Campus")
    st = ped.detector_statistics(gt, gt)
    assert st["p_detect"] == 1.0 and st["false_per_frame"] == 0.0
    np.testing.assert_allclose(st["offset_cov"], 0.0, atol=1e-12)


def test_synthetic_detections_without_misses_noise_or_clutter_are_the_centres():
    gt = load_mot_sequence("TUD-Campus")
    scans = ped.synthetic_detections(gt, np.random.default_rng(0), 1.0, 0.0, 0.0)
    for k in (1, 30, 71):
        np.testing.assert_allclose(np.sort(scans[k - 1], axis=0), np.sort(gt.centres[gt.in_frame(k)], axis=0))
    test = load_mot_sequence("TUD-Campus", "test")
    shipped = ped.shipped_detections(test)
    assert sum(len(z) for z in shipped) == 222 and np.all(np.diff(shipped[0][:, 0]) >= 0)


def test_model_q_is_stonesoups_constant_velocity():
    pytest.importorskip("stonesoup")
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    import datetime

    F, Q, H = ped.cv_matrices([2.0, 0.3], np.eye(2))
    model = CombinedLinearGaussianTransitionModel([ConstantVelocity(2.0), ConstantVelocity(0.3)])
    dt = datetime.timedelta(seconds=1)
    np.testing.assert_allclose(model.covar(time_interval=dt), Q, atol=1e-15)
    np.testing.assert_allclose(model.matrix(time_interval=dt), F, atol=1e-15)
    assert H.tolist() == [[1, 0, 0, 0], [0, 0, 1, 0]]


# -- track management and the trackers -----------------------------------------------------------

def _walkers_model(p_detect=0.99) -> PedestrianModel:
    motion = {"q": np.array([0.05, 0.05]), "jitter": np.array([0.01, 0.01]), "velocity_var": np.array([4.0, 4.0])}
    return ped.pedestrian_model(motion, np.eye(2), p_detect, 0.5, (640, 480))


def test_track_sequence_confirms_after_three_scans_and_keeps_identities():
    # two people walking apart, detected exactly every frame: each track is reported from frame 3 on
    scans = [np.array([[100.0 + 2 * k, 200.0], [400.0 - 2 * k, 300.0]]) for k in range(20)]
    for tracker in ("jpda", "gnn"):
        run = track_sequence(scans, _walkers_model(), tracker)
        assert run.n_tracks_started == 2 and run.frame.min() == 3
        assert len(run.frame) == 2 * 18 and set(run.ident.tolist()) == {1, 2}
        np.testing.assert_allclose(run.point[run.frame == 20], scans[19], atol=0.5)


def test_track_sequence_deletes_after_misses_and_outside_the_image():
    scans = [np.array([[100.0 + 2 * k, 200.0]]) for k in range(8)] + [np.zeros((0, 2))] * 6
    model = _walkers_model(p_detect=0.9)  # delete after 2 missed scans ((0.1)^2 <= 0.01)
    assert model.delete_after == 2
    run = track_sequence(scans, model, "jpda")
    assert run.frame.max() == 9  # reported at the first miss, deleted at the second
    leaving = [np.array([[630.0 + 4 * k, 200.0]]) for k in range(8)]
    assert track_sequence(leaving, model, "gnn").frame.max() == 3  # leaves the 640 px image after frame 3


def test_track_sequence_bad_inputs():
    with pytest.raises(ValueError, match="tracker"):
        track_sequence([], _walkers_model(), "pda")
    with pytest.raises(TypeError, match="PedestrianModel"):
        track_sequence([], None)


def test_trackers_equal_results_for_a_fixed_seed():
    """The book's exact JPDA tracker and Stone Soup's JPDA with EHM track the same draw alike:
    the same tracks at the same frames, positions equal to rounding, the same CLEAR MOT scores;
    and a draw is repeated exactly from its seed."""
    pytest.importorskip("stonesoup")
    a = ped.pedestrian_trial(np.random.default_rng(7), "TUD-Campus", "base", ("jpda", "gnn", "stonesoup"))
    assert a["jpda_vs_stonesoup"] < 1e-6
    assert a["jpda"] == pytest.approx(a["stonesoup"], rel=1e-9, abs=1e-12)
    b = ped.pedestrian_trial(np.random.default_rng(7), "TUD-Campus", "base", ("jpda", "gnn"))
    assert b["jpda"] == a["jpda"] and b["gnn"] == a["gnn"]
    assert 0.5 < a["jpda"]["mota"] <= 1 and 0.5 < a["gnn"]["mota"] <= 1


def test_score_table_and_tolerances():
    draws = [ped.pedestrian_trial(np.random.default_rng(s), "TUD-Campus", "base") for s in (1, 2)]
    t = ped.pedestrian_table(draws, sequence="TUD-Campus")
    assert list(t["tracker"]) == ["JPDA (book)", "GNN (book)"]
    assert t.loc[0, "MOTA"] == pytest.approx(np.mean([d["jpda"]["mota"] for d in draws]))
    tol = ped.pedestrian_tolerances(2, 359)
    assert tol["MOTA"].atol == pytest.approx(1 / 359) and tol["ID switches"].atol == 0.5


def _fake_draw(j, g):
    keys = ("mota", "motp", "idf1", "num_switches", "num_false_positives", "num_misses")
    return {"jpda": dict.fromkeys(keys, j), "gnn": dict.fromkeys(keys, g)}


def test_paired_mota_table_and_draw_spread_tolerances():
    draws = [_fake_draw(j, g) for j, g in ((0.80, 0.82), (0.84, 0.83), (0.76, 0.80), (0.80, 0.81))]
    t = ped.paired_mota_table({("base", "TUD-Campus"): draws})
    d = np.array([-0.02, 0.01, -0.04, -0.01])
    assert t.loc[0, "MOTA JPDA - GNN"] == pytest.approx(d.mean())
    assert t.loc[0, "standard error (draws)"] == pytest.approx(d.std(ddof=1) / 2)
    assert t.loc[0, "GNN better (share of draws)"] == 0.75
    tol = ped.draw_spread_tolerances([draws])
    per = 0.2  # 4 sd of JPDA's MOTA over the draws (4 x 0.0327 = 0.131), rounded up to one digit
    assert tol["MOTA"].atol == pytest.approx(per / 4)
    assert tol["MOTA JPDA - GNN"].atol == pytest.approx(per / 4)
    assert tol["standard error (draws)"].atol == pytest.approx(per / np.sqrt(12))
    assert tol["GNN better (share of draws)"].atol == 0.25
    # a single run's one-box tolerance is kept where it is the larger
    big = ped.pedestrian_tolerances(1, 3)
    assert ped.draw_spread_tolerances([draws], one_run=big)["MOTA"].atol == pytest.approx(2 / 3)
    with pytest.raises(ValueError, match="two draws"):
        ped.draw_spread_tolerances([draws[:1]])


# -- association time ---------------------------------------------------------------------------

def test_time_association_agrees_with_stonesoup_and_skips_huge_clusters():
    pytest.importorskip("stonesoup")
    gt = load_mot_sequence("TUD-Stadtmitte")
    model = ped.gt_model(gt, "base")
    rng = np.random.default_rng(3)
    probs = [pedtiming.crowd_scan(rng, model, 30, (320, 240), 10.0) for _ in range(2)]
    t = pedtiming.time_association(probs, model, repeats=1)
    assert list(t["T"]) == [30, 30] and (t["max |diff|"] < 1e-9).all()
    t2 = pedtiming.time_association(probs[:1], model, repeats=1, max_cluster=0)
    assert np.isnan(t2.loc[0, "beta [s]"]) and np.isfinite(t2.loc[0, "Stone Soup EHM [s]"])


def test_crossing_scenes_scored_with_motmetrics_keep_the_chapters_count():
    from projtrack import montecarlo
    from projtrack.experiments.jpda import tracking

    res = montecarlo.run(motscore.crossing_mot_trial, 3, np.random.default_rng(2026))
    table, tol = motscore.crossing_mot_table(res)
    own, _ = tracking.tracking_summary(tracking.tracking_study(3, 2026))
    np.testing.assert_allclose(table["tracks swapped or lost"], own["tracks swapped"] + own["tracks lost"])
    assert ((table["MOTA"] <= 1) & (table["IDF1"] <= 1)).all() and tol["MOTA"].atol == pytest.approx(3 / 270)


def test_scan_clusters_counts_shared_gates():
    model = _walkers_model()
    S = np.repeat((4.0 * np.eye(2))[None], 2, axis=0)
    apart = (np.array([[0.0, 0.0], [100.0, 0.0]]), np.array([[0.0, 0.0], [100.0, 0.0]]), S)
    close = (np.array([[0.0, 0.0]]), np.array([[0.0, 1.0], [0.0, -1.0]]), S)
    c = pedtiming.scan_clusters([apart, close], model)
    assert c["shared"].tolist() == [False, True] and c["largest cluster"].tolist() == [1, 1]
