"""The real contact along the ski: the micro curves evaluated at the apparent pressure p(x).

Every cell of the apparent contact (a station of the strip model, a cell of the surface model)
is a nominal patch of area dA under the nominal pressure p. Its micro contact is read off the
micro curves of the base × snow (:class:`~skisnow.multiscale.MicroCurves`):

* in apparent contact (p > 0): real area A_r = f(p)·dA (flat-ice model b, with the slope factor;
  the bearing model's f_grains(p)·dA beside it), mean separation ū(p) and ∫1/u dA = ⟨1/u⟩(p)·dA;
* out of it (p = 0, the ski lifted by the macroscopic gap G ≥ 0 of the apparent contact): no real
  area, separation G + ⟨h_max − h⟩ and ∫1/u dA = ⟨1/max(G + h_max − h, u_c)⟩·dA — the camber
  enters the viscous term here, near the edges of the contact patches where G is small.

What follows from the curves (stated so nobody is surprised): in the purely plastic bearing
model f(p) = (p/H)·s exactly, so Σ A_r = W·s/H whatever the camber — the pressure distribution
matters only through what is nonlinear in p: the elastic rims of the flat-ice contact at light
load, the separation and its reciprocal, and the film cut-off.

Per station, then per set of stations (:meth:`RealContact.summarize` takes boolean station
masks, so any grouping — regions fixed by the ski, contact patches — plugs in): apparent area,
real area, real fraction, mean separation over the apparent contact, total reciprocal
separation ∫1/u dA, and the friction proxies of :mod:`skisnow.multiscale._friction`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from skisnow._errors import InputError
from skisnow.multiscale._friction import ResolvedFriction

__all__ = ["RealContact", "RealSummary", "real_contact"]


@dataclass(frozen=True, kw_only=True)
class RealSummary:
    """The real contact of a set of stations (SI units; NaN where undefined)."""

    name: str
    stations: int
    load: float
    apparent_area: float
    real_area: float
    real_area_grains: float
    real_fraction: float
    mean_separation: float
    reciprocal_separation: float
    dry_force: float
    viscous_force: float
    lubricated_force: float

    def as_dict(self) -> dict[str, Any]:
        """Field units: N, cm², mm², µm, m (∫1/u dA), and the fraction."""
        return {
            "name": self.name,
            "stations": self.stations,
            "load_n": self.load,
            "apparent_area_cm2": self.apparent_area * 1e4,
            "real_area_mm2": self.real_area * 1e6,
            "real_area_grains_mm2": self.real_area_grains * 1e6,
            "real_fraction": self.real_fraction,
            "mean_separation_um": self.mean_separation * 1e6,
            "reciprocal_separation_m": self.reciprocal_separation,
            "dry_force_n": self.dry_force,
            "viscous_force_n": self.viscous_force,
            "lubricated_force_n": self.lubricated_force,
        }


@dataclass(frozen=True, kw_only=True, eq=False)
class RealContact:
    """The real contact per station along the ski (SI units; arrays of shape ``(n,)``).

    Attributes
    ----------
    x
        Stations [m].
    pressure
        Apparent pressure [Pa] (strip: per station; surface: the mean over the contact cells).
    apparent_area, real_area, real_area_grains
        Per station [m²]: cells in apparent contact; the real area of the flat-ice model (b) and
        of the bearing model (a).
    separation_integral
        Σ ū(p)·dA over the station's contact cells [m³] (for means over the contact).
    mean_separation
        Mean separation [m] over the station's whole width (in and out of contact).
    reciprocal
        ∫ 1/u dA over the station [m].
    load
        Σ p·dA per station [N].
    friction
        The parameters of the proxies (with sources).
    base, snow
        Names of the base and the snow of the micro curves.
    beyond
        Stations whose pressure exceeds the curves' last pressure (values held there).
    """

    x: np.ndarray
    pressure: np.ndarray
    apparent_area: np.ndarray
    real_area: np.ndarray
    real_area_grains: np.ndarray
    separation_integral: np.ndarray
    mean_separation: np.ndarray
    reciprocal: np.ndarray
    load: np.ndarray
    friction: ResolvedFriction
    base: str
    snow: str
    total_load: float
    beyond: np.ndarray = field(repr=False)

    @property
    def real_fraction(self) -> np.ndarray:
        """A_r/A_apparent per station (NaN out of contact)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.apparent_area > 0, self.real_area / self.apparent_area, np.nan)

    @property
    def dry_force(self) -> np.ndarray:
        """τ·A_r per station [N] (the area of ``friction.area_model``)."""
        area = self.real_area if self.friction.area_model == "flat-ice" else self.real_area_grains
        return self.friction.shear_strength * area

    @property
    def viscous_force(self) -> np.ndarray:
        """η·v·∫1/u dA per station [N]."""
        return self.friction.viscosity * self.friction.sliding_speed * self.reciprocal

    @property
    def lubricated_force(self) -> np.ndarray:
        """η·v·A_r/u_c per station [N]: the contact spots sheared through a film of u_c."""
        f = self.friction
        area = self.real_area if f.area_model == "flat-ice" else self.real_area_grains
        return f.viscosity * f.sliding_speed * area / f.film_cutoff

    #: The columns of :meth:`sums`, in order.
    SUM_COLUMNS: tuple[str, ...] = (
        "load", "apparent_area", "real_area", "real_area_grains", "separation_integral",
        "reciprocal_separation", "dry_force", "viscous_force", "lubricated_force",
    )  # fmt: skip

    def sums(self, masks: np.ndarray) -> np.ndarray:
        """``(k, 9)`` sums of :attr:`SUM_COLUMNS` over ``k`` station masks ``(k, n)`` (bool or
        0/1): one matrix product for every mask and quantity."""
        f = self.friction
        grains = f.area_model != "flat-ice"
        area = self.real_area_grains if grains else self.real_area
        vv = f.viscosity * f.sliding_speed
        q = np.stack([
            self.load, self.apparent_area, self.real_area, self.real_area_grains,
            self.separation_integral, self.reciprocal, f.shear_strength * area,
            vv * self.reciprocal, (vv / f.film_cutoff) * area,
        ])  # fmt: skip
        return np.asarray(masks, dtype=np.float64) @ q.T

    def summarize(self, masks: Mapping[str, np.ndarray]) -> dict[str, RealSummary]:
        """The real contact of every named set of stations (boolean masks over :attr:`x`)."""
        names = list(masks)
        m = np.zeros((len(names), self.x.size))
        for k, name in enumerate(names):
            mk = np.asarray(masks[name], dtype=bool)
            if mk.shape != self.x.shape:
                raise InputError(f"mask {name!r} has shape {mk.shape}; stations: {self.x.shape}")
            m[k] = mk
        sums = self.sums(m)
        counts = m.sum(axis=1)
        out: dict[str, RealSummary] = {}
        for k, name in enumerate(names):
            load, app, real, grains, sep, recip, dry, visc, lub = (float(v) for v in sums[k])
            out[name] = RealSummary(
                name=name,
                stations=int(counts[k]),
                load=load,
                apparent_area=app,
                real_area=real,
                real_area_grains=grains,
                real_fraction=real / app if app > 0 else math.nan,
                mean_separation=sep / app if app > 0 else math.nan,
                reciprocal_separation=recip,
                dry_force=dry,
                viscous_force=visc,
                lubricated_force=lub,
            )
        return out

    @property
    def total(self) -> RealSummary:
        """The whole ski."""
        return self.summarize({"total": np.ones(self.x.shape, dtype=bool)})["total"]

    def friction_estimate(self, total: RealSummary | None = None) -> dict[str, Any]:
        """µ = F/W with its terms and assumptions — never a bare number.

        ``mu`` = (τ·A_r + η·v·∫1/u dA)/W (dry real contact); ``mu_lubricated`` = (η·v·A_r/u_c
        + η·v·∫1/u dA)/W (the contact spots sheared through the film instead). ``total``: the
        whole ski's summary if already computed."""
        t = self.total if total is None else total
        w = self.total_load
        return {
            "mu": (t.dry_force + t.viscous_force) / w,
            "mu_lubricated": (t.lubricated_force + t.viscous_force) / w,
            "dry_force_n": t.dry_force,
            "viscous_force_n": t.viscous_force,
            "lubricated_force_n": t.lubricated_force,
            "load_n": w,
            "assumptions": self.friction.assumptions()
            + "; dry term: unlubricated real contact (upper bound); viscous term: a meltwater "
            "film fills every gap (Couette shear); no ploughing, compaction or capillary terms",
            "parameters": self.friction.as_dict(),
        }

    def as_dict(self) -> dict[str, Any]:
        """Totals in field units (see :meth:`RealSummary.as_dict`)."""
        return self.total.as_dict()


