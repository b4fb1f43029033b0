"""Elastic–perfectly-plastic flat-ice contact of a base texture over a range of nominal pressures:
real area, mean interfacial separation and the distribution of the gap (for ∫ 1/u dA).

For each nominal pressure p of a grid, the texture h (heights toward the snow) is pressed against
a flat ice half-space of equivalent modulus E' whose pressure is capped by the ice hardness H
(Scherge et al. 2021, §3.5: the ice yields; eq. 2 for H(T)), exactly as in
:func:`skisnow.micro.elastoplastic_contact`: the contact package's Polonsky–Keer core under
displacement control with the cap (Polonsky & Keer 1999; Sainsot & Lubrecht 2011), the rigid
approach d met to the load by a bracketing root search. Two things differ from a single solve:

* the pressures are solved in increasing order, each warm-started from the previous field and
  its approach (the curve costs a few solves per pressure, not a fresh bracket each time);
* the half-space is the mirror-continued one (:class:`~skisnow.micro._mirror.MirrorOperator`)
  by default: the map stands for a piece of a large, uniformly loaded contact.

Quantities per pressure (Persson 2007, J. Chem. Phys. 126: the average interfacial separation;
Kalliorinne et al. 2023, Lubricants 11(10) 427: real area, average and total reciprocal
interfacial separation):

* projected contact fraction (p > 0) and real fraction with the slope factor √(1 + |∇h|²)
  (Scherge et al. 2021, eq. 8); the share of contact pixels at p = H;
* mean separation ū = ⟨max(g, 0)⟩ over the whole map (g = u − h + d: zero in contact, the
  plastically flowed overlap counts as zero);
* the gap distribution over the non-contact pixels, as the area fraction and the sum of 1/g in
  log-spaced bins, so that the reciprocal separation ⟨1/u⟩ = (1/A₀) ∫_{non-contact}
  1/max(u, u_c) dA can be evaluated for any film cut-off u_c afterwards
  (:meth:`ElastoplasticCurve.reciprocal_separation`; exact when u_c is a bin edge: every
  10^(k/16) m, e.g. 0.1 µm);
* the gaps at zero load, h_max − h (quantiles), for separations outside the apparent contact.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from skisnow._errors import InputError
from skisnow.contact import polonsky_keer
from skisnow.micro._bearing import slope_factor
from skisnow.micro._mirror import MirrorOperator
from skisnow.micro._topography import Topography, fill_missing

__all__ = ["GAP_EDGES", "ElastoplasticCurve", "elastoplastic_curve", "reciprocal_from_bins"]

#: Bin edges of the gap distribution [m]: 16 per decade from 10 pm to 1 mm.
GAP_EDGES: np.ndarray = 10.0 ** (np.arange(-11 * 16, -3 * 16 + 1) / 16.0)
#: Quantiles of the zero-load gap h_max − h kept for the out-of-contact separation.
REST_QUANTILES: int = 513


@dataclass(frozen=True, kw_only=True, eq=False)
class ElastoplasticCurve:
    """The flat-ice contact of one texture over a grid of nominal pressures (SI units).

    Arrays are per pressure ``(n,)`` unless said otherwise.

    Attributes
    ----------
    pressures
        Nominal pressures asked for [Pa] (increasing).
    mean_pressure
        Mean pressure reached [Pa] (meets ``pressures`` to ``rtol``).
    fractional_area, real_fractional_area, plastic_fraction
        Projected contact fraction, with the slope factor (eq. 8), share of contact at H.
    mean_separation
        ū [m] over the whole map.
    gap_area, gap_reciprocal
        ``(n, m)``: area fraction of the non-contact pixels whose gap lies in each bin of
        :attr:`gap_edges`, and Σ(1/g)·dA/A₀ over them [1/m].
    gap_below
        Area fraction of non-contact pixels with a gap below ``gap_edges[0]`` (10 pm).
    gap_edges
        ``(m + 1,)`` bin edges [m].
    rest_gaps
        Quantiles of h_max − h [m] (the gaps at zero load), increasing.
    hardness, modulus
        H [Pa] and E' [Pa].
    iterations, converged, residual
        Core iterations, convergence (inner tolerance and load) and last Σ|Δp|/Σp, per pressure.
    """

    pressures: np.ndarray
    mean_pressure: np.ndarray
    fractional_area: np.ndarray
    real_fractional_area: np.ndarray
    plastic_fraction: np.ndarray
    mean_separation: np.ndarray
    gap_area: np.ndarray = field(repr=False)
    gap_reciprocal: np.ndarray = field(repr=False)
    gap_below: np.ndarray = field(repr=False)
    gap_edges: np.ndarray = field(repr=False)
    rest_gaps: np.ndarray = field(repr=False)
    hardness: float
    modulus: float
    iterations: np.ndarray
    converged: np.ndarray
    residual: np.ndarray

    def reciprocal_separation(self, film_cutoff: float) -> np.ndarray:
        """⟨1/u⟩ [1/m] per pressure: (1/A₀)∫ 1/max(u, u_c) dA over the non-contact area."""
        return reciprocal_from_bins(
            self.gap_edges, self.gap_area, self.gap_reciprocal, self.gap_below, film_cutoff
        )


def reciprocal_from_bins(
    edges: np.ndarray,
    area: np.ndarray,
    reciprocal: np.ndarray,
    below: np.ndarray,
    film_cutoff: float,
) -> np.ndarray:
    """Σ over bins of 1/max(g, u_c)·dA/A₀ from binned gaps (see :class:`ElastoplasticCurve`).

    Bins wholly above u_c contribute their Σ1/g, bins wholly below their area/u_c; in the bin
    that holds u_c the gaps are taken as log-uniformly spread (exact when u_c is an edge).
    """
    uc = float(film_cutoff)
    if not (math.isfinite(uc) and uc > 0):
        raise InputError(f"film cut-off must be positive [m], got {film_cutoff}")
    lo, hi = edges[:-1], edges[1:]
    share = np.clip(np.log(uc / lo) / np.log(hi / lo), 0.0, 1.0)  # part of each bin below u_c
    out = (area * share).sum(axis=-1) / uc + (reciprocal * (1.0 - share)).sum(axis=-1)
    return out + np.asarray(below) / uc


def _bins(gap: np.ndarray, free: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, ...]:
    """Area fraction and Σ(1/g)/N per gap bin over the ``free`` (non-contact) pixels, and the
    area fraction below the first edge (gaps of round-off size: they count as u_c later)."""
    n = gap.size
    g = gap[free]
    idx = np.searchsorted(edges, g, side="right") - 1
    inside = (idx >= 0) & (idx < edges.size - 1)
    area = np.bincount(idx[inside], minlength=edges.size - 1) / n
    recip = np.bincount(idx[inside], weights=1.0 / g[inside], minlength=edges.size - 1) / n
    return area, recip, float(np.count_nonzero(idx < 0)) / n


def elastoplastic_curve(
    topo: Topography,
    *,
    pressures: Sequence[float] | np.ndarray,
    hardness: float,
    modulus: float,
    boundary: str = "mirror",
    rtol: float = 1e-6,
    tol: float = 1e-8,
    max_iter: int = 5000,
) -> ElastoplasticCurve:
    """The flat-ice elastic–plastic contact of ``topo`` at every nominal pressure [Pa].

    Parameters
    ----------
    topo
        The prepared texture [m] (heights toward the ice; missing pixels are filled).
    pressures
        Nominal pressures [Pa], positive, below ``hardness`` (sorted here).
    hardness
        Ice hardness H [Pa] (the cap); ``np.inf`` for a purely elastic contact.
    modulus
        Equivalent modulus E' [Pa] of ice on the base.
    boundary
        ``'mirror'`` (default: the map continued by its mirror images, a piece of a large
        contact) or ``'free'`` (the zero-padded half-space under the map alone, as
        :func:`skisnow.micro.elastoplastic_contact`).
    rtol
        Relative tolerance on the mean pressure.
    tol, max_iter
        Tolerance Σ|Δp|/Σp and iteration limit of every inner solve.

    Returns
    -------
    ElastoplasticCurve
    """
    p_req = np.sort(np.asarray(pressures, dtype=np.float64).ravel())
    if p_req.size == 0 or not np.all(np.isfinite(p_req)) or np.any(p_req <= 0):
        raise InputError("pressures must be positive and finite [Pa]")
    if not hardness > p_req[-1]:
        raise InputError(
            f"the hardness ({hardness:.4g} Pa) must exceed the largest pressure "
            f"({p_req[-1]:.4g} Pa)"
        )
    h = np.asarray(fill_missing(topo).heights, dtype=np.float64)
    if boundary == "mirror":
        operator = MirrorOperator(h.shape, topo.dx, topo.dy, float(modulus))
    elif boundary == "free":
        from skisnow.contact import CellOperator, surface_convolution

        operator = CellOperator(surface_convolution(h.shape, topo.dx, topo.dy, modulus=modulus))
    else:
        raise InputError(f"boundary {boundary!r} unknown; valid: 'mirror', 'free'")
    flat = h.ravel()
    scale = max(float(np.ptp(h)), 1e-300)
    order = np.sort(flat)[::-1]
    weights = slope_factor(topo.__class__(h, topo.dx, topo.dy, topo.source)).ravel()
    state = {"p": np.zeros(flat.size), "it": 0, "res": math.nan, "ok": True}

    def solve_at(d: float) -> float:
        res = polonsky_keer(
            operator,
            -flat,
            p0=state["p"],
            control="displacement",
            target=np.full(flat.size, -d),
            hardness=hardness,
            tol=tol,
            max_iter=max_iter,
        )
        state["p"], state["res"], state["ok"] = res.pressure, res.residual, res.converged
        state["it"] += res.iterations
        return float(res.pressure.mean())

    n = p_req.size
    out: dict[str, list] = {
        k: [] for k in ("pm", "fa", "ra", "pl", "us", "ga", "gr", "gb", "it", "ok", "res")
    }
    ratio = 1.0  # the last pressure's N_contact·H/(N·p): the plastic level's correction
    approach = float(order[0])

    def level(load: float) -> float:
        """The height above which N·load/H pixels lie (the rigid-plastic approach)."""
        return float(order[min(int(flat.size * load / hardness), flat.size - 1)])

    for target in p_req:
        state["it"] = 0
        if math.isfinite(hardness):  # start at the plastic level, corrected by the last ratio
            d0 = level(target * ratio)
            step = abs(level(1.5 * target * ratio) - d0)
        else:  # elastic: from the last approach (the first: the highest pixel)
            d0, step = approach, 0.01 * scale
        approach = _meet(solve_at, target, d0, step, scale, rtol)
        p = state["p"]
        gap = operator(p) - flat + approach
        contact = p > 0
        n_contact = int(contact.sum())
        if math.isfinite(hardness):
            ratio = max(n_contact * hardness / (flat.size * target), 1.0)
        area, recip, below = _bins(gap, ~contact, GAP_EDGES)
        pm = float(p.mean())
        out["pm"].append(pm)
        out["fa"].append(n_contact / flat.size)
        out["ra"].append(float(weights[contact].sum()) / flat.size)
        out["pl"].append(float((p >= hardness).sum()) / max(n_contact, 1))
        out["us"].append(float(np.maximum(gap, 0.0).mean()))
        out["ga"].append(area)
        out["gr"].append(recip)
        out["gb"].append(below)
        out["it"].append(state["it"])
        out["ok"].append(bool(state["ok"] and abs(pm - target) <= rtol * target))
        out["res"].append(float(state["res"]))
    rest = np.quantile(order[0] - flat, np.linspace(0.0, 1.0, REST_QUANTILES))
    return ElastoplasticCurve(
        pressures=p_req,
        mean_pressure=np.array(out["pm"]),
        fractional_area=np.array(out["fa"]),
        real_fractional_area=np.array(out["ra"]),
        plastic_fraction=np.array(out["pl"]),
        mean_separation=np.array(out["us"]),
        gap_area=np.array(out["ga"]).reshape(n, -1),
        gap_reciprocal=np.array(out["gr"]).reshape(n, -1),
        gap_below=np.array(out["gb"]),
        gap_edges=GAP_EDGES.copy(),
        rest_gaps=np.sort(rest),
        hardness=float(hardness),
        modulus=float(modulus),
        iterations=np.array(out["it"], dtype=np.int64),
        converged=np.array(out["ok"], dtype=bool),
        residual=np.array(out["res"]),
    )


def _meet(solve_at, target: float, d0: float, step: float, scale: float, rtol: float) -> float:
    """The approach d with mean p(d) = target: from the guess ``d0``, steps of growing size
    until the sign of log(p̄/target) changes (p̄ falls monotonically with d), then the Illinois
    variant of regula falsi on log p̄."""

    def f(d: float) -> float:
        return math.log(max(solve_at(d), 1e-300) / target)

    a, fa = d0, f(d0)
    if abs(fa) <= rtol:
        return a
    step = max(step, 1e-6 * scale)
    for _ in range(200):  # expand until the sign changes
        b = a - step if fa < 0 else a + step
        fb = f(b)
        if abs(fb) <= rtol:
            return b
        if (fb > 0) != (fa > 0):
            break
        a, fa, step = b, fb, 2.0 * step
    else:  # pragma: no cover - the load is always reachable between max h and a deep approach
        raise InputError(f"no approach carries the mean pressure {target:g} Pa")
    c = b
    for _ in range(200):
        c = b - fb * (b - a) / (fb - fa)
        fc = f(c)
        if abs(fc) <= rtol or abs(b - a) <= 1e-12 * scale:
            return c
        if (fc > 0) != (fb > 0):
            a, fa = b, fb
        else:
            fa *= 0.5  # Illinois: the end kept twice has its value halved
        b, fb = c, fc
    return c  # pragma: no cover
