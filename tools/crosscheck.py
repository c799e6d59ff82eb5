"""Run the notebooks under every BLAS kernel x numpy SIMD level this CPU can run, and report.

A number that comes out of a discrete decision (k-means, EM, Viterbi, a threshold, a peak
picker) can change when the last bits of a floating-point computation change, and those
bits depend on the OpenBLAS kernel (``OPENBLAS_CORETYPE``) and on numpy's own SIMD code
paths (``NPY_DISABLE_CPU_FEATURES``). This tool re-executes every notebook under nbval,
exactly as ``make test`` does, once per configuration of the matrix

    kernels this CPU can run (tools/blas_kernels.py list)  x  numpy SIMD levels

where the SIMD levels are ``full`` (everything numpy found on this CPU), then with the
AVX-512 group of dispatch targets disabled (``no-avx512``), then with the AVX2 group
disabled too (``no-avx2``: numpy's baseline). Each configuration runs in its own process
(``--jobs`` at a time) and keeps what it produced in ``.cache/crosscheck/<config>/``.

The report (``.cache/crosscheck/report.md``, its head printed) says which configurations
passed and lists **every compared number that changed at all** against the committed book:
cells of the tables in ``figures/`` (with the tolerance declared for them and the share of it
used), numbers in the text outputs of the notebooks (those nbval compares must not move; those
of cells left out of nbval are listed so their tables can be checked), and figures whose
pixels changed (RMS). Fragile outputs are found this way on any machine, not only on the one
where they break.

Usage::

    python tools/crosscheck.py configs            # the matrix on this CPU
    python tools/crosscheck.py second             # env assignments of make test's second run
    python tools/crosscheck.py run [--jobs 2] [--kernels Haswell,Sandybridge] [--simd full,no-avx2]
                                   [--paths book/dma ...]
    python tools/crosscheck.py report             # the report of the last run again
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import csv
import json
import math
import os
import shlex
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "src"))
import blas_kernels  # noqa: E402

OUT = ROOT / ".cache" / "crosscheck"
NBVAL = ["-m", "pytest", "-p", "no:cacheprovider", "--nbval", "--nbval-current-env",
         "--nbval-sanitize-with", "tests/nbval_sanitize.cfg", "--nbval-cell-timeout=600",
         "--ignore=book/_build", "-q"]


# -- the matrix -----------------------------------------------------------------------------------

def simd_found() -> list[str]:
    """numpy's dispatch targets found on this CPU beyond its baseline, in numpy's order."""
    code = ("import numpy, json, io, contextlib\n"
            "from numpy.lib._utils_impl import _opt_info\n"
            "from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__\n"
            "print(json.dumps([f for f in __cpu_dispatch__ if __cpu_features__.get(f)]))")
    env = {k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    if out.returncode != 0:
        return []
    return json.loads(out.stdout)


def simd_levels() -> dict[str, str]:
    """SIMD level name -> value of ``NPY_DISABLE_CPU_FEATURES`` ('' for everything found)."""
    found = simd_found()
    levels = {"full": ""}
    avx512 = [f for f in found if f.startswith(("X86_V4", "AVX512"))]
    avx2 = [f for f in found if f.startswith("X86_V3")]
    if avx512:
        levels["no-avx512"] = " ".join(avx512)
    if avx2:
        levels["no-avx2"] = " ".join(avx2 + avx512)
    other = [f for f in found if f not in avx512 + avx2]
    if other and not (avx512 or avx2):  # another architecture: full and baseline
        levels["baseline"] = " ".join(other)
    return levels


def configs(kernels: list[str] | None = None, simd: list[str] | None = None) -> list[tuple[str, str, str]]:
    """The matrix: (name, OPENBLAS_CORETYPE, NPY_DISABLE_CPU_FEATURES) per configuration.

    The first entry is this machine's default (the kernel OpenBLAS picks, every SIMD level).
    """
    levels = simd_levels()
    runnable = blas_kernels.runnable() or [""]
    default = blas_kernels.default_kernel()
    order = sorted(runnable, key=lambda k: (blas_kernels.resolved(k).lower() != default.lower(), k)) \
        if runnable != [""] else runnable
    out = []
    for k in order:
        if kernels and k not in kernels:
            continue
        for lv, disable in levels.items():
            if simd and lv not in simd:
                continue
            out.append((f"{k or 'default'}-{lv}", k, disable))
    return out


def second() -> tuple[str, str]:
    """make test's second configuration: another kernel and the next SIMD level down."""
    levels = simd_levels()
    lower = [v for k, v in levels.items() if k != "full"]
    kernel = subprocess.run([sys.executable, str(ROOT / "tools" / "blas_kernels.py"), "second"],
                            capture_output=True, text=True).stdout.strip()
    return kernel, (lower[0] if lower else "")