def real_contact(
    solution: Any,
    curves: Any,
    friction: ResolvedFriction,
) -> RealContact:
    """Evaluate the micro ``curves`` on the apparent contact ``solution`` (see the module
    docstring). ``solution`` is a :class:`~skisnow.contact.ContactSolution` (strip/line: one
    cell per station; surface: cells across the width, only those in the ski's footprint)."""
    p = np.asarray(solution.pressure, dtype=np.float64)
    gap = np.asarray(solution.gap, dtype=np.float64)
    da = float(solution.cell_area)
    uc = friction.film_cutoff
    surface = p.ndim == 2
    inside = np.asarray(solution.footprint, dtype=bool) if surface else None
    contact = (p > 0) & inside if surface else p > 0
    # the curves are evaluated where they apply: in contact at p, elsewhere at the gap
    flat_contact = contact.ravel()
    ci = np.flatnonzero(flat_contact)
    oi = np.flatnonzero((inside & ~contact).ravel() if surface else ~flat_contact)
    pc = p.ravel()[ci]
    n = p.size
    fr, frg, sep_in, sep, rec = np.zeros((5, n))
    fr[ci], frg[ci], sep_in[ci], rec[ci] = curves.contact_values(pc, uc)
    sep[ci] = sep_in[ci]
    go = np.maximum(gap.ravel()[oi], 0.0)
    sep[oi] = curves.rest_separation(go)
    rec[oi] = curves.rest_reciprocal(go, uc)
    beyond = np.zeros(n, dtype=bool)
    beyond[ci] = curves.beyond(pc)
    if surface:
        shape = p.shape
        w = inside.astype(np.float64) * da
        cw = contact.astype(np.float64) * da

        def along(v: np.ndarray) -> np.ndarray:
            return (v.reshape(shape) * w).sum(axis=1)

        def along_c(v: np.ndarray) -> np.ndarray:
            return (v.reshape(shape) * cw).sum(axis=1)

        app, width_area = cw.sum(axis=1), w.sum(axis=1)
        load = (p * w).sum(axis=1)
        beyond_along = beyond.reshape(shape).any(axis=1)
    else:  # one cell per station: the per-station values are the cells'

        def along(v: np.ndarray) -> np.ndarray:
            return v * da

        def along_c(v: np.ndarray) -> np.ndarray:
            return v * da  # zero off the contact already

        app = flat_contact * da
        width_area = np.full(n, da)
        load = p * da
        beyond_along = beyond
    pressure = np.divide(load, app, out=np.zeros_like(load), where=app > 0)
    mean_sep = np.divide(along(sep), width_area, out=np.zeros_like(load), where=width_area > 0)
    return RealContact(
        x=np.asarray(solution.x, dtype=np.float64),
        pressure=pressure,
        apparent_area=app,
        real_area=along_c(fr),
        real_area_grains=along_c(frg),
        separation_integral=along_c(sep_in),
        mean_separation=mean_sep,
        reciprocal=along(rec),
        load=load,
        friction=friction,
        base=curves.base,
        snow=curves.snow,
        total_load=float(solution.load),
        beyond=beyond_along,
    )
