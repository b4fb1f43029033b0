"""Compile skisnow's numba kernels into numba's on-disk cache (``cache=True``), one group per
process: ``python tests/_numba_warm.py contact|micro|identify``.

A fresh clone has no cache: every process that first calls a kernel compiles it (the contact's
kernels ~11 s of CPU, measured with an empty ``NUMBA_CACHE_DIR``). The suite's two xdist
workers would each compile the same kernels, and every CLI subprocess started before a worker
had written the cache would compile them again. ``tests/conftest.py`` runs these groups once,
side by side, at the start of a session whose cache lacks them; the workers and subprocesses
then load the kernels from the cache (milliseconds). Each group calls the library's own entry
points with the argument types the suite uses, so the signatures cached are those the tests
need; a kernel called with other types is compiled where it is called, as before. The kernels
and their answers are numba's and the library's: nothing here changes what a test computes.
"""

from __future__ import annotations

import sys
from pathlib import Path


def contact() -> None:
    """The strip and flexible solvers (skisnow.contact's kernels), as the demo warms them."""
    from skisnow.pipeline import solve_case

    for model in ("flexible", "rigid"):
        solve_case("classic", mass=60.0, load_position=-0.12, snow_modulus=100e6,
                   n_points=1024, ski_model=model)  # fmt: skip
    # the flexible candidate iteration's beam block (when the multilevel start fails), with the
    # argument types of skisnow.contact._flexible_candidates: the operator's read-only
    # generators (int8 sides, float64 d, u, v) and float64 work arrays
    import numpy as np

    from skisnow.contact._flexible_kernel import beam_block_apply

    side, d, u, v = np.zeros(8, dtype=np.int8), np.ones(8), np.ones(8), np.ones(8)
    for arr in (side, d, u, v):
        arr.setflags(write=False)
    beam_block_apply(np.flatnonzero(np.ones(8)), side, d, u, v, 1.0, np.ones(8), np.empty(8))


def micro() -> None:
    """The bearing model's kernel and selections, both grain shapes, on a small raster."""
    import numpy as np

    from skisnow.micro import bearing_area, make_topography

    h = np.random.default_rng(0).normal(0.0, 1e-6, (48, 48))
    topo = make_topography(h, dx=1e-6)
    for shape in ("sphere", "paraboloid"):
        bearing_area(topo, diameter=20e-6, pressure=20e3, hardness=100e6, shape=shape)


def identify() -> None:
    """The banded Cholesky factor and solves of identification (one and many right sides)."""
    import numpy as np

    from skisnow.identify._banded_kernel import banded_cholesky, banded_solve

    n = 40
    ab = np.zeros((4, n))
    ab[3] = 4.0
    ab[2, 1:] = -1.0
    factor = banded_cholesky(ab)
    banded_solve(factor, np.ones(n))
    banded_solve(factor, np.ones((n, 3)))


GROUPS = {"contact": contact, "micro": micro, "identify": identify}

#: The kernels each group compiles: (module under src/skisnow, functions).
KERNELS = {
    "contact": (
        ("contact/_beam_kernel.py", ("boot_deflect_strided", "cantilever_apply_strided",
                                     "half_generators")),
        ("contact/_flexible_kernel.py", ("beam_block_apply", "coupled_block")),
        ("contact/_pdas_kernel.py", ("_cholesky", "_key", "_triangular", "pdas_dense")),
        ("contact/_pk_kernel.py", ("_fit", "_restore", "pk_dense")),
    ),
    "micro": (
        ("micro/_bearing_kernel.py", ("_bearing_kernel",)),
        ("micro/_bearing_select.py", ("_band_select", "_kth_largest_inplace")),
    ),
    "identify": (("identify/_banded_kernel.py", ("_factor", "_solve")),),
}  # fmt: skip


def cached(group: str, src: Path) -> bool:
    """Whether numba's cache beside the sources (``__pycache__``, the default without
    ``NUMBA_CACHE_DIR``) holds an index of every kernel of ``group``, newer than its source
    (numba names it ``<module>.<function>-<line of the decorator>.py<XY>.nbi``). A renamed or
    moved kernel counts as not cached: the group is then compiled (or loaded) again."""
    import os

    if os.environ.get("NUMBA_CACHE_DIR"):
        return False  # elsewhere, in numba's own layout: let the group load or compile
    tag = f"py{sys.version_info.major}{sys.version_info.minor}"
    for module, functions in KERNELS[group]:
        path = src / module
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
            stamp = path.stat().st_mtime
        except OSError:
            return False
        for name in functions:
            at = [i for i, line in enumerate(lines) if line.startswith(f"def {name}(")]
            if not at:
                return False
            first = at[0]
            while first > 0 and lines[first - 1].startswith("@"):
                first -= 1  # up to the first decorator's line
            index = path.parent / "__pycache__" / f"{path.stem}.{name}-{first + 1}.{tag}.nbi"
            try:
                if index.stat().st_mtime < stamp:
                    return False
            except OSError:
                return False
    return True


if __name__ == "__main__":
    for name in sys.argv[1:] or list(GROUPS):
        GROUPS[name]()
