"""The book's overview pages: what reproduces, by part and by chapter.

Built on :func:`projtrack.scorecard.summary` (one line per inventory id, counted once, with
the weakest verdict of its rows): the counts of the landing page's three-line answer
(:func:`what_reproduces`), the figure of every verdict by chapter (:func:`plot_verdicts`)
and the per-chapter tables of the Reproducibility summary page (:func:`items_html`).
"""

from __future__ import annotations

import html

from projtrack.scorecard import _CELL, _HEAD, _TABLE_STYLE, COLOURS, REPRODUCTION_VERDICTS, VERDICTS, badge

__all__ = ["what_reproduces", "plot_verdicts", "items_html"]


def what_reproduces(items) -> dict[str, dict[str, int]]:
    """Counts of inventory ids per verdict, for each book part and for the whole book.

    Parameters
    ----------
    items : pandas.DataFrame
        The first table of :func:`summary`.

    Returns
    -------
    dict
        ``{"Part I": {"ids": n, "reproduced": n, ...}, ..., "all": {...}}``: per part the
        number of ids and of each verdict (``"not yet covered"`` for ids without rows).
    """
    out: dict[str, dict[str, int]] = {}
    for part, group in [*items.groupby("part", sort=False), ("all", items)]:
        verdicts = group["verdict"].replace("", "not yet covered")
        out[part] = {"ids": int(len(group)), **{v: int((verdicts == v).sum()) for v in (*VERDICTS, "not yet covered")}}
    return out


def plot_verdicts(items):
    """A bar per chapter: how many of its inventory ids got each verdict (one count per id).

    Parameters
    ----------
    items : pandas.DataFrame
        The first table of :func:`summary`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.ticker import MaxNLocator

    from projtrack.inventory import PARTS

    prefixes = list(PARTS)
    chapter = items["id"].str.split("-").str[0]
    order = [*REPRODUCTION_VERDICTS, "beyond", ""]
    per = (items.assign(chapter=chapter).pivot_table(index="chapter", columns="verdict", values="id",
                                                     aggfunc="count", fill_value=0)
           .reindex(index=prefixes, columns=order, fill_value=0))
    colours = {**COLOURS, "": "#ffffff"}
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    y = np.arange(len(prefixes))[::-1]
    left = np.zeros(len(prefixes))
    for v in order:
        n = per[v].to_numpy()
        if not n.any():
            continue
        label = {"": "not yet covered", "beyond": "beyond (whole id)"}.get(v, v)
        ax.barh(y, n, left=left, color=colours[v], edgecolor="black", linewidth=0.4, label=label)
        for yi, li, ni in zip(y, left, n):
            if ni:
                ax.text(li + ni / 2, yi, str(ni), ha="center", va="center", fontsize=9,
                        color="white" if v in ("reproduced", "differs", "misprint", "not-reproducible") else "black")
        left += n
    ax.set_yticks(y, [f"{p} ({PARTS[p][0]})" for p in prefixes])
    ax.set_xlabel("inventory ids (each counted once)")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.legend(loc="upper center", bbox_to_anchor=(0.45, -0.22), ncol=3, frameon=False)
    fig.tight_layout()
    return fig


class _Rec:
    def __init__(self, d: dict):
        self.__dict__.update(d)


def items_html(items, prefix: str) -> str:
    """One chapter's inventory ids as an HTML table: id (linked to its page), what it is, the
    paper's value, ours (from the id's headline row) and the id's verdict badge, with the
    verdicts of its sub-rows beside it; folded under a line that counts the verdicts.

    Parameters
    ----------
    items : pandas.DataFrame
        The first table of :func:`summary`.
    prefix : str
        The chapter's id prefix (``"KVW"``).
    """
    group = items[items["id"].str.split("-").str[0] == prefix]
    if group.empty:
        raise ValueError(f"no inventory id with prefix {prefix!r}")
    head = "".join(f"<th {_HEAD}>{h}</th>" for h in ("id", "item", "paper", "ours", "verdict"))
    body = []
    for rec in group.to_dict("records"):
        r = _Rec(rec)
        nbs = [n for n in r.notebook.split("; ") if n]
        ident = html.escape(r.id)
        if nbs:
            ident = f'<a href="{html.escape(nbs[0].removesuffix(".ipynb"))}.html">{ident}</a>'
        verdict = badge(r.verdict) if r.verdict else "<em>not yet covered</em>"
        subs = rec.get("sub-row verdicts", "")
        if subs:
            verdict += f'<div style="color:#666;font-size:0.8em;margin-top:0.2em">rows: {html.escape(subs)}</div>'
        body.append("<tr>" + "".join(f"<td {_CELL}>{v}</td>" for v in (
            f"<code>{ident}</code>", html.escape(r.item), html.escape(r.paper), html.escape(r.ours), verdict))
                    + "</tr>")
    table = f'<table class="pt-items" {_TABLE_STYLE}><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'
    counts: dict[str, int] = {}
    for v in group["verdict"].fillna(""):
        counts[v or "not yet covered"] = counts.get(v or "not yet covered", 0) + 1
    tally = ", ".join(f"{n} {v}" for v, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))
    return ('<details class="pt-items-fold"><summary style="cursor:pointer">'
            f"<strong>{len(group)} items</strong>: {html.escape(tally)} (open for each item's values)"
            f"</summary>{table}</details>")
