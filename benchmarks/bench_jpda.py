"""Wall-clock time of exact JPDA beta on fully gated m = T = n problems (Fisher & Casasent 1989).

Methods: the conventional enumeration of feasibility matrices (``beta_enumerated``, the
baseline), the paper's fast MU-word algorithm (``beta_paper``), the clustered
forward-backward method (``beta``, the package default), and two exact peers from
Stone Soup: ``JPDA`` (joint-hypothesis enumeration) and ``JPDAwithEHM`` (efficient
hypothesis management), driven on the same tracks and detections, with hypothesis
generation done once outside the timing so that only the association is timed.
All methods are checked to give the same beta. Best of a few repeats; a method is
not run at a size whose time, extrapolated from the growth between the two previous
sizes, would exceed ``CAP`` seconds (the exact methods grow exponentially). Run:
``python benchmarks/bench_jpda.py``.

A second table times the exact forward-backward method at larger clusters (m = T = 16, 20,
24): the compiled sweep (numba, the default when installed) against the previous numpy
sweep (``PROJTRACK_NO_NUMBA=1``) in the same run, with the targets m = T = 20 in under
0.25 s and m = T = 24 in under 5 s (2 cores, one BLAS thread) and the largest relative
difference between the two. Wall-clock and CPU seconds (all threads) are both shown: on a
busy machine the wall-clock time of a threaded run says little; the system CPU seconds are
mostly the page faults of fresh message buffers, and the compiled sweep is checked to give
the same numbers without threads.
"""

from __future__ import annotations

import os
import time
import warnings

import numpy as np

from projtrack import jpda
from projtrack._numba import numpy_only
from projtrack.jpda import _kernel as _fast_jpda
from projtrack._peers import stonesoup_jpda

CAP = 2.5  # seconds: a method is not run at a size whose predicted time exceeds this
P_D, P_G, LAM = 0.9, 0.9999, 1e-3


def problem(n: int, rng: np.random.Generator):
    """n targets and n measurements, all inside every gate (fully gated)."""
    zp = rng.uniform(-1, 1, (n, 2))
    S = np.repeat((25.0 * np.eye(2))[None], n, axis=0)
    z = rng.uniform(-1, 1, (n, 2))
    mvm = jpda.modified_validation_matrix(z, zp, S, P_D, gate_prob=P_G, clutter_density=LAM)
    mvm[0] = 1 - P_D * P_G
    assert np.all(mvm[1:] > 0)
    return z, zp, S, mvm


def stonesoup_peer(z, zp, S, ehm: bool):
    """A Stone Soup associator with precomputed hypotheses on the same problem."""
    return stonesoup_jpda(z, zp, S, ehm=ehm, p_detect=P_D, p_gate=P_G, clutter_density=LAM,
                          precompute_hypotheses=True)


def best_time(fn, repeats: int) -> tuple[float, np.ndarray]:
    best, out = np.inf, None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
        if best > CAP / 5:
            break
    return best, out


def main() -> None:
    warnings.simplefilter("ignore")  # Stone Soup warns about Probability arithmetic
    if _fast_jpda.numba_enabled():
        _fast_jpda.warm_up()  # compile (or load numba's cache) before anything is timed
    rng = np.random.default_rng(0)
    names = ["enumerate", "paper", "auto", "stonesoup JPDA", "stonesoup EHM"]
    alive = dict.fromkeys(names, True)
    last: dict[str, list[float]] = {k: [] for k in names}
    rows = []
    for n in range(2, 21):
        z, zp, S, mvm = problem(n, rng)
        fns = {
            "enumerate": lambda: jpda.beta_enumerated(mvm),
            "paper": lambda: jpda.beta_paper(mvm),
            "auto": lambda: jpda.beta(mvm),
        }
        times = {}
        ref = None
        for name in names:
            if not alive[name]:
                times[name] = np.nan
                continue
            if name.startswith("stonesoup"):
                fn = stonesoup_peer(z, zp, S, ehm=name.endswith("EHM"))
            else:
                fn = fns[name]
            t, b = best_time(fn, 3 if n < 16 else 2)
            if ref is None:
                ref = b
            elif not np.allclose(b, ref, atol=1e-9):
                raise AssertionError(f"{name} disagrees at n = {n}")
            times[name] = t
            last[name].append(t)
            growth = max(2.0, last[name][-1] / last[name][-2]) if len(last[name]) > 1 else 2.0
            if t * growth > CAP:
                alive[name] = False
        rows.append((n, jpda.count_feasible_events(n, n), times))
        print(f"n={n:2d} " + "  ".join(f"{k}={v:.2e}" for k, v in times.items()), flush=True)
    print()
    print("Fully gated m = T = n, best wall-clock seconds; ratios are enumerate / method")
    print("(or stonesoup EHM / auto). '-' = not run (an earlier size exceeded the cap).")
    hdr = (f"{'n':>3} {'events':>14} " + " ".join(f"{k:>15}" for k in names)
           + f" {'enum/auto':>10} {'EHM/auto':>9}")
    print(hdr)
    for n, ev, t in rows:
        cells = " ".join(f"{t[k]:15.2e}" if np.isfinite(t[k]) else f"{'-':>15}" for k in names)
        r1 = t["enumerate"] / t["auto"]
        r2 = t["stonesoup EHM"] / t["auto"]
        print(f"{n:3d} {ev:14.3g} {cells} "
              + (f"{r1:10.3g}" if np.isfinite(r1) else f"{'-':>10}")
              + (f" {r2:9.3g}" if np.isfinite(r2) else f" {'-':>9}"))
    t16 = [t for n, _, t in rows if n == 16][0]["auto"]
    t20 = [t for n, _, t in rows if n == 20][0]["auto"]
    print(f"\nbeta (auto) at m = T = 16: {t16:.3f} s, at m = T = 20: {t20:.3f} s "
          "(the targets are judged in the compiled-sweep table below)")


