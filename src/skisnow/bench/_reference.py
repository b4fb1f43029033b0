"""A reference camber bench independent of the beam of :mod:`skisnow.ski`, for validation.

The bench of Kalliorinne et al. (2023), §3.1 (eq. 1, h = f(x, m, x_m)) solved a second way, so
that an identification (:mod:`skisnow.identify`) is never validated only against its own forward
model. It shares no code with :func:`skisnow.ski.solve_beam` (Hermite finite elements, nodal
contact, flexibility matrix, primal active set); it reads only the ski's definition EI(x), z0(x):

* discretisation: finite differences on a uniform grid of spacing ``dx`` (default 0.5 mm) in
  the mixed form of (EI w'')'' = q: the bending moment M = EI w'' and the balance M'' = q by
  central second differences at the nodes, M = 0 at the free ends (second order in dx; the
  mixed form keeps the round-off of a fine grid below its truncation error);
* load: the boot plate's uniform line load m·g / b over [x_m − b/2, x_m + b/2], lumped on the
  nodes by the overlap of each node's cell with the plate;
* contact: at EVERY grid node, h_i = z0_i + w_i ≥ 0, r_i ≥ 0, r_i h_i = 0 (the stone), and the
  ski free-floating (no supports: K w = f + r must balance, which the contact set enforces);
* solver: the primal–dual active-set method (Hintermüller, Ito & Kunisch 2002; a semismooth
  Newton method) on the displacement form: for a contact set A the nodes of A sit on the stone
  (w_A = −z0_A) and the others carry no reaction (one sparse LU solve of the mixed system for
  w, M and r_A); then A ← {i : r_i − c h_i > 0}. From a
  start the method may cycle on degenerate sets; it then continues one node at a time
  (the most violated condition first), which terminates.

Heights are returned at the grid nodes, or sampled at bench stations by linear interpolation
(stations on the grid are exact).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csc_matrix
from scipy.sparse.linalg import spsolve

from skisnow._errors import ConvergenceError, InputError
from skisnow.bench._data import BenchData
from skisnow.constants import STANDARD_GRAVITY
from skisnow.ski import Ski

__all__ = ["FiniteDifferenceProfile", "reference_bench", "reference_profile"]


class FiniteDifferenceProfile:
    """A loaded profile of :func:`reference_profile`: grid ``x`` [m], heights ``height`` [m],
    nodal reactions ``reactions`` [N], the contact set ``active`` and the iterations taken."""

    __slots__ = ("active", "height", "iterations", "reactions", "x")

    def __init__(self, x, height, reactions, active, iterations) -> None:
        self.x, self.height, self.reactions = x, height, reactions
        self.active, self.iterations = active, iterations

    def sample(self, x: ArrayLike) -> NDArray[np.float64]:
        """Heights [m] at stations ``x`` [m] (linear between grid nodes)."""
        return np.interp(np.asarray(x, dtype=float), self.x, self.height)


def _grid(ski: Ski, dx: float) -> NDArray[np.float64]:
    n = max(8, round((ski.x_tip - ski.x_tail) / dx))
    return np.linspace(ski.x_tail, ski.x_tip, n + 1)


def _boot_forces(x: NDArray[np.float64], force: float, xm: float, b: float) -> NDArray[np.float64]:
    """Nodal forces [N] (downward negative) of the uniform line load of a boot plate of length
    ``b`` centred at ``xm``: the load on each node's cell."""
    dx = x[1] - x[0]
    lo, hi = np.maximum(x - dx / 2, x[0]), np.minimum(x + dx / 2, x[-1])
    overlap = np.clip(np.minimum(hi, xm + b / 2) - np.maximum(lo, xm - b / 2), 0.0, None)
    return -force * overlap / b


