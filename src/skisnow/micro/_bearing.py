"""The bearing model of plastic ice grains on a ski-base topography (Scherge et al. 2021, eq. 5–9).

Model (Scherge et al. 2021 §3.7, with the symbols lost in its typesetting reconstructed). A
loose, rounded ice grain is a sphere of diameter D = 2R pressed against the base topography
h(x, y) [m] (heights pointing out of the base, toward the snow). At a raster position (x0, y0) the
sphere's centre is lowered along the normal until it first touches the base — *it settles into
the valley under it*: the first-contact height of the sphere's lowest point is

    z0(x0, y0) = max_{(x, y) in footprint} [ h(x, y) − s(|x − x0|) ],   s(r) = R − √(R² − r²),

i.e. the grey-scale dilation of h by the sphere (the "rolling ball"; s is the sag of the sphere
surface at distance r from its axis). The ice then yields plastically (its hardness is far below
that of UHMWPE, see :func:`~skisnow.micro.deformation_regime`), and the base is pressed a further
δ into the grain until the projected contact area (eq. 6–7, gap g = s − h + z0 − δ)

    A0(δ) = ∬ Θ(−g) dx dy

carries the load share of one grain at the hardness (eq. 5):  A0(δ)·H_ice = p_macro·(2R)².
The real area (eq. 8) is the base surface wrapped by the ice, A = ∬ Θ(−g)·√(1 + |∇h|²) dx dy,
and the fractional area (eq. 9) is A_fr = A/(2R)². Scherge et al.'s figure of the result is the mean
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

The search is exact (no approximation beyond this discretisation) and compiled: its algorithm
and cost are described in :mod:`skisnow.micro._bearing_kernel`. :func:`bearing_area_reference`
is the naive search over the whole footprint, kept in the library to check it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from skisnow._errors import InputError
from skisnow.micro._bearing_kernel import bearing_search, block_max
from skisnow.micro._bearing_kernel import sag as _sag
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
    """Mean fractional contact area per grain size (A_fr(D) of Scherge et al. 2021, Fig. 6–7)."""

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


#: positions per side of a tile, tiles per side of a super-tile (performance only)
_BLOCK = (8, 8)
_SUPERBLOCK = (2, 2)


def slope_factor(topo: Topography) -> np.ndarray:
    """√(1 + |∇h|²) per pixel (eq. 8), central differences (one-sided at the edges)."""
    h = np.asarray(topo.heights)
    gx, gy = np.gradient(h, topo.dx, topo.dy)
    return np.sqrt(1.0 + gx * gx + gy * gy)


def _check(
    topo: Topography, diameter: float, pressure: float, hardness: float, shape: str, stride: int
) -> tuple[np.ndarray, float, int, int]:
    if shape not in ("sphere", "paraboloid"):
        raise InputError(f"shape {shape!r} unknown; valid: 'sphere', 'paraboloid'")
    from skisnow._checks import positive_finite  # the one positive-and-finite rule

    positive_finite("grain diameter", diameter, "m")
    positive_finite("macroscopic pressure", pressure, "Pa")
    if not (np.isfinite(hardness) and hardness > pressure):
        raise InputError(
            f"the ice hardness ({hardness * 1e-6:.4g} MPa) must exceed the macroscopic pressure "
            f"({pressure * 1e-3:.4g} kPa): at p/H >= 1 the base bears on the ice over its whole "
            "area and the bearing model (eq. 5-9) does not apply"
        )
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


def _prepare(
    topo: Topography,
    diameter: float,
    pressure: float,
    hardness: float,
    shape: str,
    stride: int,
    w: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, float, int, int, np.ndarray, float]:
    """Validated heights, slope factors (eq. 8; ``w`` if the caller computed them for this
    map already), R, footprint half-sizes [pixels], positions and N* = p(2R)²/(H·dx·dy), the
    pixels that carry the grain's load share (eq. 5)."""
    h, radius, ci, cj = _check(topo, diameter, pressure, hardness, shape, stride)
    if w is None:
        w = slope_factor(topo.__class__(h, topo.dx, topo.dy, topo.source))
    nstar = pressure * diameter**2 / (hardness * topo.dx * topo.dy)
    return h, w, radius, ci, cj, _positions(h.shape, ci, cj, stride), nstar


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


def bearing_area(
    topo: Topography,
    *,
    diameter: float,
    pressure: float,
    hardness: float,
    shape: str = "sphere",
    stride: int = 1,
    block: int | tuple[int, int] = _BLOCK,
    superblock: int | tuple[int, int] = _SUPERBLOCK,
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
        Macroscopic pressure p_macro [Pa] (Scherge et al. 2021: 20 kPa).
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

    Returns
    -------
    BearingMap
        Per position: fractional area A_fr (eq. 9), projected area, penetration δ and first
        contact z0 [m].

    Raises
    ------
    InputError
        Non-positive diameter or pressure, a hardness not above the pressure, an unknown shape,
        a stride < 1, or a map smaller than the grain's footprint.
    """
    return _bearing_area(topo, diameter, pressure, hardness, shape, stride, block, superblock)


def _bearing_area(
    topo: Topography,
    diameter: float,
    pressure: float,
    hardness: float,
    shape: str,
    stride: int,
    block: int | tuple[int, int],
    superblock: int | tuple[int, int],
    w: np.ndarray | None = None,
    bmax: np.ndarray | None = None,
) -> BearingMap:
    """:func:`bearing_area`, with the map's slope factors ``w`` and the block maxima of its
    heights ``bmax`` (``block_max`` of the kernel's module) when a sweep over grain
    sizes has computed them once for all sizes."""
    h, w, radius, ci, cj, pos, nstar = _prepare(
        topo, diameter, pressure, hardness, shape, stride, w
    )
    dx, dy = topo.dx, topo.dy
    n = math.floor(nstar)
    frac = nstar - n
    out_w, out_z, out_l = bearing_search(
        h, w, ii=np.arange(ci, h.shape[0] - ci, stride), jj=np.arange(cj, h.shape[1] - cj, stride),
        ci=ci, cj=cj, dx=dx, dy=dy, radius=radius, shape=shape, n=n, frac=frac, stride=stride,
        block=block, superblock=superblock, bmax=bmax,
    )  # fmt: skip
    return _result(topo, diameter, pressure, hardness, pos, out_w, out_z, out_l, nstar)


# The same signature as bearing_area on purpose (repeated, not shared): the reference is called
# with the same arguments to check it (tests/micro/test_bearing.py).
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
    h, w, radius, ci, cj, pos, nstar = _prepare(topo, diameter, pressure, hardness, shape, stride)
    dx, dy = topo.dx, topo.dy
    n = math.floor(nstar)
    frac = nstar - n
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
    """Mean fractional area A_fr(D) over a range of grain diameters [m] (Scherge et al. 2021,
    Fig. 6–7).

    ``workers`` threads process different diameters at once (the compiled kernel releases the
    GIL, so 2 workers use both cores); ``progress(done, total)`` is called after each diameter.
    """
    ds = np.asarray(diameters, dtype=np.float64).ravel()
    if ds.size == 0:
        raise InputError("no grain diameters given")
    filled = fill_missing(topo)
    # the slope factors and the heights' block maxima serve every size: computed once
    w = slope_factor(filled)
    bmax = block_max(np.asarray(filled.heights, dtype=np.float64))

    def one(d: float) -> BearingMap:
        return _bearing_area(
            filled, float(d), pressure, hardness, shape, stride, _BLOCK, _SUPERBLOCK, w, bmax
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
