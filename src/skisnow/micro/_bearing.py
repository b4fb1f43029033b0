"""The bearing model of plastic ice grains on a ski-base topography (Scherge et al. 2021, eq. 5–9).

Model (seed §3.7, with its lost symbols reconstructed). A loose, rounded ice grain is a sphere of
diameter D = 2R pressed against the base topography h(x, y) [m] (heights pointing out of the
base, toward the snow). At a raster position (x0, y0) the sphere's centre is lowered along the
normal until it first touches the base — *it settles into the valley under it*: the first-contact
height of the sphere's lowest point is

    z0(x0, y0) = max_{(x, y) in footprint} [ h(x, y) − s(|x − x0|) ],   s(r) = R − √(R² − r²),

i.e. the grey-scale dilation of h by the sphere (the "rolling ball"; s is the sag of the sphere
surface at distance r from its axis). The ice then yields plastically (its hardness is far below
that of UHMWPE, see :func:`~skisnow.micro.deformation_regime`), and the base is pressed a further
δ into the grain until the projected contact area (eq. 6–7, gap g = s − h + z0 − δ)

    A0(δ) = ∬ Θ(−g) dx dy

carries the load share of one grain at the hardness (eq. 5):  A0(δ)·H_ice = p_macro·(2R)².
The real area (eq. 8) is the base surface wrapped by the ice, A = ∬ Θ(−g)·√(1 + |∇h|²) dx dy,
and the fractional area (eq. 9) is A_fr = A/(2R)². The seed's figure of the result is the mean
of A_fr over all raster positions, for each grain size.

Discretisation (what this module computes exactly):

* Pixels are points of area dx·dy at their centres; ∇h by central differences (``np.gradient``).
* A0(δ) is a step function of δ: pixels enter the contact in decreasing order of
  F(x) = h(x) − s(|x − x0|). With N* = p(2R)²/(H·dx·dy) (not an integer), the contact is the
  ⌊N*⌋ pixels of largest F plus the fraction N* − ⌊N*⌋ of the next one, and δ is interpolated
  linearly between the two steps. Hence A0·H = p·(2R)² holds EXACTLY at every position, and a
  flat base gives A_fr = p/H exactly.
* Positions that count: every pixel centre (or every ``stride``-th) whose whole footprint disc
  of radius R lies inside the map — no padding, no periodic wrap; positions near the edges are
  simply not used (a 1 mm map and D = 750 µm leave a 250 µm × 250 µm square of centres).
* Sphere surface: exact (``shape='sphere'``) or the paraboloid s(r) ≈ r²/2R
  (``shape='paraboloid'``), whose sag error is s_sphere − s_parab = r⁴/8R³ + O(r⁶/R⁵): 0.006 µm
  at r = 30 µm and 0.1 µm at r = 70 µm for R = 300 µm — small against the µm penetrations, but
  not zero when the grain touches the far flanks of a wide groove, hence the exact default.

Algorithm (exact; no approximation beyond the discretisation above). Only ⌊N*⌋ + 1 pixels per
position matter — a few hundred for D = 450–750 µm at 1 µm pixels and 20 kPa — so the
positions are processed in tiles (default 4 × 4) grouped in super-tiles (default 4 × 4 tiles)
and everything else is pruned by bounds:

1. Any pixel with F(x) < τ (τ = (⌊N*⌋+1)-th largest F of that position) is irrelevant.
2. For a set B of positions, F_x0(x) ≤ h(x) − s(d_min(x, B)) and F_x0(x) ≥ h(x) − s(d_max(x, B))
   for every x0 in B (s increases with r). The (⌊N*⌋+1)-th largest of the lower bound is a lower
   bound τ_B of every position's τ; pixels whose upper bound is below τ_B are dropped.
   A super-tile applies this to its search window once; each tile applies it again, with its
   own tighter distances, to the super-tile's survivors.
3. For the tile's survivors the exact F is evaluated for every position of the tile, the
   (⌊N*⌋+1)-th largest found by an in-place selection, and the contact summed (ties at the
   boundary taken in raster order, as the reference's stable sort does).

Steps 1–3 run in one compiled kernel (numba, GIL released; see the comment at
``_bearing_kernel`` for why). F is h − s read from a table of the sag at integer pixel offsets,
the very values the reference computes, so the selected pixels are the reference's.
The search window around a super-tile is bounded a priori: a pixel at distance r can only
compete if s(r) ≤ max h − min h + s(ρ*), ρ* the radius holding N*+1 pixels.
:func:`bearing_area_reference` is the naive search over the whole footprint, kept in the
library to check this one.

Selection in step 3 avoids a full selection per position: the threshold (the (⌊N*⌋+1)-th
largest F) of a position is guessed from the plane through those of its left, upper and
upper-left neighbours, one pass sums the candidates above guess + Δ and gathers the band
guess ± Δ (Δ = 3× the recent guess error), and only the band is selected; a guess that misses
is retried on the side the pass reports. The super-tile's window is also shrunk to the rows
and columns where max h − s(r) still reaches a first lower bound of τ from its core.

Cost (measured, ``benchmarks/bench_bearing.py``, preset S3, 1 mm² at 1 µm, 31 sizes
450–750 µm, 5.2 million position–size pairs): ~10 µs CPU per pair, i.e. ~51 s CPU and 26 s
wall with 2 threads (load average 2.4 on 2 cores), against ~35–45 µs per pair for the previous
NumPy block search and ~10 ms for the naive search. ``stride`` trades positions for time
(stride 3 changed the mean A_fr by 4·10⁻⁵ relative on preset S3).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numba
import numpy as np

from skisnow._errors import InputError
from skisnow.micro._topography import Topography, fill_missing

__all__ = [
    "BearingMap",
    "BearingSweep",
    "bearing_area",
    "bearing_area_reference",
    "bearing_sweep",
    "slope_factor",
]


@dataclass(frozen=True, eq=False)
class BearingMap:
    """Bearing model for one grain size at every counted raster position.

    Attributes
    ----------
    diameter
        Grain diameter D [m].
    positions
        ``(n, 2)`` integer pixel indices (i, j) of the sphere axis.
    fractional_area
        A_fr = A/(2R)² per position (eq. 9) [-].
    projected_area
        A0 per position [m²] (equals p(2R)²/H at every position by construction).
    penetration
        δ per position [m]: how far the base is pressed into the grain after first contact.
    first_contact
        z0 per position [m]: height of the sphere's lowest point at first contact (dilation).
    target_pixels
        N* = p(2R)²/(H dx dy).
    """

    diameter: float
    pressure: float
    hardness: float
    positions: np.ndarray
    fractional_area: np.ndarray
    projected_area: np.ndarray
    penetration: np.ndarray
    first_contact: np.ndarray
    target_pixels: float

    @property
    def mean_fractional_area(self) -> float:
        """Mean of A_fr over the raster positions."""
        return float(np.mean(self.fractional_area))


@dataclass(frozen=True, eq=False)
class BearingSweep:
    """Mean fractional contact area per grain size (the seed's A_fr(D))."""

    diameters: np.ndarray
    fractional_area: np.ndarray
    fractional_area_std: np.ndarray
    mean_penetration: np.ndarray
    max_penetration: np.ndarray
    n_positions: np.ndarray
    pressure: float
    hardness: float
    shape: str
    stride: int


def slope_factor(topo: Topography) -> np.ndarray:
    """√(1 + |∇h|²) per pixel (eq. 8), central differences (one-sided at the edges)."""
    h = np.asarray(topo.heights)
    gx, gy = np.gradient(h, topo.dx, topo.dy)
    return np.sqrt(1.0 + gx * gx + gy * gy)


def _sag(r2: np.ndarray, radius: float, shape: str) -> np.ndarray:
    """Sag s(r) of the sphere surface [m] from r² [m²]; +inf outside the footprint r > R."""
    if shape == "paraboloid":
        s = r2 / (2.0 * radius)
    else:
        with np.errstate(invalid="ignore"):
            s = radius - np.sqrt(radius * radius - r2)
    return np.where(r2 <= radius * radius, s, np.inf)


def _check(
    topo: Topography, diameter: float, pressure: float, hardness: float, shape: str, stride: int
) -> tuple[np.ndarray, float, int, int]:
    if shape not in ("sphere", "paraboloid"):
        raise InputError(f"shape {shape!r} unknown; valid: 'sphere', 'paraboloid'")
    if not (np.isfinite(diameter) and diameter > 0):
        raise InputError(f"grain diameter must be positive [m], got {diameter}")
    if not (np.isfinite(pressure) and pressure > 0):
        raise InputError(f"macroscopic pressure must be positive [Pa], got {pressure}")
    if not (np.isfinite(hardness) and hardness > pressure):
        raise InputError(f"ice hardness must exceed the pressure [Pa], got {hardness}")
    if int(stride) < 1:
        raise InputError(f"stride must be a positive number of pixels, got {stride}")
    radius = diameter / 2.0
    ci = math.ceil(radius / topo.dx - 1e-9)
    cj = math.ceil(radius / topo.dy - 1e-9)
    nx, ny = topo.shape
    if nx - 2 * ci < 1 or ny - 2 * cj < 1:
        raise InputError(
            f"{topo.source}: map {topo.size[0] * 1e6:.0f} × {topo.size[1] * 1e6:.0f} µm is too "
            f"small for a grain of {diameter * 1e6:.0f} µm (its footprint must fit inside)"
        )
    h = np.asarray(fill_missing(topo).heights)
    return h, radius, ci, cj


def _positions(shape: tuple[int, int], ci: int, cj: int, stride: int) -> np.ndarray:
    ii = np.arange(ci, shape[0] - ci, stride)
    jj = np.arange(cj, shape[1] - cj, stride)
    return np.stack(np.meshgrid(ii, jj, indexing="ij"), axis=-1).reshape(-1, 2)


def _result(
    topo: Topography,
    diameter: float,
    pressure: float,
    hardness: float,
    pos: np.ndarray,
    wsum: np.ndarray,
    z0: np.ndarray,
    level: np.ndarray,
    nstar: float,
) -> BearingMap:
    area = (2.0 * diameter / 2.0) ** 2
    da = topo.dx * topo.dy
    return BearingMap(
        diameter=float(diameter),
        pressure=float(pressure),
        hardness=float(hardness),
        positions=pos,
        fractional_area=wsum * da / area,
        projected_area=np.full(len(pos), nstar * da),
        penetration=z0 - level,
        first_contact=z0,
        target_pixels=nstar,
    )


# ---------------------------------------------------------------------------------------------
# Compiled kernel. Why numba: the exact search is a selection (the (N*+1)-th largest F) over a
# few hundred candidates per position, repeated 5 million times in the target case; in NumPy
# every step (bounds, F, partition, masked sums) is a separate pass over a temporary, and the
# best vectorised version measured (tiles of positions against a shared candidate list, value
# partition, batched masked sums) stayed at ~45 µs per position under load, 4× short of the
# target. A loop that computes F from a sag table and runs an in-place quickselect touches each
# candidate twice and releases the GIL, so ``bearing_sweep`` threads use both cores.
# ---------------------------------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def _kth_largest_inplace(a: np.ndarray, m: int, k: int) -> float:  # pragma: no cover - jit
    """The k-th largest of a[:m] (k = 1: the maximum); reorders a[:m] (Wirth's selection)."""
    t = m - k  # index of the answer in ascending order
    lo = 0
    hi = m - 1
    while lo < hi:
        x = a[t]
        i = lo
        j = hi
        while True:
            while a[i] < x:
                i += 1
            while x < a[j]:
                j -= 1
            if i <= j:
                tmp = a[i]
                a[i] = a[j]
                a[j] = tmp
                i += 1
                j -= 1
            if i > j:
                break
        if j < t:
            lo = i
        if t < i:
            hi = j
    return a[t]


@numba.njit(cache=True, nogil=True)
def _bearing_kernel(
    h: np.ndarray,
    w: np.ndarray,
    ii: np.ndarray,
    jj: np.ndarray,
    ux: int,
    uy: int,
    uci: int,
    ucj: int,
    h_max: float,
    table: np.ndarray,
    n: int,
    frac: float,
    bx: int,
    by: int,
    sx: int,
    sy: int,
    out_w: np.ndarray,
    out_z: np.ndarray,
    out_l: np.ndarray,
) -> None:  # pragma: no cover - jit
    """The pruned exact search of the module docstring for every position ii × jj.

    ``table[a, b]`` is the sag at the pixel offset (a, b) (+inf outside the footprint), so F is
    h − table[|Δi|, |Δj|], the reference's arithmetic. Super-tiles of sx × sy positions scan
    their window once (step 1); tiles of bx × by positions filter the super-tile's list with
    their own bounds (step 2); each position selects from its tile's list (step 3)."""
    n_i = ii.size
    n_j = jj.size
    # thresholds fn1 found so far: the guess for a position is the plane through its left,
    # upper and upper-left neighbours (all done before it in this loop order); the bracket
    # half-width follows the recent guess errors
    thr = np.empty((n_i, n_j))
    err = -1.0
    for si in range(0, n_i, sx):
        se = min(si + sx, n_i)
        p0i = ii[si]
        p1i = ii[se - 1]
        for sj in range(0, n_j, sy):
            sje = min(sj + sy, n_j)
            p0j = jj[sj]
            p1j = jj[sje - 1]
            # step 1: the super-tile's window, bounds at the extreme distances
            i0 = p0i - ux
            i1 = p1i + ux + 1
            j0 = p0j - uy
            j1 = p1j + uy + 1
            size = (i1 - i0) * (j1 - j0)
            buf = np.empty(size)
            # a first lower bound L0 of τ from the core (the super-tile grown by uci, ucj,
            # which holds more than N*+1 pixels); the window's (N*+1)-th largest lower bound
            # is ≥ L0, so only the window pixels with a lower bound ≥ L0 enter the selection
            k = 0
            for i in range(max(i0, p0i - uci), min(i1, p1i + uci + 1)):
                dmi = max(abs(i - p0i), abs(i - p1i))
                for j in range(max(j0, p0j - ucj), min(j1, p1j + ucj + 1)):
                    dmj = max(abs(j - p0j), abs(j - p1j))
                    buf[k] = h[i, j] - table[dmi, dmj]
                    k += 1
            low0 = _kth_largest_inplace(buf, k, n + 1)
            # a pixel a rows beyond the super-tile has F ≤ max h − s(a·dx) for all its
            # positions: the window shrinks to the rows and columns where that reaches L0
            ra = 0
            while ra < ux and h_max - table[ra + 1, 0] >= low0:
                ra += 1
            rb = 0
            while rb < uy and h_max - table[0, rb + 1] >= low0:
                rb += 1
            i0 = p0i - ra
            i1 = p1i + ra + 1
            j0 = p0j - rb
            j1 = p1j + rb + 1
            size = (i1 - i0) * (j1 - j0)
            k = 0
            for i in range(i0, i1):
                dmi = max(abs(i - p0i), abs(i - p1i))
                for j in range(j0, j1):
                    dmj = max(abs(j - p0j), abs(j - p1j))
                    v = h[i, j] - table[dmi, dmj]
                    buf[k] = v
                    k += v >= low0
            tau = _kth_largest_inplace(buf, k, n + 1)
            c_i = np.empty(size, np.int64)
            c_j = np.empty(size, np.int64)
            c_h = np.empty(size)
            c_w = np.empty(size)
            nc = 0
            for i in range(i0, i1):
                dni = max(0, p0i - i, i - p1i)
                for j in range(j0, j1):
                    dnj = max(0, p0j - j, j - p1j)
                    hv = h[i, j]
                    if hv - table[dni, dnj] >= tau:
                        c_i[nc] = i
                        c_j[nc] = j
                        c_h[nc] = hv
                        c_w[nc] = w[i, j]
                        nc += 1
            low = np.empty(nc)
            t_i = np.empty(nc, np.int64)
            t_j = np.empty(nc, np.int64)
            t_h = np.empty(nc)
            t_w = np.empty(nc)
            band = np.empty(2 * nc)
            band_w = np.empty(nc)
            res = np.empty(6)
            for ti in range(si, se, bx):
                te = min(ti + bx, se)
                q0i = ii[ti]
                q1i = ii[te - 1]
                for tj in range(sj, sje, by):
                    tje = min(tj + by, sje)
                    q0j = jj[tj]
                    q1j = jj[tje - 1]
                    # step 2: the tile's candidates. The tile's lower bounds are ≥ the
                    # super-tile's, whose (N*+1)-th largest is τ: only those ≥ τ compete
                    kl = 0
                    for c in range(nc):
                        gi = c_i[c]
                        gj = c_j[c]
                        dmi = max(abs(gi - q0i), abs(gi - q1i))
                        dmj = max(abs(gj - q0j), abs(gj - q1j))
                        v = c_h[c] - table[dmi, dmj]
                        low[kl] = v
                        kl += v >= tau
                    tau_t = _kth_largest_inplace(low, kl, n + 1)
                    m = 0
                    for c in range(nc):
                        gi = c_i[c]
                        gj = c_j[c]
                        dni = max(0, q0i - gi, gi - q1i)
                        dnj = max(0, q0j - gj, gj - q1j)
                        if c_h[c] - table[dni, dnj] >= tau_t:
                            t_i[m] = gi
                            t_j[m] = gj
                            t_h[m] = c_h[c]
                            t_w[m] = c_w[c]
                            m += 1
                    # step 3: exact selection for every position of the tile
                    for a in range(ti, te):
                        pi = ii[a]
                        for b in range(tj, tje):
                            pj = jj[b]
                            # bracket the threshold near its neighbours'; if it falls
                            # outside, the pass tells on which side (res[5])
                            if a > 0 and b > 0:
                                guess = thr[a, b - 1] + thr[a - 1, b] - thr[a - 1, b - 1]
                            elif b > 0:
                                guess = thr[a, b - 1]
                            elif a > 0:
                                guess = thr[a - 1, b]
                            else:
                                guess = np.nan
                            lo, hi = tau_t, np.inf
                            if err >= 0.0 and guess == guess:
                                delta = 3.0 * err + 1e-300
                                lo, hi = max(guess - delta, tau_t), guess + delta
                            while not _band_select(
                                t_h, t_w, t_i, t_j, m, pi, pj, table, n, lo, hi, band, band_w,
                                res,
                            ):  # fmt: skip
                                lo, hi = (hi, np.inf) if res[5] > 0 else (tau_t, lo)
                            wsum, z0, fn, fn1 = res[0], res[1], res[2], res[3]
                            out_w[a, b] = wsum + frac * res[4]
                            out_z[a, b] = z0
                            out_l[a, b] = fn - frac * (fn - fn1)
                            thr[a, b] = fn1
                            if guess == guess:
                                e = abs(fn1 - guess)
                                err = e if err < 0.0 else 0.7 * err + 0.3 * e


@numba.njit(cache=True, nogil=True)
def _band_select(
    t_h: np.ndarray,
    t_w: np.ndarray,
    t_i: np.ndarray,
    t_j: np.ndarray,
    m: int,
    pi: int,
    pj: int,
    table: np.ndarray,
    n: int,
    g_lo: float,
    g_hi: float,
    band: np.ndarray,
    band_w: np.ndarray,
    res: np.ndarray,
) -> bool:  # pragma: no cover - jit
    """Exact contact of the position (pi, pj) from the tile's candidates, if its threshold
    fn1 (the (n+1)-th largest F) lies in [g_lo, g_hi]; returns False otherwise.

    One branch-free pass sums the pixels above g_hi (all in the contact) and gathers the band
    [g_lo, g_hi] in raster order; the selection runs on the band only. ``res`` receives
    (Σw over the n largest, z0 = max F, n-th largest F, fn1, w of the (n+1)-th pixel)."""
    khi = 0
    kb = 0
    w_hi = 0.0
    z_hi = -np.inf
    fmin_hi = np.inf
    for c in range(m):
        v = t_h[c] - table[abs(t_i[c] - pi), abs(t_j[c] - pj)]
        hi = v > g_hi
        khi += hi
        w_hi += t_w[c] if hi else 0.0
        z_hi = max(z_hi, v)
        fmin_hi = min(fmin_hi, v if hi else np.inf)
        band[kb] = v
        band_w[kb] = t_w[c]
        kb += (not hi) and v >= g_lo
    if khi > n or khi + kb < n + 1:
        res[5] = 1.0 if khi > n else -1.0
        return False
    scratch = band[kb : 2 * kb]
    scratch[:] = band[:kb]
    fn1 = _kth_largest_inplace(scratch, kb, n + 1 - khi)
    cnt = khi
    wsum = w_hi
    fmin = fmin_hi
    w_next = 0.0
    need = -1
    for c in range(kb):
        v = band[c]
        if v > fn1:
            cnt += 1
            wsum += band_w[c]
            fmin = min(fmin, v)
    # ties at the boundary: taken in raster order, like the reference's stable sort
    need = n - cnt
    for c in range(kb):
        if band[c] == fn1:
            if need > 0:
                wsum += band_w[c]
                need -= 1
            else:
                w_next = band_w[c]
                break
    z0 = z_hi
    if n == 0 or cnt == 0:
        z0 = fn1
    fn = fn1 if (n == 0 or cnt < n) else fmin
    res[0] = wsum
    res[1] = z0
    res[2] = fn
    res[3] = fn1
    res[4] = w_next
    return True


def bearing_area(
    topo: Topography,
    *,
    diameter: float,
    pressure: float,
    hardness: float,
    shape: str = "sphere",
    stride: int = 1,
    block: int | tuple[int, int] = (4, 4),
    superblock: int | tuple[int, int] = (4, 4),
) -> BearingMap:
    """Bearing model of one grain size over the raster (eq. 5–9; see the module docstring).

    Parameters
    ----------
    topo
        Base topography [m] (form removed and filtered as the caller wishes; missing pixels are
        filled harmonically).
    diameter
        Grain diameter D [m].
    pressure
        Macroscopic pressure p_macro [Pa] (the seed: 20 kPa).
    hardness
        Ice hardness H_ice [Pa] (:func:`~skisnow.micro.ice_hardness`).
    shape
        ``'sphere'`` (exact) or ``'paraboloid'``.
    stride
        Raster step in pixels (1 = every pixel centre).
    block
        Positions per side of the tile that shares one candidate list (performance only).
    superblock
        Tiles per side of the super-tile whose search window is scanned once (performance
        only; results identical).
    """
    h, radius, ci, cj = _check(topo, diameter, pressure, hardness, shape, stride)
    w = slope_factor(topo.__class__(h, topo.dx, topo.dy, topo.source))
    dx, dy = topo.dx, topo.dy
    nstar = pressure * diameter**2 / (hardness * dx * dy)
    n = math.floor(nstar)
    frac = nstar - n
    pos = _positions(h.shape, ci, cj, stride)
    # a priori search radius: s(r) <= range(h) + s(rho*), rho* holding N*+1 pixels
    rho = math.sqrt((n + 2) * dx * dy / math.pi) + math.hypot(dx, dy)
    s_rho = float(_sag(np.array(min(rho, radius) ** 2), radius, shape))
    reach = float(np.ptp(h)) + s_rho
    r_max = radius if reach >= radius else math.sqrt(min(2 * radius * reach, radius**2))
    if shape == "paraboloid":
        r_max = min(math.sqrt(2 * radius * reach), radius)
    ux = min(math.ceil(r_max / dx), ci)
    uy = min(math.ceil(r_max / dy), cj)
    ii = np.unique(pos[:, 0]).astype(np.int64)
    jj = np.unique(pos[:, 1]).astype(np.int64)
    bx, by = (block, block) if np.isscalar(block) else block  # type: ignore[misc]
    bx, by = max(1, int(bx)), max(1, int(by))
    sx, sy = (superblock, superblock) if np.isscalar(superblock) else superblock  # type: ignore[misc]
    sx, sy = bx * max(1, int(sx)), by * max(1, int(sy))
    # sag at every integer pixel offset a window can hold, as the reference computes it
    ea = ux + (min(sx, ii.size) - 1) * stride
    eb = uy + (min(sy, jj.size) - 1) * stride
    oa = np.arange(ea + 1) * dx
    ob = np.arange(eb + 1) * dy
    table = np.ascontiguousarray(_sag(oa[:, None] ** 2 + ob[None, :] ** 2, radius, shape))
    grid_w = np.empty((ii.size, jj.size))
    grid_z = np.empty_like(grid_w)
    grid_l = np.empty_like(grid_w)
    _bearing_kernel(
        np.ascontiguousarray(h, dtype=np.float64),
        np.ascontiguousarray(w, dtype=np.float64),
        ii,
        jj,
        ux,
        uy,
        min(ux, math.ceil(rho / dx)),
        min(uy, math.ceil(rho / dy)),
        float(np.max(h)),
        table,
        n,
        frac,
        bx,
        by,
        sx,
        sy,
        grid_w,
        grid_z,
        grid_l,
    )
    out_w = grid_w.ravel()
    out_z = grid_z.ravel()
    out_l = grid_l.ravel()
    return _result(topo, diameter, pressure, hardness, pos, out_w, out_z, out_l, nstar)


def bearing_area_reference(
    topo: Topography,
    *,
    diameter: float,
    pressure: float,
    hardness: float,
    shape: str = "sphere",
    stride: int = 1,
) -> BearingMap:
    """The naive bearing model: for each position, all pixels of the footprint disc are sorted
    by F. Same discretisation as :func:`bearing_area`; slow, for checking it on small maps."""
    h, radius, ci, cj = _check(topo, diameter, pressure, hardness, shape, stride)
    w = slope_factor(topo.__class__(h, topo.dx, topo.dy, topo.source))
    dx, dy = topo.dx, topo.dy
    nstar = pressure * diameter**2 / (hardness * dx * dy)
    n = math.floor(nstar)
    frac = nstar - n
    pos = _positions(h.shape, ci, cj, stride)
    oi = np.arange(-ci, ci + 1)
    oj = np.arange(-cj, cj + 1)
    r2 = (oi[:, None] * dx) ** 2 + (oj[None, :] * dy) ** 2
    sag = _sag(r2, radius, shape)
    inside = np.isfinite(sag)
    wsum = np.empty(len(pos))
    z0 = np.empty(len(pos))
    level = np.empty(len(pos))
    for k, (i, j) in enumerate(pos):
        win = (slice(i - ci, i + ci + 1), slice(j - cj, j + cj + 1))
        f = (h[win] - sag)[inside]
        ww = w[win][inside]
        order = np.argsort(-f, kind="stable")
        fs = f[order]
        wsum[k] = ww[order[:n]].sum() + frac * ww[order[n]]
        z0[k] = fs[0]
        level[k] = fs[0] if n == 0 else fs[n - 1] - frac * (fs[n - 1] - fs[n])
    return _result(topo, diameter, pressure, hardness, pos, wsum, z0, level, nstar)


def bearing_sweep(
    topo: Topography,
    *,
    diameters: Sequence[float] | np.ndarray,
    pressure: float,
    hardness: float,
    shape: str = "sphere",
    stride: int = 1,
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> BearingSweep:
    """Mean fractional area A_fr(D) over a range of grain diameters [m] (seed Fig. 6–7).

    ``workers`` threads process different diameters at once (the compiled kernel releases the
    GIL, so 2 workers use both cores); ``progress(done, total)`` is called after each diameter.
    """
    ds = np.asarray(diameters, dtype=np.float64).ravel()
    if ds.size == 0:
        raise InputError("no grain diameters given")
    filled = fill_missing(topo)

    def one(d: float) -> BearingMap:
        return bearing_area(
            filled,
            diameter=float(d),
            pressure=pressure,
            hardness=hardness,
            shape=shape,
            stride=stride,
        )

    maps: list[BearingMap] = []
    if workers > 1:
        with ThreadPoolExecutor(max_workers=int(workers)) as pool:
            for k, m in enumerate(pool.map(one, ds)):
                maps.append(m)
                if progress:
                    progress(k + 1, ds.size)
    else:
        for k, d in enumerate(ds):
            maps.append(one(d))
            if progress:
                progress(k + 1, ds.size)
    return BearingSweep(
        diameters=ds,
        fractional_area=np.array([m.mean_fractional_area for m in maps]),
        fractional_area_std=np.array([float(np.std(m.fractional_area)) for m in maps]),
        mean_penetration=np.array([float(np.mean(m.penetration)) for m in maps]),
        max_penetration=np.array([float(np.max(m.penetration)) for m in maps]),
        n_positions=np.array([len(m.positions) for m in maps]),
        pressure=float(pressure),
        hardness=float(hardness),
        shape=shape,
        stride=int(stride),
    )
