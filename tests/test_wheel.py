"""The library as a user installs it: the wheel in a clean venv with only the core dependencies.

Builds the wheel of this checkout, creates a fresh virtual environment, installs the core
dependencies (``[project] dependencies`` of ``pyproject.toml``: numpy and scipy) at the
versions pinned in ``environment.lock`` with their hashes from the package index, then the
wheel with ``--no-deps``, and in that environment imports every algorithm package and runs
one small call of each. The optional features must then fail with an ImportError that names
the extra to install. Needs the package index (pip's cache makes it fast: about a minute);
``PROJTRACK_SKIP_WHEEL_TEST=1`` skips it on a machine without one.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import textwrap
import zipfile
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TOPICS = ["ellipsoids", "dma", "correlators", "hough", "jpda", "neuralnet", "novelty"]

pytestmark = [
    pytest.mark.wheel,
    pytest.mark.skipif(os.environ.get("PROJTRACK_SKIP_WHEEL_TEST") == "1",
                       reason="PROJTRACK_SKIP_WHEEL_TEST=1: no package index here"),
]

# One small call per algorithm package, run with numpy and scipy only; then the optional
# features, each of which must name its extra.
SCRIPT = textwrap.dedent("""
    import importlib, sys, warnings
    import numpy as np
    import projtrack
    print("version", projtrack.__version__)
    from projtrack import ellipsoids as E, dma, correlators as C, hough, jpda, neuralnet as N, novelty as K

    phi = np.linspace(0, np.pi, 6, endpoint=False)
    Cs = [np.array([np.cos(p), np.sin(p)]) for p in phi]
    X = E.reconstruct([E.project(np.diag([4.0, 1.0]), c) for c in Cs], Cs)
    assert np.allclose(X, np.diag([4.0, 1.0]))

    with np.errstate(divide="ignore"):
        lt = np.log([[0.5, 0.5], [0.0, 1.0]])
        ls = np.log([1.0, 0.0])
    assert dma.viterbi(ls, lt, np.zeros((3, 2))).shape == (3,)

    img = np.zeros((16, 16)); img[4:8, 5:9] = 1.0
    assert C.project(img, 0.0).shape[0] > 0

    t = np.linspace(-50, 50, 30)
    H, rhos, thetas = hough.hough_transform(np.c_[t, 0.5 * t] + 128, (256, 256))
    assert len(hough.find_peaks(H, rhos, thetas)) == 1

    b = jpda.beta([[0.1, 0.1], [0.5, 0.0], [0.3, 0.6], [0.0, 0.4]])
    assert np.allclose(b.sum(axis=0), 1)

    D = N.distance_tensor(np.random.default_rng(0).random((3, 3, 3)))
    assert D.ndim >= 3

    nf = K.NoveltyFilter()
    for k in range(3):
        nf.partial_fit(np.random.default_rng(k).random((8, 8)))
    assert nf.rank_ >= 1

    heavy = sorted(m for m in ("matplotlib", "pandas", "cvxpy", "numba", "filterpy", "sklearn")
                   if m in sys.modules)
    assert not heavy, heavy

    def needs(extra, call):
        try:
            call()
        except ImportError as exc:
            assert f"projtrack[{extra}]" in str(exc), str(exc)
            print("extra", extra, "named")
        else:
            raise AssertionError(f"expected an ImportError naming projtrack[{extra}]")

    needs("sdp", lambda: E.reconstruct([1.0, 2.0, 1.5], Cs[:3], lower=0, method="sdp"))
    needs("kalman", lambda: jpda.JPDATracker([[0.0, 0.0]], np.eye(2), np.eye(2), np.eye(2),
                                             np.eye(2), np.eye(2)))
    needs("learn", lambda: dma.learn_manifold(np.random.default_rng(0).random((50, 2)), 2, 4,
                                              np.random.default_rng(0)))
    print("ok")
""")


def _run(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    out = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert out.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{out.stdout}\n{out.stderr}"
    return out


def _locked_requirements(names: list[str]) -> str:
    """The blocks of environment.lock (pin, markers and hashes) of the given packages."""
    text = (ROOT / "environment.lock").read_text()
    blocks = re.split(r"\n(?=[A-Za-z0-9])", text)
    keep = []
    for name in names:
        norm = re.sub(r"[-_.]+", "-", name).lower()
        found = [b for b in blocks if re.sub(r"[-_.]+", "-", re.split(r"[=;\s\[]", b, 1)[0]).lower() == norm]
        assert found, f"{name} is not pinned in environment.lock"
        keep += ["\n".join(ln for ln in b.splitlines() if not ln.strip().startswith("#")) for b in found]
    return "\n".join(keep) + "\n"


def test_wheel_installs_and_imports_with_the_core_dependencies_only(tmp_path):
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = [re.split(r"[<>=!~;\s\[]", d, 1)[0] for d in meta["dependencies"]]
    assert sorted(core) == ["numpy", "scipy"], "the library's core is numpy and scipy"

    # build from a copy, so that no build/ folder of an earlier run can leak into the wheel
    src = tmp_path / "src"
    shutil.copytree(ROOT / "src", src / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "*.pyc"))
    for name in ("pyproject.toml", "README.md", "LICENSE", "CITATION.cff"):
        shutil.copy2(ROOT / name, src / name)
    dist = tmp_path / "dist"
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--quiet",
          "-w", str(dist), str(src)])
    wheels = list(dist.glob("projtrack-*.whl"))
    assert len(wheels) == 1, wheels
    with zipfile.ZipFile(wheels[0]) as zf:
        names = zf.namelist()
    assert any(n.endswith("licenses/LICENSE") or n.endswith("/LICENSE") for n in names), "LICENSE not in the wheel"

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)])
    py = venv / ("Scripts" if os.name == "nt" else "bin") / "python"
    req = tmp_path / "core.txt"
    req.write_text(_locked_requirements(core))
    _run([str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", "--require-hashes",
          "--only-binary", ":all:", "--no-deps", "-r", str(req)])
    _run([str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", "--no-deps",
          str(wheels[0])])
    listed = _run([str(py), "-m", "pip", "list", "--format=freeze"]).stdout.lower()
    assert set(re.findall(r"^([a-z0-9_.-]+)==", listed, re.M)) == {"numpy", "scipy", "projtrack", "pip"} | (
        {"setuptools"} if "setuptools==" in listed else set())

    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env["OPENBLAS_NUM_THREADS"] = "1"
    out = _run([str(py), "-c", SCRIPT], cwd=tmp_path, env=env).stdout
    assert f"version {meta['version']}" in out
    assert out.count("named") == 3 and out.rstrip().endswith("ok"), out