def timed(fn, repeats: int) -> tuple[float, float, np.ndarray, float]:
    """Best wall-clock and CPU seconds of ``repeats`` calls, the result, and the system CPU
    seconds of the call with the least CPU time (mostly page faults of fresh memory)."""
    wall = cpu = np.inf
    out = None
    sys_cpu = 0.0
    for _ in range(repeats):
        t, c, s0 = time.perf_counter(), time.process_time(), os.times().system
        out = fn()
        wall = min(wall, time.perf_counter() - t)
        if time.process_time() - c < cpu:
            cpu, sys_cpu = time.process_time() - c, os.times().system - s0
    return wall, cpu, out, sys_cpu


def bench_large() -> None:
    """The exact forward-backward method at m = T = 16, 20, 24: compiled against numpy."""
    targets = {20: 0.25, 24: 5.0}
    if not _fast_jpda.numba_enabled():
        print("\nnumba missing or PROJTRACK_NO_NUMBA=1: the compiled sweep is not timed")
        return
    _fast_jpda.warm_up()  # compilation (or loading numba's cache) is not timed
    print("\nExact forward-backward beta, fully gated m = T = n: compiled sweep vs the previous numpy")
    print("sweep, same run (wall-clock and CPU seconds, of which sys: page faults; ratio = compiled")
    print("/ numpy wall-clock; 1 thread: the compiled sweep without threads gives the same numbers)")
    print(f"{'n':>3} {'compiled wall':>14} {'cpu':>8} {'sys':>6} {'numpy wall':>11} {'cpu':>8} "
          f"{'ratio':>6} {'max rel diff':>13} {'1 thread':>9}  target")
    for n in (16, 20, 24):
        mvm = problem(n, np.random.default_rng(n))[3]
        fast = timed(lambda: jpda.beta_forward_backward(mvm), 3 if n < 24 else 1)
        if n < 24:
            with numpy_only():
                slow = timed(lambda: jpda.beta_forward_backward(mvm), 2)
            rel = float(np.max(np.abs(fast[2] - slow[2]) / np.abs(slow[2])))
            same = np.array_equal(one_thread(mvm), fast[2])
            cells = (f"{slow[0]:11.3f} {slow[1]:8.3f} {fast[0] / slow[0]:6.2f} {rel:13.1e} "
                     f"{'same' if same else 'DIFFERS':>9}")
        else:  # the numpy sweep keeps all 25 messages of 2^24 doubles (3.4 GB): not run
            cells = f"{'-':>11} {'-':>8} {'-':>6} {'-':>13} {'-':>9}"
        goal = targets.get(n)
        note = (f"< {goal:g} s: {'met' if fast[0] < goal else 'NOT met'} (cpu/2 = {fast[1] / 2:.3f} s)"
                if goal else "")
        print(f"{n:3d} {fast[0]:14.3f} {fast[1]:8.3f} {fast[3]:6.2f} {cells}  {note}", flush=True)


def one_thread(mvm: np.ndarray) -> np.ndarray:
    """Exact beta by the compiled sweep run in the calling thread only."""
    old = _fast_jpda._PARALLEL_MIN_SLOTS
    _fast_jpda._PARALLEL_MIN_SLOTS = 10**6
    try:
        return jpda.beta_forward_backward(mvm)
    finally:
        _fast_jpda._PARALLEL_MIN_SLOTS = old


if __name__ == "__main__":
    main()
    bench_large()
