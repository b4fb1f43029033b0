"""Elastic–perfectly-plastic contact of a base topography with a flat ice surface (Scherge et
al. 2021, §3.5 and Fig. 3).

Scherge et al. (2021) justify the purely plastic bearing model by comparing it with an
elastic–plastic calculation (Pastewka et al. 2012) of the base against a FLAT ice surface of
hardness H at 20 kPa: the ranking of S1–S5 was the same. This module does that calculation.

Model: both bodies are elastic half-spaces with the equivalent modulus E' of the contact
package's convention (2/E' = Σ(1 − ν²)/E, :func:`skisnow.contact.effective_modulus`; ice
9.5 GPa/0.31 and UHMWPE 840 MPa/0.46 give E' = 1.93 GPa), the pressure is capped by the hardness
(0 ≤ p ≤ H, perfectly plastic ice: where p = H the surfaces may overlap, the excess flows away
plastically). With gap g = u − h + d (u = K∗p from :func:`skisnow.contact.surface_convolution`,
non-periodic, zero-padded FFT; d the rigid approach):

    0 < p < H ⇒ g = 0,   p = 0 ⇒ g ≥ 0,   p = H ⇒ g ≤ 0,   mean(p) = p_macro.

Solver: for a given approach d, the contact package's Polonsky–Keer core
(:func:`skisnow.contact.polonsky_keer`, Polonsky & Keer 1999) under displacement control with
its hardness cap (the box 0 ≤ p ≤ H, as in Sainsot & Lubrecht 2011: the CG runs on the free cells
and on the cells at H that the gap pushes back, iterates are projected on the box), converged
when Σ|Δp|/Σp ≤ ``tol``. The load is then met by Brent's method on d (mean p decreases
monotonically with d), each inner solve warm-started from the previous pressure. (A
load-controlled PK with the cap stalled when almost every contact point is plastic, which is
the normal case here: E'/H ≈ 100.)

Also here: :func:`flat_plastic_area`, the purely plastic limit against a flat (the highest pixels
carry H until the load is reached — the "bearing area" of Fig. 3's grey curve).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skisnow._errors import ConvergenceError, InputError, SolverStatus
from skisnow.contact import (
    CellOperator,
    effective_modulus,
    polonsky_keer,
    surface_convolution,
)
from skisnow.micro._bearing import slope_factor
from skisnow.micro._ice import ICE, UHMWPE
from skisnow.micro._topography import Topography, fill_missing, make_topography

__all__ = [
    "ElastoplasticResult",
    "elastoplastic_contact",
    "flat_plastic_area",
    "ice_base_modulus",
]


def ice_base_modulus() -> float:
    """Equivalent modulus E' [Pa] of ice on UHMWPE (Table 2), contact-package convention."""

    return effective_modulus(ICE, UHMWPE)


@dataclass(frozen=True, eq=False)
class ElastoplasticResult:
    """Pressure [Pa], gap [m] and contact areas of the flat-ice contact.

    ``fractional_area`` is the projected contact fraction (p > 0), ``real_fractional_area``
    weights each contact pixel with √(1 + |∇h|²) (eq. 8), ``plastic_fraction`` is the share of
    contact pixels at p = H. ``residual`` is the last Σ|Δp|/Σp of the final inner solve and
    ``status`` how that solve ended (:class:`~skisnow.SolverStatus`); ``converged`` also asks
    that the mean pressure meets the load to 1e-6.
    """

    pressure: np.ndarray
    gap: np.ndarray
    approach: float
    fractional_area: float
    real_fractional_area: float
    plastic_fraction: float
    mean_pressure: float
    iterations: int
    residual: float
    converged: bool
    status: SolverStatus


def flat_plastic_area(topo: Topography, *, pressure: float, hardness: float) -> tuple[float, float]:
    """Purely plastic contact with a flat: the N* = N·p/H highest pixels (fraction of the last)
    carry H. Returns (projected fraction = p/H exactly, real fraction with the slope factor)."""
    h = np.asarray(fill_missing(topo).heights).ravel()
    w = slope_factor(make_topography(h.reshape(topo.shape), dx=topo.dx, dy=topo.dy)).ravel()
    nstar = h.size * pressure / hardness
    n = math.floor(nstar)
    order = np.argsort(-h, kind="stable")
    real = (w[order[:n]].sum() + (nstar - n) * w[order[n]]) / h.size
    return nstar / h.size, float(real)