def _solve_active(
    x: NDArray[np.float64],
    ei: NDArray[np.float64],
    z0: NDArray[np.float64],
    f: NDArray[np.float64],
    active: NDArray[np.bool_],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Deflection w and reactions r of the contact set ``active`` (w = -z0 there, r = 0 off it).

    The mixed form (moments M as unknowns beside w, so the conditioning is that of two second
    differences, O(dx^-2), not of a fourth, O(dx^-4): at dx = 0.25 mm the fourth-difference
    system lost 1 % of a three-point-bending deflection to round-off, the mixed one 3e-8, its
    truncation error): at every node (M_{i-1} - 2 M_i + M_{i+1}) / dx = f_i + r_i, at every
    interior node EI_i (w_{i-1} - 2 w_i + w_{i+1}) / dx² = M_i, and M = 0 at the free ends.
    Unknowns interleaved per node (w_i or r_i, then M_i): a band matrix, solved by sparse LU.
    """
    n = x.size
    dx = x[1] - x[0]
    i = np.arange(n)
    rows, cols, vals = [], [], []
    for off, co in ((-1, 1.0), (0, -2.0), (1, 1.0)):  # force balance rows 2i
        j = i + off
        ok = (j >= 1) & (j <= n - 2)  # M is zero at the ends
        rows.append(2 * i[ok])
        cols.append(2 * j[ok] + 1)
        vals.append(np.full(int(ok.sum()), co / dx))
    rows.append(2 * i[active])
    cols.append(2 * i[active])
    vals.append(-np.ones(int(active.sum())))
    rhs = np.zeros(2 * n)
    rhs[0::2] = f
    k = np.arange(1, n - 1)  # moment rows 2k+1
    for off, co in ((-1, 1.0), (0, -2.0), (1, 1.0)):
        j = k + off
        free = ~active[j]
        rows.append(2 * k[free] + 1)
        cols.append(2 * j[free])
        vals.append(co * ei[k[free]] / dx**2)
        np.add.at(rhs, 2 * k[~free] + 1, co * ei[k[~free]] / dx**2 * z0[j[~free]])
    rows.append(2 * i + 1)
    cols.append(2 * i + 1)
    vals.append(-np.ones(n))
    mat = csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(2 * n, 2 * n)
    )
    sol = spsolve(mat, rhs)
    w = np.where(active, -z0, sol[0::2])
    r = np.where(active, sol[0::2], 0.0)
    return w, r


def reference_profile(
    ski: Ski,
    *,
    mass: float,
    load_position: float,
    boot_length: float = 0.10,
    dx: float = 0.5e-3,
    start: NDArray[np.bool_] | None = None,
    max_iterations: int = 400,
) -> FiniteDifferenceProfile:
    """The loaded camber of ``ski`` under ``mass`` [kg] through a uniform boot plate of
    ``boot_length`` [m] centred at ``load_position`` [m], on the rigid stone, by finite
    differences of spacing ``dx`` [m] with contact at every node (module docstring).

    ``start`` is a contact set to start from (e.g. the previous mass's ``active``).
    Raises :class:`~skisnow.ConvergenceError` if the active-set iteration does not end.
    """
    if not (np.isfinite(mass) and mass > 0):
        raise InputError(f"mass must be > 0 kg, got {mass}")
    x = _grid(ski, dx)
    n = x.size
    ei = ski.stiffness(x)
    z0 = ski.free_camber(x)
    f = _boot_forces(x, mass * STANDARD_GRAVITY, float(load_position), float(boot_length))
    if start is not None and start.sum() >= 2:
        active = start.copy()
    else:
        active = np.zeros(n, dtype=bool)
        active[_hull_pair(x, z0, float(np.sum(f * x) / np.sum(f)))] = True
    seen: set[bytes] = set()
    single = False
    for it in range(1, max_iterations + 1):
        w, r = _solve_active(x, ei, z0, f, active)
        h = z0 + w
        tol_r, tol_h = 1e-9 * mass * STANDARD_GRAVITY, 1e-12
        drop = active & (r < -tol_r)
        add = ~active & (h < -tol_h)
        if not drop.any() and not add.any():
            h[active] = 0.0
            return FiniteDifferenceProfile(x, np.maximum(h, 0.0), r, active.copy(), it)
        key = active.tobytes()
        if key in seen:
            single = True
        seen.add(key)
        if single:  # one node at a time: the most violated condition
            score = np.where(drop, -r / (mass * STANDARD_GRAVITY), 0.0)
            score = np.maximum(score, np.where(add, -h / max(float(np.ptp(z0)), 1e-6), 0.0))
            j = int(np.argmax(score))
            new = active.copy()
            new[j] = ~new[j]
        else:  # drop every negative reaction, add the deepest node of each penetrating run
            new = active & ~drop
            new[_deepest_of_runs(h, add)] = True
        if new.sum() < 2:  # a free-floating ski needs two supports: add, do not drop
            new = active | add
        active = new
    raise ConvergenceError(
        f"reference bench: the active-set iteration did not end in {max_iterations} steps "
        f"(ski {ski.name!r}, m = {mass:g} kg, x_m = {load_position * 1e3:g} mm)",
        result=None,
    )


def _deepest_of_runs(h: NDArray[np.float64], mask: NDArray[np.bool_]) -> NDArray[np.intp]:
    """The node of lowest ``h`` in each run of consecutive ``mask`` nodes."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return idx
    cuts = np.flatnonzero(np.diff(idx) > 1) + 1
    return np.array([run[np.argmin(h[run])] for run in np.split(idx, cuts)], dtype=np.intp)


def _hull_pair(x: NDArray[np.float64], g: NDArray[np.float64], xc: float) -> list[int]:
    hull: list[int] = []
    for i in range(x.size):
        while len(hull) >= 2:
            i0, i1 = hull[-2], hull[-1]
            if (x[i1] - x[i0]) * (g[i] - g[i0]) - (g[i1] - g[i0]) * (x[i] - x[i0]) <= 0.0:
                hull.pop()
            else:
                break
        hull.append(i)
    k = int(np.clip(np.searchsorted(x[hull], xc, side="right") - 1, 0, len(hull) - 2))
    return [hull[k], hull[k + 1]]


def reference_bench(
    ski: Ski,
    *,
    masses: Sequence[float],
    load_positions: Sequence[float],
    stations: ArrayLike | None = None,
    station_step: float = 1e-3,
    noise: float = 0.0,
    seed: int | None = None,
    boot_length: float = 0.10,
    dx: float = 0.5e-3,
) -> BenchData:
    """A bench sequence of ``ski`` by :func:`reference_profile` (independent of
    :func:`skisnow.ski.solve_beam`): every mass [kg] at every load position [m], heights at
    ``stations`` [m] (default every ``station_step`` on the ski) plus Gaussian noise of standard
    deviation ``noise`` [m] (seeded). The table and metadata of :func:`~skisnow.bench.run_bench`
    (``device`` says ``reference``)."""
    from skisnow import __version__

    if stations is None:
        k0 = int(np.ceil(ski.x_tail / station_step - 1e-9))
        k1 = int(np.floor(ski.x_tip / station_step + 1e-9))
        xs = np.arange(k0, k1 + 1) * station_step
    else:
        xs = np.asarray(stations, dtype=float)
    rng = np.random.default_rng(seed)
    rows = []
    for p in sorted(load_positions, reverse=True):
        prev = None
        for m in sorted(masses):
            sol = reference_profile(
                ski, mass=float(m), load_position=float(p), boot_length=boot_length, dx=dx,
                start=prev,
            )  # fmt: skip
            prev = sol.active
            h = sol.sample(xs)
            if noise > 0:
                h = h + rng.normal(0.0, noise, size=h.shape)
            rows.append(pd.DataFrame({
                "ski": ski.name, "mass_kg": float(m), "load_position_mm": p * 1e3,
                "x_mm": xs * 1e3, "height_mm": h * 1e3,
            }))  # fmt: skip
    table = pd.concat(rows, ignore_index=True)
    metadata = {
        **ski.summary_mm(),
        "balance_point": "x_mm = 0; x_mm and load_position_mm positive toward the tip",
        "kick_zone_mm": None if ski.kick_zone is None else [v * 1e3 for v in ski.kick_zone],
        "source": "reference bench: finite differences, contact at every node (skisnow.bench)",
        "device": "skisnow.bench.reference_bench",
        "skisnow_version": __version__,
        "boot_length_mm": boot_length * 1e3,
        "dx_mm": dx * 1e3,
        "noise_mm": noise * 1e3,
        "seed": seed,
        "units": {"mass_kg": "kg", "load_position_mm": "mm", "x_mm": "mm", "height_mm": "mm"},
    }
    return BenchData(table=table, metadata=metadata)