# -- running ----------------------------------------------------------------------------------------

def _run_one(name: str, kernel: str, disable: str, paths: list[str]) -> tuple[str, int, float]:
    folder = OUT / name
    folder.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PROJTRACK_CROSSCHECK_DIR=str(folder), OPENBLAS_NUM_THREADS="1",
               OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    env.pop("OPENBLAS_CORETYPE", None)
    env.pop("NPY_DISABLE_CPU_FEATURES", None)
    if kernel:
        env["OPENBLAS_CORETYPE"] = kernel
    if disable:
        env["NPY_DISABLE_CPU_FEATURES"] = disable
    cmd = [sys.executable, *NBVAL, *paths]
    if paths == ["book"]:
        cmd.append("tests/test_figure_regression.py")
    t0 = time.monotonic()
    with (folder / "nbval.log").open("w") as log:
        log.write(f"OPENBLAS_CORETYPE={kernel!r} NPY_DISABLE_CPU_FEATURES={disable!r}\n$ {shlex.join(cmd)}\n")
        log.flush()
        rc = subprocess.run(cmd, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT).returncode
    (folder / "status.json").write_text(json.dumps({"kernel": kernel, "disable": disable, "returncode": rc,
                                                    "seconds": round(time.monotonic() - t0)}))
    return name, rc, time.monotonic() - t0


def run(args: argparse.Namespace) -> int:
    matrix = configs(args.kernels, args.simd)
    if not matrix:
        print("no configuration to run", file=sys.stderr)
        return 2
    missing = blas_kernels.KERNELS.keys() - set(blas_kernels.supported())
    if missing:
        print(f"==> this CPU cannot run the OpenBLAS kernels {' '.join(sorted(missing))} (not checked here)")
    print(f"==> {len(matrix)} configurations, {args.jobs} at a time: " + ", ".join(n for n, _, _ in matrix))
    OUT.mkdir(parents=True, exist_ok=True)
    for stale in OUT.glob("*/status.json"):
        stale.unlink()
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(_run_one, n, k, d, args.paths) for n, k, d in matrix]
        for fut in cf.as_completed(futures):
            name, rc, secs = fut.result()
            print(f"    {name}: {'passed' if rc == 0 else 'FAILED'} ({secs / 60:.1f} min)", flush=True)
    return report(args, names=[n for n, _, _ in matrix])


# -- the report -------------------------------------------------------------------------------------

def _rows(path: Path) -> list[list[str]]:
    with path.open(newline="", encoding="utf-8") as fh:
        return list(csv.reader(fh))


def _table_moves(folder: Path) -> list[dict]:
    from projtrack.tolerance import moved_numbers, read_manifest

    committed = ROOT / "figures"
    out = []
    for fresh in sorted((folder / "figures").rglob("*.csv")):
        rel = fresh.relative_to(folder / "figures")
        if Path(rel.stem).suffix == ".timing":
            continue
        expected = committed / rel
        if not expected.is_file():
            out.append({"where": f"figures/{rel}", "expected": "", "actual": "(not committed)", "delta": math.inf,
                        "allowed": 0.0, "tolerance": "", "ok": False})
            continue
        for m in moved_numbers(_rows(expected), _rows(fresh), read_manifest(expected)):
            where = f"figures/{rel} row {m['row']} [{m['column']}]"
            out.append({**m, "where": where})
    return out


