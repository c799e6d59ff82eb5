"""The sensitivity study of the Table 1 chapter: Table 1 under other readings of the paper.

The paper pins neither the unit of the distance tensor D, nor the details of the update rule,
nor the law of the measurement noise. A *reading* fixes all three; the study runs the paper's
simulations under each reading of a grid and judges each against Table 1 with the chapter's
criterion (:mod:`projtrack.experiments.neuralnet.criterion`):

* :data:`SENSITIVITY_RULES`: the update rules of the grid and their options of
  :func:`projtrack.experiments.neuralnet.simulate`;
* :func:`sensitivity_readings`: the grid of readings (rule, noise law, unit);
* :func:`sensitivity_seed`: the seed of one cell (reading x noise level);
* :func:`sensitivity_study`: every cell run (noise-free cells shared across noise laws), as a
  table of how its runs end (:data:`MODES`);
* :func:`sensitivity_table`: the same as shares, with their tolerances;
* :func:`sensitivity_verdicts`: one row per reading, its probability of a ten-run table at least
  as good as the paper's, and of failures like the paper's;
* :func:`plot_readings`: the readings' figure.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
import pandas as pd

from projtrack._validation import as_int, as_probability, as_real
from projtrack.tolerance import EXACT, Tolerance, share, statistical

from .criterion import mode_probability, p_table, rate_ci, stable_up
from .studies import sensitivity_cells
from .table1 import MODES

__all__ = ["SENSITIVITY_RULES", "sensitivity_readings", "sensitivity_seed", "sensitivity_study",
           "sensitivity_verdicts", "sensitivity_table", "plot_readings"]

#: The update rules of the grid (name -> options of ``simulate``); a rule's position is its seed id.
SENSITIVITY_RULES: dict[str, dict[str, Any]] = {
    "as printed": {},
    "no self term": {"self_coupling": False},
    "exact energy change": {"exact_energy": True},
    "parallel updates": {"mode": "parallel"},
}

_SEED = 3000


def _units(units: object, name: str, empty: bool = False) -> list[int]:
    if isinstance(units, (str, bytes)) or not hasattr(units, "__iter__"):
        raise TypeError(f"{name} must be a sequence of ints, got {type(units).__name__}")
    out = [as_int(u, f"{name}[{j}]", minimum=1) for j, u in enumerate(units)]
    if not out and not empty:
        raise ValueError(f"{name} must not be empty")
    return out


def _laws(laws: object) -> list[str]:
    if isinstance(laws, str) or not hasattr(laws, "__iter__"):
        raise TypeError(f"laws must be a sequence of noise-law names, got {type(laws).__name__}")
    laws = list(laws)
    if not laws or not all(isinstance(law, str) for law in laws) or len(set(laws)) != len(laws):
        raise ValueError(f"laws must be distinct noise-law names, got {laws!r}")
    return laws


def sensitivity_readings(units: Sequence[int], fine_units: Sequence[int], laws: Sequence[str],
                         coarse_units: Sequence[int] = (256, 1024, 16384), parallel_unit: int = 256
                         ) -> list[tuple[str, int, str, dict[str, Any]]]:
    """The grid of readings: ``(label, unit, noise_law, options)`` per reading.

    Parameters
    ----------
    units : sequence of int
        Units of D (pixels) for every rule under the first law (``laws[0]``, the ball).
    fine_units : sequence of int
        Extra units of the rule as printed, under every law.
    laws : sequence of str
        The noise laws; the first one is the paper's (the other rules run under it only).
    coarse_units : sequence of int
        The units of ``units`` the rule as printed runs under the other laws.
    parallel_unit : int
        The one unit of the parallel update (first law).

    Returns
    -------
    list of (label, unit, noise_law, options)
        ``label`` is ``"<rule>, <law>, unit <unit>"`` (the rule, a key of
        :data:`SENSITIVITY_RULES`, before the first comma). First the rule as printed, law by
        law over the sorted units; then the other rules under the first law; last the parallel
        update.
    """
    units = _units(units, "units")
    fine = _units(fine_units, "fine_units", empty=True)
    coarse = _units(coarse_units, "coarse_units", empty=True)
    laws = _laws(laws)
    parallel_unit = as_int(parallel_unit, "parallel_unit", minimum=1)
    out = [(f"as printed, {law}, unit {u}", u, law, {}) for law in laws
           for u in sorted(set(units if law == laws[0] else coarse) | set(fine))]
    out += [(f"{name}, {laws[0]}, unit {u}", u, laws[0], dict(SENSITIVITY_RULES[name]))
            for name in ["no self term", "exact energy change"] for u in units]
    out.append((f"parallel updates, {laws[0]}, unit {parallel_unit}", parallel_unit, laws[0],
                dict(SENSITIVITY_RULES["parallel updates"])))
    return out


def sensitivity_seed(rule: str, unit: int, law_index: int, level_index: int, noise_percent: float) -> list[int]:
    """The seed of one cell: ``[3000, rule id, unit, law index, level index]``.

    A noise-free cell does not depend on the noise law: its seed is ``[3000, rule id, unit, 0, 0]``
    whatever the law and level index. The rule id is the rule's position in
    :data:`SENSITIVITY_RULES`.
    """
    if rule not in SENSITIVITY_RULES:
        raise ValueError(f"rule must be one of {list(SENSITIVITY_RULES)}, got {rule!r}")
    rule_id = list(SENSITIVITY_RULES).index(rule)
    unit = as_int(unit, "unit", minimum=1)
    if float(noise_percent) == 0.0:
        return [_SEED, rule_id, unit, 0, 0]
    return [_SEED, rule_id, unit, as_int(law_index, "law_index", minimum=0),
            as_int(level_index, "level_index", minimum=0)]


def sensitivity_study(readings: Sequence[tuple[str, int, str, dict[str, Any]]], noise_levels: Sequence[float],
                      laws: Sequence[str], n_runs: int, chunk: int) -> pd.DataFrame:
    """Successes and wrong convergences of ``n_runs`` simulations per reading and noise level.

    Each cell (reading x noise level) is
    :func:`projtrack.experiments.neuralnet.sensitivity_cell` seeded by :func:`sensitivity_seed`
    (``law_index`` the law's position in ``laws``); noise-free cells of one rule and unit are run
    once (under the first law) and shared by every reading. The nets of all cells of one rule
    run as one batch (:func:`projtrack.experiments.neuralnet.sensitivity_cells`).

    Parameters
    ----------
    readings : sequence of (label, unit, noise_law, options)
        As from :func:`sensitivity_readings`; the rule is the label before its first comma.
    noise_levels : sequence of float
        Noise levels (percent).
    laws : sequence of str
        The noise laws (their order gives the seeds).
    n_runs, chunk : int
        Simulations per cell and per Monte Carlo trial (``chunk`` divides ``n_runs``).

    Returns
    -------
    pandas.DataFrame
        One row per reading and level, in the order of ``readings`` then ``noise_levels``:
        ``reading``, ``rule``, ``noise law``, ``unit (px)``, ``noise %``, ``runs`` and the number
        of runs ending in each of :data:`MODES` (``correct`` is
        the paper's success, ``wrong`` a convergence to a wrong state).
    """
    laws = _laws(laws)
    levels = [as_real(n, f"noise_levels[{j}]", 0.0) for j, n in enumerate(noise_levels)]
    if not levels:
        raise ValueError("noise_levels must not be empty")
    n_runs = as_int(n_runs, "n_runs", minimum=1)
    readings = list(readings)
    if not readings:
        raise ValueError("readings must not be empty")
    for j, r in enumerate(readings):
        if not isinstance(r, (tuple, list)) or len(r) != 4 or not isinstance(r[0], str):
            raise ValueError(f"readings[{j}] must be (label, unit, noise_law, options), got {r!r}")
        if r[2] not in laws:
            raise ValueError(f"readings[{j}]: noise law {r[2]!r} is not one of laws {laws}")

    def key(label: str, u: int, n: float) -> tuple:
        return (label.split(",")[0], u) if n == 0.0 else (label, n)

    cells: dict[tuple, tuple] = {}
    for label, u, law, kw in readings:
        rule = label.split(",")[0]
        for i, n in enumerate(levels):
            if key(label, u, n) not in cells:
                seed = sensitivity_seed(rule, u, laws.index(law), i, n)
                cells[key(label, u, n)] = (n, u, laws[0] if n == 0.0 else law, kw, seed)
    counts = dict(zip(cells, sensitivity_cells(list(cells.values()), n_runs, chunk)))
    rows = []
    for label, u, law, kw in readings:
        for n in levels:
            c = counts[key(label, u, n)]
            rows.append({"reading": label, "rule": label.split(",")[0], "noise law": law, "unit (px)": u,
                         "noise %": n, "runs": n_runs, **{m: c[m] for m in MODES}})
    return pd.DataFrame(rows)


def _verdict_numbers(correct: Sequence[int], wrong: Sequence[int], cycles: Sequence[int], wander: Sequence[int],
                     n_runs: int, paper_k: Sequence[int]) -> dict[str, float]:
    """The criterion's numbers of one reading from its counts per noise level."""
    p_hat = [k / n_runs for k in correct]
    w_hat = [k / n_runs for k in wrong]
    fail_rows = [j for j, k in enumerate(paper_k) if k < 10]
    n_fail = sum(n_runs - correct[j] for j in fail_rows)
    if n_fail:
        q = sum(cycles[j] for j in fail_rows) / n_fail
        w = sum(wander[j] for j in fail_rows) / n_fail
        modes = mode_probability(q, w)
    else:
        modes = float("nan")
    return {"P(table >= paper's)": p_table(p_hat, paper_k),
            "at 95% high": p_table([rate_ci(int(k), n_runs)[1] for k in correct], paper_k),
            "P(... and no wrong stop)": p_table(p_hat, paper_k, w_hat),
            "P(paper's failure modes)": modes}


def sensitivity_verdicts(sens: pd.DataFrame, paper_k: Sequence[int], p_min: float = 0.05
                         ) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """Each reading judged against the paper's Table 1 and its account of the failures.

    Parameters
    ----------
    sens : pandas.DataFrame
        The table of :func:`sensitivity_study`.
    paper_k : sequence of int
        The paper's successes out of ten, one per noise level of ``sens``.
    p_min : float
        The criterion's threshold on the probability of a table at least as good as the paper's.

    Returns
    -------
    verdicts : pandas.DataFrame
        One row per reading (in the order of ``sens``): ``reading``, ``P(table >= paper's)``
        (:func:`~projtrack.experiments.neuralnet.p_table` at the estimated success rates),
        ``at 95% high`` (at the upper ends of their 95% intervals), ``P(... and no wrong stop)``
        (also no run converging to a wrong state), ``reproduces Table 1`` (the probability at the
        upper ends at least ``p_min``: judged at the most favourable rates the runs allow), ``P(paper's failure modes)``
        (:func:`~projtrack.experiments.neuralnet.mode_probability` of the failures pooled over the
        levels where the paper has failures; NaN without failures) and ``failure modes seen`` (it
        at least ``p_min``).
    tolerance : dict of str to Tolerance
        For the probability columns: the largest change any one run changing its outcome (in
        any cell of any reading) makes to the column.
    """
    if not isinstance(sens, pd.DataFrame):
        raise TypeError(f"sens must be a pandas.DataFrame, got {type(sens).__name__}")
    missing = {"reading", "noise %", "runs", *MODES} - set(sens.columns)
    if missing:
        raise ValueError(f"sens lacks the columns {sorted(missing)}")
    p_min = as_probability(p_min, "p_min")
    paper_k = [as_int(k, "paper_k", minimum=0, maximum=10) for k in paper_k]
    verdicts, steps = [], {}
    for label, s in sens.groupby("reading", sort=False):
        if len(s) != len(paper_k):
            raise ValueError(f"reading {label!r} has {len(s)} noise levels, paper_k has {len(paper_k)}")
        n_runs = int(s["runs"].iloc[0])
        counts = [s[m].astype(int).tolist() for m in ("correct", "wrong", "cycle with the truth", "wandering")]
        num = _verdict_numbers(*counts, n_runs, paper_k)
        # one run changing its outcome: a count goes up or down by one in one cell
        for c in range(4):
            for j in range(len(paper_k)):
                for d in (-1, 1):
                    moved = [list(x) for x in counts]
                    moved[c][j] += d
                    if not 0 <= moved[c][j] <= n_runs:
                        continue
                    other = _verdict_numbers(*moved, n_runs, paper_k)
                    for key, v in num.items():
                        if np.isfinite(v) and np.isfinite(other[key]):
                            steps[key] = max(steps.get(key, 0.0), abs(other[key] - v))
        verdicts.append({"reading": label, **{k: num[k] for k in list(num)[:3]},
                         "reproduces Table 1": bool(num["at 95% high"] >= p_min),
                         "P(paper's failure modes)": num["P(paper's failure modes)"],
                         "failure modes seen": bool(num["P(paper's failure modes)"] >= p_min)})
    tolerance = {key: statistical(atol=stable_up(max(step, 1e-12)),
                                  why="one run changing its outcome in any cell moves this probability by at most "
                                      "this much (largest change over the readings, rounded up to one digit)")
                 for key, step in steps.items()}
    for key in ("P(table >= paper's)", "at 95% high", "P(... and no wrong stop)", "P(paper's failure modes)"):
        tolerance.setdefault(key, statistical(atol=1e-12, why="no count can move it"))
    return pd.DataFrame(verdicts), tolerance


def sensitivity_table(sens: pd.DataFrame) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """The shares of runs ending in each mode, per reading and noise level, and their tolerances.

    Parameters
    ----------
    sens : pandas.DataFrame
        The table of :func:`sensitivity_study`.

    Returns
    -------
    table : pandas.DataFrame
        ``reading``, ``noise %`` and ``<mode> %`` for each of
        :data:`MODES` (``correct %`` is the success rate).
    tolerance : dict of str to Tolerance
        A share of ``runs`` runs: one run changing its outcome moves it by ``100 / runs`` points.
    """
    if not isinstance(sens, pd.DataFrame):
        raise TypeError(f"sens must be a pandas.DataFrame, got {type(sens).__name__}")
    missing = {"reading", "noise %", "runs", *MODES} - set(sens.columns)
    if missing:
        raise ValueError(f"sens lacks the columns {sorted(missing)}")
    n = int(sens["runs"].min())
    table = sens[["reading", "noise %"]].copy()
    for m in MODES:
        table[f"{m} %"] = 100 * sens[m] / sens["runs"]
    return table, {"noise %": EXACT, "*": share(n, percent=True)}


# ----------------------------------------------------------------------------- figures


def plot_readings(shares, verdicts, paper: Sequence[float], units: Sequence[int], p_min: float = 0.05):
    """The readings of the net as printed: (a) success against noise for each unit (ball noise),
    (b) runs stopping at a wrong assignment, (c) the criterion's probability against the unit for
    the three noise laws.

    Parameters
    ----------
    shares : pandas.DataFrame
        :func:`~projtrack.experiments.neuralnet.sensitivity_table` (``reading``, ``noise %``,
        ``correct %``, ``wrong %``).
    verdicts : pandas.DataFrame
        :func:`~projtrack.experiments.neuralnet.sensitivity_verdicts`.
    paper : sequence of float
        The paper's success (%) per noise level.
    units : sequence of int
        The units of panels (a) and (b).
    """
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(6.4, 6.4))
    gs = fig.add_gridspec(2, 2, height_ratios=[1, 1], hspace=0.75, wspace=0.3)
    ax_a, ax_b, ax_c = fig.add_subplot(gs[0, 0]), fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, :])
    colours = plt.get_cmap("viridis")(np.linspace(0, 0.9, len(units)))
    noise = None
    for u, col in zip(units, colours):
        s = shares[shares["reading"] == f"as printed, ball, unit {u}"]
        noise = s["noise %"].to_numpy()
        ax_a.plot(noise, s["correct %"], "o-", ms=3, color=col, label=f"{u} px")
        ax_b.plot(noise, s["wrong %"], "o-", ms=3, color=col)
    ax_a.plot(noise, paper, "*", color="C3", ms=11, label="paper")
    ax_b.plot(noise, [0] * len(noise), "*", color="C3", ms=11)
    for ax, title in [(ax_a, "(a) correct"), (ax_b, "(b) stopped wrong")]:
        ax.set_xlabel("noise, %")
        ax.set_ylim(-3, 103)
        ax.set_xticks(noise)
        ax.set_title(title)
    ax_a.set_ylabel("runs, %")
    fig.legend(*ax_a.get_legend_handles_labels(), frameon=False, ncol=5, loc="center", bbox_to_anchor=(0.5, 0.47),
               handlelength=1.2, columnspacing=0.8)
    floor = 1e-12
    for law, mk in zip(["ball", "radial", "coordinate"], ["o", "s", "^"]):
        r = verdicts[verdicts["reading"].str.startswith(f"as printed, {law},")]
        us = [int(v.rsplit(" ", 1)[1]) for v in r["reading"]]
        ax_c.plot(us, np.maximum(r["at 95% high"], floor), marker=mk, ms=4, label=f"{law} noise")
    ax_c.axhline(p_min, color="0.4", lw=0.9, ls="--", label=f"criterion {p_min:g}")
    ax_c.set_xscale("log"); ax_c.set_yscale("log")
    ax_c.set_ylim(floor / 3, 3)
    ax_c.set_xlabel("unit of D (pixels)")
    ax_c.set_ylabel("P(table $\\geq$ paper's)")
    ax_c.set_title(f"(c) at the upper 95% ends of the rates; below {floor:g} drawn at {floor:g}")
    ax_c.legend(frameon=False, loc="upper left", ncol=2)
    return fig
