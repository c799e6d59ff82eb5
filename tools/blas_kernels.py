"""Which OpenBLAS kernels (``OPENBLAS_CORETYPE``) this CPU can run, for the cross-kernel check.

Usage:
  ``python tools/blas_kernels.py default``  the kernel OpenBLAS picks here by itself
  ``python tools/blas_kernels.py list``     the kernels of the cross-check this CPU can run,
                                            one per distinct OpenBLAS kernel
  ``python tools/blas_kernels.py second``   one runnable kernel other than the default
  ``python tools/blas_kernels.py missing``  the kernels of the cross-check this CPU cannot run
  ``python tools/blas_kernels.py duplicates``  supported names that map onto a listed kernel

The cross-check kernels are x86-64 ones: ``Haswell`` (AVX2), ``SkylakeX`` (AVX-512),
``Sandybridge`` (AVX), ``Zen`` (AVX2), ``Nehalem`` (SSE4.2) and ``Prescott`` (SSE3). They
give different last bits for the same BLAS call. A kernel needs its instruction set (a
SkylakeX kernel on a CPU without AVX-512 dies with SIGILL), so only those the CPU supports
are listed; and a name the installed OpenBLAS maps onto a kernel already listed (in the
numpy wheels, ``Zen`` runs the ``Haswell`` kernel) is listed once. On other architectures
the lists are empty and only the default kernel is checked.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
from pathlib import Path

# kernel -> CPU flags it needs (from /proc/cpuinfo)
KERNELS: dict[str, tuple[str, ...]] = {
    "Haswell": ("avx2", "fma"),
    "SkylakeX": ("avx512f", "avx512dq", "avx512bw", "avx512vl"),
    "Sandybridge": ("avx",),
    "Zen": ("avx2", "fma"),
    "Nehalem": ("sse4_2",),
    "Prescott": ("sse3",),
}
_PREFERRED_SECOND = ("Sandybridge", "Haswell", "Prescott")


def cpu_flags() -> set[str]:
    info = Path("/proc/cpuinfo")
    if not info.is_file():
        return set()
    for line in info.read_text().splitlines():
        if line.startswith("flags"):
            flags = set(line.split(":", 1)[1].split())
            if "pni" in flags:  # Linux calls SSE3 "pni"
                flags.add("sse3")
            return flags
    return set()


def supported() -> list[str]:
    """The cross-check kernels whose instructions this CPU has."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return []
    flags = cpu_flags()
    return [k for k, need in KERNELS.items() if all(f in flags for f in need)]


def resolved(kernel: str) -> str:
    """The kernel OpenBLAS reports when asked for ``kernel`` (in a fresh process)."""
    env = {**os.environ, "OPENBLAS_CORETYPE": kernel}
    out = subprocess.run([sys.executable, __file__, "default"], env=env, capture_output=True, text=True)
    return out.stdout.strip() if out.returncode == 0 else ""


def runnable() -> list[str]:
    """Supported kernels, one per distinct kernel OpenBLAS actually runs."""
    seen, keep = set(), []
    for k in supported():
        r = resolved(k)
        if r and r not in seen:
            seen.add(r)
            keep.append(k)
    return keep


def default_kernel() -> str:
    import numpy  # noqa: F401  (loads OpenBLAS, so threadpoolctl can see it)
    from threadpoolctl import threadpool_info

    archs = [i.get("architecture") for i in threadpool_info() if i.get("internal_api") == "openblas"]
    return archs[0] if archs and archs[0] else "unknown"


def main(argv: list[str]) -> int:
    what = argv[1] if len(argv) > 1 else "list"
    if what == "default":
        print(default_kernel())
    elif what == "list":
        print(" ".join(runnable()))
    elif what == "missing":
        print(" ".join(k for k in KERNELS if k not in supported()))
    elif what == "duplicates":
        run = runnable()
        print(" ".join(f"{k}={resolved(k)}" for k in supported() if k not in run))
    elif what == "second":
        default = default_kernel().lower()
        options = [k for k in _PREFERRED_SECOND if k in supported() and resolved(k).lower() != default]
        print(options[0] if options else "")
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