def _png_moves(folder: Path) -> list[dict]:
    import numpy as np
    from matplotlib.image import imread
    from matplotlib.testing.compare import calculate_rms

    committed = ROOT / "figures"
    out = []
    for fresh in sorted((folder / "figures").rglob("*.png")):
        rel = fresh.relative_to(folder / "figures")
        expected = committed / rel
        if Path(rel.stem).suffix == ".timing" or not expected.is_file() or fresh.read_bytes() == expected.read_bytes():
            continue
        a, b = imread(str(expected)), imread(str(fresh))
        if a.shape != b.shape:
            rms = math.inf
        else:
            rms = calculate_rms((a * 255).astype(np.int16), (b * 255).astype(np.int16))
        out.append({"where": f"figures/{rel}", "expected": "", "actual": f"RMS {rms:.3g}", "delta": rms,
                    "allowed": 1.0, "tolerance": "figure RMS 1.0 (0-255)", "ok": rms <= 1.0})
    return out


def _committed_outputs(nb_path: Path) -> list[list[str]]:
    import nbformat

    nb = nbformat.read(nb_path, as_version=4)
    cells = []
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        texts = []
        for o in cell.get("outputs", []):
            if o.get("output_type") == "stream":
                texts.append(o.get("text", ""))
            else:
                texts.append(o.get("data", {}).get("text/plain", "") if "data" in o else "")
        cells.append(texts)
    return cells


def _text_moves(folder: Path) -> list[dict]:
    from projtrack.tolerance import split_numbers

    path = folder / "outputs.json"
    if not path.is_file():
        return []
    out = []
    for nb, cells in json.loads(path.read_text()).items():
        committed = _committed_outputs(ROOT / nb)
        for num, got in cells.items():
            i = int(num)
            want = committed[i] if i < len(committed) else []
            # nbval joins consecutive streams; compare the concatenated text of the cell
            w, g = "".join(want), "".join(got["outputs"])
            if w == g:
                continue
            (ws, wn), (gs, gn) = split_numbers(w), split_numbers(g)
            checked = got["checked"]
            note = "compared by nbval" if checked else "not compared by nbval (the cell's tables are)"
            if ws != gs or len(wn) != len(gn):
                out.append({"where": f"{nb} cell {i}", "expected": "", "actual": "(text changed)",
                            "delta": math.inf, "allowed": 0.0, "tolerance": note, "ok": not checked})
                continue
            for x, y in zip(wn, gn):
                if x != y:
                    out.append({"where": f"{nb} cell {i}", "expected": x, "actual": y,
                                "delta": abs(float(y) - float(x)), "allowed": 0.0, "tolerance": note,
                                "ok": not checked})
    return out