def elastoplastic_contact(
    topo: Topography,
    *,
    pressure: float,
    hardness: float,
    modulus: float | None = None,
    tol: float = 1e-8,
    max_iter: int = 5000,
    precondition: bool = False,
    raise_on_failure: bool = False,
) -> ElastoplasticResult:
    """Elastic–perfectly-plastic contact of ``topo`` with a flat (see the module docstring).

    Parameters
    ----------
    topo
        Base topography [m]; heights toward the ice.
    pressure
        Mean (nominal) pressure over the map [Pa].
    hardness
        Ice hardness H [Pa] (the cap of p); ``np.inf`` gives the purely elastic contact.
    modulus
        Equivalent modulus E' [Pa]; default :func:`ice_base_modulus`.
    tol
        Tolerance of every inner solve on Σ|Δp|/Σp (Polonsky & Keer 1999).
    max_iter
        Iteration limit of every inner solve.
    precondition
        Precondition the inner solves with the circulant inverse of the half-space (Vollebregt
        2014). Off by default: on the grinds it saves a quarter of the iterations but costs an
        FFT pair more per iteration (measured: 82 against 107 iterations, 210 against 158
        FFTs on a 200² S3 map).
    raise_on_failure
        Raise :class:`~skisnow.ConvergenceError` (with ``.result``) when not converged.

    Returns
    -------
    ElastoplasticResult
        Pressure, gap, approach, areas, and the convergence report with its status.
    """
    if not (pressure > 0 and np.isfinite(pressure)):
        raise InputError(f"pressure must be positive [Pa], got {pressure}")
    if not (hardness > pressure):
        raise InputError(f"hardness must exceed the mean pressure [Pa], got {hardness}")
    e = ice_base_modulus() if modulus is None else float(modulus)
    h = np.asarray(fill_missing(topo).heights, dtype=np.float64)
    nx, ny = h.shape
    conv = surface_convolution((nx, ny), topo.dx, topo.dy, modulus=e)
    scale = max(float(np.ptp(h)), 1e-300)
    operator = CellOperator(conv)
    inverse = CellOperator(conv.inverse()) if precondition else None
    state: dict = {"p": np.zeros(h.size), "iterations": 0, "residual": math.inf, "ok": True}
    relief = -h.ravel()  # the core's profile: g = −h + u + d

    def solve_at(d: float) -> float:
        """Displacement-controlled PK with the cap; returns mean(p) − pressure."""
        res = polonsky_keer(
            operator, relief, p0=state["p"], control="displacement",
            target=np.full(h.size, -d), hardness=hardness, preconditioner=inverse,
            tol=tol, max_iter=max_iter,
        )  # fmt: skip
        state["p"] = res.pressure
        state["iterations"] += res.iterations
        state["residual"] = res.residual
        state["ok"] = res.converged
        state["status"] = res.status
        return float(res.pressure.mean()) - pressure

    # bracket the rigid approach d: p = 0 everywhere for d >= max h; the purely plastic level
    # (N·p/H highest pixels at H) with the largest elastic displacement possible below it
    order = np.sort(h.ravel())[::-1]
    d_plastic = float(order[min(int(h.size * pressure / hardness), h.size - 1)])
    from scipy.optimize import brentq

    hi = d_plastic
    f_hi = solve_at(hi)
    if f_hi > 0:  # cannot happen for an elastic body (it carries less than the plastic one)
        hi = float(h.max())
        f_hi = solve_at(hi)
    step = 0.01 * scale
    lo = hi - step
    while solve_at(lo) < 0:  # expand downward until the load is exceeded
        hi, step = lo, 2.0 * step
        lo = hi - step
    approach = brentq(solve_at, lo, hi, xtol=1e-6 * tol * scale, rtol=1e-14, maxiter=200)
    solve_at(approach)
    p = state["p"].reshape(h.shape)
    residual = float(state["residual"])
    converged = bool(state["ok"] and abs(p.mean() - pressure) <= 1e-6 * pressure)
    it = int(state["iterations"])
    w = slope_factor(make_topography(h, dx=topo.dx, dy=topo.dy))
    contact = p > 0
    n_contact = int(contact.sum())
    gap = conv(p) - h + approach
    result = ElastoplasticResult(
        pressure=p,
        gap=gap,
        approach=float(approach),
        fractional_area=n_contact / h.size,
        real_fractional_area=float(w[contact].sum()) / h.size,
        plastic_fraction=float((p >= hardness).sum()) / max(n_contact, 1),
        mean_pressure=float(p.mean()),
        iterations=it,
        residual=residual,
        converged=converged,
        status=state["status"],
    )
    if not converged and raise_on_failure:
        raise ConvergenceError(
            f"elastoplastic contact: residual {residual:.3g} after {it} iterations (tol {tol})",
            result=result,
        )
    return result
