"""Obtain OpenCV's sample video ``vtest.avi`` from Debian and write the plaza excerpt.

The KL chapter (Vermeulen & Casasent, Fig. 2-3) uses a 24-frame sequence of people walking,
128x128 pixels, 8-bit grey, one frame per second.  OpenCV's sample video ``vtest.avi``
(795 frames, 768x576, 10 fps, fixed camera, pedestrians crossing a plaza) is the same kind of
scene.  Debian's ``opencv-doc`` package ships it; this script

1. runs ``apt-get download opencv-doc`` and ``dpkg-deb -x`` in a temporary directory
   (no root needed; run ``apt-get update`` first if the package lists are missing),
2. decodes ``vtest.avi`` with ``cv2`` (opencv-python-headless from PyPI),
3. keeps one frame per second (every 10th frame, starting at frame 0), converts it to grey,
   takes the centred 576x576 square and resizes it to 128x128 (``cv2.INTER_AREA``),
4. picks the 24-frame window by the rule stated in advance in ``plaza-excerpt.md``
   (implemented in :func:`choose_window`), and
5. writes ``src/projtrack/data/plaza-excerpt.npz`` (uint8 frames + provenance fields).

Usage: ``.venv/bin/python tools/fetch_plaza_video.py [--out PATH] [--deb PATH]``.
"""
from __future__ import annotations

import argparse
import hashlib
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "src" / "projtrack" / "data" / "plaza-excerpt.npz"
FPS = 10            # frame rate of vtest.avi
STEP = 10           # keep one frame per second
N_WINDOW = 24       # frames in the excerpt (the paper's sequence length)
ENTRY_INDEX = 7     # 0-based position of the entering person in the window (paper: frame 8)
SIZE = 128
# Window rule constants (fixed before the novelty filter was ever run on the video).
FG_DIFF = 30        # grey-level difference from the median background that counts as "changed"
FG_ROWS = 0.5       # the foreground is the lower half of the 128x128 crop (nearest the camera)
FG_FRACTION = 0.02  # a person "is in the foreground" when > 2 % of the lower half changed


def download_vtest(workdir: pathlib.Path, deb: pathlib.Path | None = None) -> pathlib.Path:
    """Download (or use ``deb``) the opencv-doc package, unpack it, return vtest.avi's path."""
    if deb is None:
        done = subprocess.run(["apt-get", "download", "opencv-doc"], cwd=workdir)
        if done.returncode != 0:
            raise SystemExit("apt-get download opencv-doc failed; run `apt-get update` once "
                             "(the package lists may be missing) and try again")
        debs = sorted(workdir.glob("opencv-doc_*.deb"))
        if not debs:
            raise SystemExit("apt-get download opencv-doc produced no .deb (run apt-get update?)")
        deb = debs[-1]
    subprocess.run(["dpkg-deb", "-x", str(deb), str(workdir / "x")], check=True)
    hits = sorted((workdir / "x").rglob("vtest.avi"))
    if not hits:
        raise SystemExit(f"vtest.avi not found in {deb}")
    return hits[0]


def decode_one_per_second(path: pathlib.Path) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
    """Decode every STEP-th frame, grey, centre square crop, resize to SIZE x SIZE (uint8)."""
    import cv2

    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise SystemExit(f"cv2 cannot open {path}")
    frames, index, k, shape = [], [], 0, None
    while True:
        ok, bgr = cap.read()
        if not ok:
            break
        if k % STEP == 0:
            grey = cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY)
            h, w = grey.shape
            shape = (h, w)
            s = min(h, w)
            r0, c0 = (h - s) // 2, (w - s) // 2
            square = grey[r0:r0 + s, c0:c0 + s]
            frames.append(cv2.resize(square, (SIZE, SIZE), interpolation=cv2.INTER_AREA))
            index.append(k)
        k += 1
    cap.release()
    return np.stack(frames).astype(np.uint8), np.asarray(index), shape + (k,)


def foreground_activity(frames: np.ndarray) -> np.ndarray:
    """Fraction of lower-half pixels differing from the temporal median by more than FG_DIFF."""
    background = np.median(frames.astype(float), axis=0)
    rows = slice(int(SIZE * (1 - FG_ROWS)), SIZE)
    diff = np.abs(frames[:, rows].astype(float) - background[rows])
    return (diff > FG_DIFF).mean(axis=(1, 2))


def choose_window(frames: np.ndarray) -> tuple[int, int]:
    """The window rule (stated in plaza-excerpt.md before any filtering was run).

    Scan the one-per-second frames in time order.  The first second ``t`` with
    ``t >= ENTRY_INDEX`` whose foreground activity exceeds ``FG_FRACTION`` while the
    previous second's did not is the "entry" second; the window starts ``ENTRY_INDEX``
    seconds earlier, so the entering person appears in frame 8 (1-based) as in the paper.
    Returns ``(start, entry)`` in one-per-second sample indices.
    """
    act = foreground_activity(frames)
    for t in range(ENTRY_INDEX, len(frames) - (N_WINDOW - ENTRY_INDEX) + 1):
        if act[t] > FG_FRACTION and act[t - 1] <= FG_FRACTION:
            return t - ENTRY_INDEX, t
    raise SystemExit("no window satisfies the rule")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=pathlib.Path, default=OUT)
    p.add_argument("--deb", type=pathlib.Path, default=None, help="use this opencv-doc .deb")
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        avi = download_vtest(tmp, args.deb)
        sha = hashlib.sha256(avi.read_bytes()).hexdigest()
        debname = (args.deb.name if args.deb else sorted(tmp.glob("opencv-doc_*.deb"))[-1].name)
        frames, index, (h, w, n_total) = decode_one_per_second(avi)
    start, entry = choose_window(frames)
    sel = slice(start, start + N_WINDOW)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(
        args.out,
        frames=frames[sel],
        source_frame_index=index[sel],
        entry_position=np.int64(entry - start),
        source=np.str_(f"vtest.avi from Debian package {debname}"),
        vtest_sha256=np.str_(sha),
        source_shape=np.asarray([n_total, h, w]),
    )
    print(f"decoded {n_total} frames of {w}x{h}; one per second: {len(frames)}")
    print(f"window: seconds {start}..{start + N_WINDOW - 1} (source frames "
          f"{index[start]}..{index[start + N_WINDOW - 1]}), entry at second {entry}")
    print(f"wrote {args.out} ({args.out.stat().st_size} bytes), vtest.avi sha256 {sha}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