def report(args: argparse.Namespace, names: list[str] | None = None) -> int:
    folders = sorted(p.parent for p in OUT.glob("*/status.json"))
    if names is not None:
        folders = [OUT / n for n in names if (OUT / n / "status.json").is_file()]
    if not folders:
        print("no cross-check run found in .cache/crosscheck (run `python tools/crosscheck.py run`)")
        return 2
    lines = ["# Cross-check report", "", "| configuration | OPENBLAS_CORETYPE | NPY_DISABLE_CPU_FEATURES | nbval + regression | minutes |",
             "|---|---|---|---|---|"]
    moves: dict[tuple, dict] = {}
    failed = []
    for folder in folders:
        st = json.loads((folder / "status.json").read_text())
        ok = st["returncode"] == 0
        if not ok:
            failed.append(folder.name)
        lines.append(f"| {folder.name} | {st['kernel'] or '(default)'} | {st['disable'] or '(none)'} | "
                     f"{'passed' if ok else '**FAILED**'} | {st['seconds'] / 60:.1f} |")
        for m in _table_moves(folder) + _png_moves(folder) + _text_moves(folder):
            key = (m["where"], m["expected"], m["actual"])
            entry = moves.setdefault(key, {**m, "configs": []})
            entry["configs"].append(folder.name)
    compared = {k: m for k, m in moves.items() if "not compared by nbval" not in m["tolerance"]}
    ignored = {k: m for k, m in moves.items() if k not in compared}

    def used(m: dict) -> float:
        if m["delta"] == 0:
            return 0.0
        return math.inf if not m["allowed"] else m["delta"] / m["allowed"]

    def table(entries: dict) -> list[str]:
        out = ["| where | committed | this run | delta | allowed | used | ok | tolerance | configurations |",
               "|---|---|---|---|---|---|---|---|---|"]
        for m in sorted(entries.values(), key=lambda m: (-used(m), m["where"])):
            u = used(m)
            out.append(f"| {m['where']} | {m['expected']} | {m['actual']} | {m['delta']:.3g} | {m['allowed']:.3g} | "
                       f"{'—' if math.isinf(u) else f'{u:.0%}'} | {'yes' if m['ok'] else '**no**'} | "
                       f"{m['tolerance']} | {len(m['configs'])}: {', '.join(m['configs'][:4])}"
                       f"{' ...' if len(m['configs']) > 4 else ''} |")
        return out

    lines += ["", f"## Every compared number that moved ({len(compared)})", "",
              "Tables, scorecards, figures and the text nbval compares, sorted by the share of its tolerance "
              "each move used (`delta / allowed`; an exact number or a changed text has no allowance). `ok` says "
              "whether the tests accept it.", "", *table(compared), "",
              f"## Outputs of cells left out of nbval that changed ({len(ignored)})", "",
              "Cells marked `# NBVAL_IGNORE_OUTPUT` (timings, or statistical numbers glued into the text whose "
              "table is compared above): listed so that a number that reaches the page without a compared table "
              "can be spotted.", "", *table(ignored)]
    text = "\n".join(lines) + "\n"
    (OUT / "report.md").write_text(text)
    head = lines[: 8 + len(folders) + min(len(compared), 20) + 4]
    print("\n".join(head))
    if len(lines) > len(head):
        print(f"... the whole report: {OUT / 'report.md'}")
    if failed:
        print(f"==> FAILED under: {', '.join(failed)} (logs: .cache/crosscheck/<config>/nbval.log)")
        return 1
    bad = [m for m in moves.values() if not m["ok"]]
    if bad:
        print(f"==> {len(bad)} moved numbers are outside their tolerance")
        return 1
    print(f"==> crosscheck passed under {len(folders)} configurations; {len(moves)} compared numbers moved, "
          "all within their tolerance")
    return 0


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("what", choices=["configs", "second", "run", "report"], nargs="?", default="run")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--kernels", type=lambda s: [x for x in s.split(",") if x], default=None)
    parser.add_argument("--simd", type=lambda s: [x for x in s.split(",") if x], default=None)
    parser.add_argument("--paths", nargs="*", default=["book"],
                        help="notebooks or folders to run (default: the whole book and the figure regression)")
    args = parser.parse_args(argv[1:])
    if args.what == "configs":
        for name, kernel, disable in configs(args.kernels, args.simd):
            print(f"{name}: OPENBLAS_CORETYPE={kernel or '(default)'} NPY_DISABLE_CPU_FEATURES={disable!r}")
        return 0
    if args.what == "second":
        kernel, disable = second()
        print(f"OPENBLAS_CORETYPE={shlex.quote(kernel)} NPY_DISABLE_CPU_FEATURES={shlex.quote(disable)}")
        return 0
    if args.what == "report":
        return report(args)
    return run(args)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
