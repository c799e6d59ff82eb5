"""Association time per scan on real pedestrians and on a dense crowd: exact beta vs Stone Soup's EHM.

The association problems (one scan's detections, the tracks' predicted measurements and
innovation covariances) come from the book's JPDA tracker run on the two real sequences
that ``motmetrics`` ships (TUD-Campus, TUD-Stadtmitte; their ``test.txt`` as detections,
and one draw of noisy annotations with misses and clutter, the page's "base" setting),
and from a dense synthetic crowd: 100 targets uniform in a centred region of the 640 x 480
image, shrunk step by step, with 30 false detections per frame over the image
(``projtrack.experiments.jpda.crowd_scan``). On each problem, in the same run:

* ``beta``: ``projtrack.jpda.beta`` on the MVM (independent clusters, then the
  forward-backward sweep on each; cost ``2^min(m_c, T_c)`` per cluster); it refuses
  clusters with ``min(m_c, T_c) > 26`` (shown as "refused");
* ``EHM`` (the baseline): Stone Soup's ``JPDAwithEHM`` on hypotheses generated beforehand,
  so both times cover the association only.

Both give the same beta (the largest difference is printed). Best of three calls per
scan; the ratio is EHM / beta (above 1: the sweep is faster), as the median of the
per-scan ratios and as the ratio of the summed times. Run: ``python benchmarks/bench_pedestrians.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from projtrack.datasets import SEQUENCES, load_mot_sequence
from projtrack.experiments import jpda as ex

REGIONS = [(640, 480), (320, 240), (240, 180), (200, 150), (160, 120)]
N_CROWD_SCANS = 5


def sequence_problems() -> dict[str, tuple[list, object]]:
    out = {}
    for name in SEQUENCES:
        gt, test = load_mot_sequence(name, "gt"), load_mot_sequence(name, "test")
        model = ex.shipped_model(gt, test)
        run = ex.track_sequence(ex.shipped_detections(test), model, "jpda", record=True)
        out[f"{name}, test.txt"] = (run.problems, model)
        model = ex.gt_model(gt, "base")
        scans = ex.synthetic_detections(gt, np.random.default_rng(2027), **ex.pedestrians.SETTINGS["base"])
        run = ex.track_sequence(scans, model, "jpda", record=True)
        out[f"{name}, noisy annotations"] = (run.problems, model)
    return out


def summary(label: str, t: pd.DataFrame) -> dict:
    ok = t["beta [s]"].notna()
    ratio = t.loc[ok, "Stone Soup EHM [s]"] / t.loc[ok, "beta [s]"]
    return {"scans": label, "n": len(t), "T (median)": float(t["T"].median()),
            "largest cluster": int(t["largest cluster"].max()), "refused": int((~ok).sum()),
            "beta median [ms]": 1e3 * float(t.loc[ok, "beta [s]"].median()) if ok.any() else np.nan,
            "EHM median [ms]": 1e3 * float(t["Stone Soup EHM [s]"].median()),
            "EHM/beta median": float(ratio.median()) if ok.any() else np.nan,
            "EHM/beta total": float(t.loc[ok, "Stone Soup EHM [s]"].sum() / t.loc[ok, "beta [s]"].sum())
            if ok.any() else np.nan,
            "max |diff|": float(t["max |diff|"].max())}


def main() -> None:
    warnings.simplefilter("ignore")
    rows = []
    for label, (problems, model) in sequence_problems().items():
        rows.append(summary(label, ex.time_association(problems, model)))
        print(rows[-1], flush=True)
    gt = load_mot_sequence("TUD-Stadtmitte")
    model = ex.gt_model(gt, "base")
    crowd = []
    for region in REGIONS:
        rng = np.random.default_rng(7)
        problems = [ex.crowd_scan(rng, model, 100, region, 30.0) for _ in range(N_CROWD_SCANS)]
        t = ex.time_association(problems, model)
        rows.append(summary(f"crowd of 100 in {region[0]} x {region[1]}", t))
        crowd.append(t.assign(region=f"{region[0]} x {region[1]}"))
        print(rows[-1], flush=True)
    table = pd.DataFrame(rows)
    fmt = {"float_format": lambda v: f"{v:.3g}", "index": False}
    print()
    print("Association time per scan, best of 3 (ratio EHM / beta: above 1, the sweep is faster)")
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(table.to_string(**fmt))
        crowd = pd.concat(crowd, ignore_index=True).sort_values("largest cluster", kind="stable")
        crowd["beta [ms]"] = 1e3 * crowd.pop("beta [s]")
        crowd["EHM [ms]"] = 1e3 * crowd.pop("Stone Soup EHM [s]")
        crowd["EHM/beta"] = crowd["EHM [ms]"] / crowd["beta [ms]"]
        print("\nCrowd scans by their largest cluster (the sweep costs 2^min(m_c, T_c) per cluster; "
              "NaN: refused above 26)")
        print(crowd[["region", "m", "T", "largest cluster", "beta [ms]", "EHM [ms]", "EHM/beta", "max |diff|"]]
              .to_string(**fmt))


if __name__ == "__main__":
    main()
