"""Benchmarks of projtrack.hough (Casasent & Slaski's Hough track initiator).

1. The Hough transform of a 256 x 256, 21-frame composite (6 boost-phase targets, 5 false
   pixels per frame): our point voting at the paper's resolution and at scikit-image's
   (1-pixel rho bins), our binary-image entry point, and the numerical rotate-and-integrate
   transform of Fig. 11, against ``skimage.transform.hough_line`` (the baseline); the
   paper-resolution row has the target of at most 1.0x scikit-image, and the voting is also
   timed on its numpy path (the previous implementation, the same votes).
2. The whole initiator against the number of targets: the HT stage (transform + peak
   detection on a fixed-size plane) should stay nearly flat, the estimation stage (one strip
   projection per detected line) grow linearly.

Run: ``python benchmarks/bench_hough.py`` (best of a few repeats, < 60 s).
"""

from __future__ import annotations


import numpy as np

from projtrack._numba import numpy_only
from projtrack.hough import _kernel as _fast_hough
from projtrack.hough import (TrackInitiator, detect_peaks, estimate_track, hough_transform,
                             hough_transform_image, rotate_integrate_hough)
from projtrack.scenes.boost import BoostTrajectory, frame_times, in_view_launches, render_frames
from _timing import best_of


def bench_transform():
    from skimage.transform import hough_line

    rng = np.random.default_rng(0)
    times = frame_times(21, 0.25)
    frames = render_frames(in_view_launches(rng, 6, times), times, rng, n_noise=5)
    pts = frames.composite()
    img = np.zeros(frames.shape, dtype=bool)
    img[pts[:, 1].astype(int), pts[:, 0].astype(int)] = True
    theta = np.deg2rad(np.arange(180.0))
    # the compiled voting kernel is compiled (or loaded from numba's cache) before timing
    hough_transform(pts, frames.shape)
    skimage_t = best_of(lambda: hough_line(img, theta=theta), repeats=5, number=20)
    paper_t = best_of(lambda: hough_transform(pts, frames.shape), repeats=5, number=20)
    with numpy_only():  # the previous implementation: the same votes with array operations
        numpy_t = best_of(lambda: hough_transform(pts, frames.shape), repeats=5, number=20)
    rows = [
        ("skimage hough_line (1-px rho, 180 angles)", skimage_t, ""),
        ("ours, points, drho=2 (paper)", paper_t,
         f"target <= 1.0x skimage: {'met' if paper_t <= skimage_t else 'NOT met'}"),
        ("ours, points, drho=2, numpy path (previous)", numpy_t, ""),
        ("ours, points, drho=1, corner origin", best_of(lambda: hough_transform(pts, frames.shape, 1.0, origin="corner"), repeats=5, number=20), ""),
        ("ours, binary image, drho=2", best_of(lambda: hough_transform_image(img), repeats=5, number=20), ""),
        ("ours, rotate-and-integrate (Fig. 11)", best_of(lambda: rotate_integrate_hough(img), repeats=2), ""),
    ]
    base = rows[0][1]
    kernel = "compiled kernel (numba)" if _fast_hough.numba_enabled() else "numpy path (numba missing or off)"
    print(f"Hough transform of a 256x256 composite of 21 frames ({len(pts)} points); voting: {kernel}")
    print(f"{'method':45s} {'time (ms)':>10s} {'ratio to skimage':>17s}")
    for name, t, note in rows:
        print(f"{name:45s} {1e3 * t:10.3f} {t / base:17.2f}  {note}")
    fast_votes = hough_transform(pts, frames.shape)[0]
    with numpy_only():
        numpy_votes = hough_transform(pts, frames.shape)[0]
    same = bool(np.array_equal(fast_votes, numpy_votes))
    print(f"compiled / numpy path: {paper_t / numpy_t:.2f}x; "
          f"same votes cell for cell: {'yes' if same else 'NO'}")
    if not same:
        raise SystemExit("the compiled voting differs from the numpy voting")


def straight_scene(rng, n_targets, times):
    trajs = []
    for _ in range(n_targets):
        start = rng.uniform(30, 226, 2)
        head = rng.uniform(0, 2 * np.pi)
        speed = rng.uniform(10, 30)
        trajs.append(BoostTrajectory(-1.0, start, speed * np.array([np.cos(head), np.sin(head)]), np.zeros(2)))
    return trajs, render_frames(trajs, times, rng, n_noise=5)


def true_line(tr, times, shape):
    """(rho, theta_deg) of a straight trajectory, rho from the image centre."""
    v = tr.velocity(times[0])
    th = np.arctan2(v[0], -v[1]) % np.pi  # normal to the direction of motion, in [0, pi)
    n = np.array([np.cos(th), np.sin(th)])
    rho = (tr.position(times[0]) - np.array([shape[1] / 2, shape[0] / 2])) @ n
    return float(rho), float(np.rad2deg(th))


def bench_scaling():
    times = frame_times(21, 0.25)
    print("\nInitiator against the number of targets (21 frames, 5 false pixels per frame)")
    print(f"{'targets':>8s} {'points':>7s} {'vote (ms)':>10s} {'peaks (ms)':>11s} {'estimate (ms)':>14s} "
          f"{'per target (ms)':>16s}")
    for n in (1, 5, 10, 20, 50, 100, 200):
        trajs, fr = straight_scene(np.random.default_rng(n), n, times)
        init = TrackInitiator()
        comp = fr.composite()
        H, r, t = init.hough(fr.points, fr.shape)
        lines = [true_line(tr, times, fr.shape) for tr in trajs]

        def est_stage():
            for rho, th in lines:
                estimate_track(comp, fr.shape, rho, th, frame_time=0.25, n_frames=21)

        t_vote = best_of(lambda: init.hough(fr.points, fr.shape), repeats=5, number=5)
        t_peak = best_of(lambda: detect_peaks(H, r, t, min_votes=6), repeats=5, number=5)
        t_est = best_of(est_stage, repeats=5, number=2)
        print(f"{n:8d} {len(comp):7d} {1e3 * t_vote:10.2f} {1e3 * t_peak:11.2f} {1e3 * t_est:14.2f} "
              f"{1e3 * t_est / n:16.3f}")
    print("vote: Eq. (1) for every point of the composite (linear in points, the optical processor's is constant);")
    print("peaks: ratio rule on the fixed 183 x 180 plane; estimate: one strip projection per target (Sec. III).")


if __name__ == "__main__":
    bench_transform()
    bench_scaling()
