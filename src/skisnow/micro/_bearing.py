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
positions are processed in blocks (default 6 × 6) and everything else is pruned by bounds:

1. Any pixel with F(x) < τ (τ = (⌊N*⌋+1)-th largest F of that position) is irrelevant.
2. For a block B of positions, F_x0(x) ≤ h(x) − s(d_min(x, B)) and F_x0(x) ≥ h(x) − s(d_max(x, B))
   for every x0 in B (s increases with r). The (⌊N*⌋+1)-th largest of the lower bound is a lower
   bound τ_B of every position's τ; pixels whose upper bound is below τ_B are dropped.
3. For the survivors the exact F is evaluated for every position of the block and the top
   ⌊N*⌋+1 are selected with ``argpartition`` (vectorised over the block's positions).

The search window around a block is bounded a priori: a pixel at distance r can only compete if
s(r) ≤ max h − min h + s(ρ*), ρ* the radius holding N*+1 pixels. :func:`bearing_area_reference`
is the naive search over the whole footprint, kept in the library to check this one.

Cost (measured, ``benchmarks/bench_bearing.py``): about 4–5 candidate pixels per contact pixel
survive the bounds, i.e. ~45 µs per position and grain size on this 2-core machine; the naive
search is ~300× slower. The target case (1 mm², 1 µm, 31 sizes, 5.2 million position–size
pairs) therefore takes minutes, not the 30 s aimed at; ``stride`` trades positions for time
(stride 3 changed the mean A_fr by < 4·10⁻⁵ relative on preset S3).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

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


def _select(
    f: np.ndarray, w: np.ndarray, n: int, frac: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For rows of F values and per-column weights w: (Σ w over the contact, z0 = max F,
    F at the fractional step)."""
    idx = np.argpartition(-f, n, axis=1)
    top = idx[:, :n]
    nxt = idx[:, n]
    rows = np.arange(f.shape[0])
    ftop = np.take_along_axis(f, top, axis=1)
    wsum = w[top].sum(axis=1) + frac * w[nxt]
    fn1 = f[rows, nxt]
    if n == 0:  # less than one pixel: part of the highest one, at δ = 0
        return wsum, fn1, fn1
    fn = ftop.min(axis=1)
    level = fn - frac * (fn - fn1)  # δ interpolated between the n-th and (n+1)-th step
    return wsum, ftop.max(axis=1), level


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


def bearing_area(
    topo: Topography,
    *,
    diameter: float,
    pressure: float,
    hardness: float,
    shape: str = "sphere",
    stride: int = 1,
    block: int | tuple[int, int] = (6, 6),
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
        Positions per block side of the pruned search (performance only; results identical).
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
    ii = np.unique(pos[:, 0])
    jj = np.unique(pos[:, 1])
    bx, by = (block, block) if np.isscalar(block) else block  # type: ignore[misc]
    bx, by = max(1, int(bx)), max(1, int(by))
    # sag of every integer pixel offset that a block can reach (lookup instead of sqrt per pair)
    ex, ey = ux + (bx - 1) * stride, uy + (by - 1) * stride
    oi = np.arange(-ex, ex + 1) * dx
    oj = np.arange(-ey, ey + 1) * dy
    sag_table = _sag(oi[:, None] ** 2 + oj[None, :] ** 2, radius, shape).ravel()
    width = 2 * ey + 1
    centre = ex * width + ey
    hflat = h.ravel()
    wflat = w.ravel()
    ny = h.shape[1]
    bounds: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}

    def window_bounds(mi: int, mj: int) -> tuple[np.ndarray, np.ndarray]:
        """Sag at the largest / smallest distance from a block of mi × mj positions."""
        if (mi, mj) not in bounds:
            ext_i = np.arange(-ux, (mi - 1) * stride + ux + 1)
            ext_j = np.arange(-uy, (mj - 1) * stride + uy + 1)
            last_i, last_j = (mi - 1) * stride, (mj - 1) * stride
            dmin_i = np.maximum(0, np.maximum(-ext_i, ext_i - last_i)) * dx
            dmin_j = np.maximum(0, np.maximum(-ext_j, ext_j - last_j)) * dy
            dmax_i = np.maximum(np.abs(ext_i), np.abs(ext_i - last_i)) * dx
            dmax_j = np.maximum(np.abs(ext_j), np.abs(ext_j - last_j)) * dy
            bounds[(mi, mj)] = (
                _sag(dmax_i[:, None] ** 2 + dmax_j[None, :] ** 2, radius, shape),
                _sag(dmin_i[:, None] ** 2 + dmin_j[None, :] ** 2, radius, shape),
            )
        return bounds[(mi, mj)]

    grid_w = np.empty((ii.size, jj.size))
    grid_z = np.empty_like(grid_w)
    grid_l = np.empty_like(grid_w)
    for bi in range(0, ii.size, bx):
        pi = ii[bi : bi + bx]
        i0, i1 = pi[0] - ux, pi[-1] + ux + 1
        for bj in range(0, jj.size, by):
            pj = jj[bj : bj + by]
            j0, j1 = pj[0] - uy, pj[-1] + uy + 1
            sag_far, sag_near = window_bounds(pi.size, pj.size)
            hw = h[i0:i1, j0:j1]
            lower = (hw - sag_far).ravel()
            k = lower.size - (n + 1)
            tau = np.partition(lower, k)[k]
            ci_, cj_ = np.nonzero(hw - sag_near >= tau)
            cand = (ci_ + i0) * ny + (cj_ + j0)  # flat pixel index
            cand_off = (ci_ + i0) * width + (cj_ + j0)
            pos_off = (pi[:, None] * width + pj[None, :]).ravel()
            f = hflat[cand][None, :] - sag_table[cand_off[None, :] - pos_off[:, None] + centre]
            wsum, z0, level = _select(f, wflat[cand], n, frac)
            sl = (slice(bi, bi + pi.size), slice(bj, bj + pj.size))
            grid_w[sl] = wsum.reshape(pi.size, pj.size)
            grid_z[sl] = z0.reshape(pi.size, pj.size)
            grid_l[sl] = level.reshape(pi.size, pj.size)
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

    ``workers`` threads process different diameters at once (NumPy releases the GIL in the
    heavy kernels); ``progress(done, total)`` is called after each diameter.
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
