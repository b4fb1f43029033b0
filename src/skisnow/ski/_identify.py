"""Identify a ski's bending stiffness EI(x) and free camber z0(x) from camber-bench data.

The forward model is the bench itself (Kalliorinne et al. 2023, §3.1, eq. 1 h = f(x, m, x_m)):
an Euler–Bernoulli beam with stiffness EI(x) and stress-free shape z0(x), free-floating in
unilateral contact with the rigid stone, loaded by m·g through the boot plate at x_m
(:mod:`skisnow.ski._beam`, same Hermite elements and exact LCP). All load cases of the bench
(every mass and load position) are fitted at once by nonlinear least squares:

    min_p  Σ_k Σ_i n_ki (h_model(x̄_ki; m_k, x_mk, p) - h̄_ki)² / σ²  +  λ ||D₂ θ_E||²
           + λ_z ||D₂ θ_z / z_ref||²

* Parameters p: log EI(x) = Σ_j θ_E,j B_j(x) and z0(x) = Σ_j θ_z,j B_j(x), cubic B-splines on
  uniform knots (EI > 0 and smooth by construction). A linear function added to z0 is invisible
  to the bench (the ski's rigid motion absorbs it): θ_z is restricted to the complement of the
  linear coefficient vectors, and the result is returned resting on the plane (z0 = 0 at the two
  support points of its lower convex hull), the convention of :class:`~skisnow.ski.Ski`.
* Data: each profile is averaged over bins of ``bin_width`` (x̄, h̄, count n); the weights n make
  this the least-squares fit of every sample. σ is the bench noise, estimated from the scatter
  inside the bins (model-free: the profile varies by < 0.1 µm across a 5 mm bin).
* Exact Jacobian by the tangent of the beam at its active set (no finite differences): with the
  contact nodes A fixed, the clamped equilibrium K(θ_E) u = f + E_A r, the gap conditions
  z0(x_A) + a + b x_A + w_A = 0 and the balances Σr = F, Σ r x = M are linear in (u, r, a, b);
  differentiating them gives, per load case, one banded solve per stiffness parameter
  (K⁻¹ ∂K/∂θ_j u) and one small KKT solve (the same matrix as the forward problem). The active
  set is piecewise constant in p, so this is the derivative wherever it is defined.
* Optimiser: SciPy's trust-region reflective least squares (``scipy.optimize.least_squares``)
  with that Jacobian.
* Regularisation: λ on the second differences of log-EI coefficients, chosen by generalised
  cross-validation (GCV, Craven & Wahba 1979) on the Gauss–Newton linearisation at each fit,
  over a grid of λ (fits warm-started from the previous λ). λ_z is fixed small (z_ref = 1 mm,
  λ_z = 1): z0 is measured directly almost everywhere; the term only continues z0 smoothly over
  ends the bench did not measure.
* Uncertainty: the Gauss–Newton (sandwich) covariance of the penalised estimate,
  (JᵀJ + P)⁻¹ JᵀJ (JᵀJ + P)⁻¹ with σ-normalised residuals, propagated to log EI and to z0 (in
  the rest-on-the-plane gauge) at the stations of the identified ski. It is the noise-only
  (linearised) uncertainty; it does not include the bias of the regularisation.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import BSpline
from scipy.linalg import solveh_banded
from scipy.optimize import least_squares, minimize_scalar
from scipy.sparse import csr_matrix

from skisnow._errors import ConvergenceError, InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.ski._beam import DEFAULT_BOOT_LENGTH
from skisnow.ski._fem import (
    _GAUSS4_W,
    _GAUSS4_X,
    banded_upper,
    boot_load_vector,
    shape_functions,
)
from skisnow.ski._lcp import BeamLcp, lower_hull_bracket
from skisnow.ski._skis import Provenance, Ski

__all__ = ["IdentificationResult", "identify_ski"]

#: Default λ grid of the GCV search (penalty on second differences of log-EI coefficients, in
#: units of the σ-normalised misfit).
DEFAULT_LAMBDAS: tuple[float, ...] = (1e5, 1e4, 1e3, 1e2, 1e1)
_Z_REF = 1e-3  # [m]: scale of the z0 smoothness term
_LAMBDA_Z = 1.0
_LAMBDA_1 = 1.0


# --------------------------------------------------------------------------- data


@dataclass(frozen=True)
class _Case:
    mass: float
    position: float
    x: NDArray[np.float64]  # bin centres [m]
    h: NDArray[np.float64]  # bin means [m]
    w: NDArray[np.float64]  # sqrt(count)
    force: float
    f_boot: NDArray[np.float64]  # (2n,)
    f_total: float
    m_total: float
    hermite: Any  # sparse (n_bins, 2n)


def _bins(x: NDArray[np.float64], h: NDArray[np.float64], width: float):
    """Bin means (x̄, h̄, count) and the scatter about a straight line inside each bin (the
    profile's slope removed; its curvature changes h by < 0.1 µm across 5 mm): sum of squares
    and degrees of freedom (count - 2 per bin of >= 3 samples)."""
    key = np.floor(x / width + 1e-9).astype(np.int64)
    _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
    xs = np.bincount(inv, weights=x) / counts
    hs = np.bincount(inv, weights=h) / counts
    dx, dh = x - xs[inv], h - hs[inv]
    sxx = np.bincount(inv, weights=dx * dx)
    sxh = np.bincount(inv, weights=dx * dh)
    slope = np.divide(sxh, sxx, out=np.zeros_like(sxh), where=sxx > 0)
    ss = np.bincount(inv, weights=(dh - slope[inv] * dx) ** 2)
    dof = np.where(counts >= 3, counts - 2, 0)
    ss = np.where(counts >= 3, ss, 0.0)
    return xs, hs, counts.astype(float), float(ss.sum()), int(dof.sum())


def _hermite_matrix(nodes: NDArray[np.float64], x: NDArray[np.float64]) -> Any:
    n = nodes.size
    e = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, n - 2)
    le = nodes[e + 1] - nodes[e]
    nsh = shape_functions((x - nodes[e]) / le, le)  # (m, 4)
    rows = np.repeat(np.arange(x.size), 4)
    cols = (2 * e[:, None] + np.arange(4)[None, :]).ravel()
    return csr_matrix((nsh.ravel(), (rows, cols)), shape=(x.size, 2 * n))


# --------------------------------------------------------------------------- splines


def _uniform_bspline(x0: float, x1: float, n_coef: int) -> tuple[NDArray[np.float64], float]:
    """Knots of a cubic B-spline with ``n_coef`` coefficients on uniform knots whose base
    interval is [x0, x1] (basis functions extend beyond: linear functions have linear
    coefficients, Marsden's identity)."""
    h = (x1 - x0) / (n_coef - 3)
    t = x0 + h * np.arange(-3, n_coef + 1)
    return t, h


def _design(t: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    lo, hi = t[3], t[-4]
    xc = np.clip(x, lo, np.nextafter(hi, lo))  # the base interval is right-open
    return BSpline.design_matrix(xc, t, 3).toarray()


def _second_differences(n: int) -> NDArray[np.float64]:
    d = np.zeros((n - 2, n))
    for i in range(n - 2):
        d[i, i : i + 3] = (1.0, -2.0, 1.0)
    return d


# --------------------------------------------------------------------------- the model


class _Problem:
    """The bench sequence and the discretised beam; evaluates residuals and their Jacobian."""

    def __init__(
        self,
        cases: list[_Case],
        nodes: NDArray[np.float64],
        n_stiffness: int,
        n_camber: int,
        sigma: float,
    ) -> None:
        self.cases = cases
        self.nodes = nodes
        n = nodes.size
        self.n = n
        self.clamp = int(np.argmin(np.abs(nodes)))
        self.sigma = sigma
        x0, x1 = float(nodes[0]), float(nodes[-1])
        self.t_e, _ = _uniform_bspline(x0, x1, n_stiffness)
        self.t_z, _ = _uniform_bspline(x0, x1, n_camber)
        self.n_e, self.n_z = n_stiffness, n_camber
        # Gauss points of every element, and the B-spline of log EI there
        le = np.diff(nodes)[:, None]
        self.le = le
        xq = nodes[:-1, None] + le * _GAUSS4_X[None, :]
        self.phi_q = _design(self.t_e, xq.ravel()).reshape(n - 1, 4, n_stiffness)
        xi = _GAUSS4_X[None, :]
        self.bq = np.stack(
            [
                (-6.0 + 12.0 * xi) / le**2,
                (-4.0 + 6.0 * xi) / le,
                (6.0 - 12.0 * xi) / le**2,
                (-2.0 + 6.0 * xi) / le,
            ],
            axis=-1,
        )  # fmt: skip  (n_el, nq, 4): curvature per DOF
        self.wq = _GAUSS4_W[None, :] * le  # (n_el, nq)
        # z0: basis at nodes and at the bins; gauge: no linear part
        self.phi_z_nodes = _design(self.t_z, nodes)
        greville = (self.t_z[1:-3] + self.t_z[2:-2] + self.t_z[3:-1]) / 3.0
        lin = np.stack([np.ones(n_camber), greville], axis=1)
        q, _ = np.linalg.qr(lin, mode="complete")
        self.q_z = q[:, 2:]  # (n_z, n_z - 2), orthogonal to linear coefficient vectors
        self.lin_z = lin
        self.q_z_nodes = self.phi_z_nodes @ self.q_z
        self.phi_z_cases = [_design(self.t_z, c.x) for c in cases]
        self.q_z_cases = [phi @ self.q_z for phi in self.phi_z_cases]  # ∂z0(x̄)/∂φ per case
        self.d2_e = _second_differences(n_stiffness)
        self.d2_z = _second_differences(n_camber) / _Z_REF
        self.n_params = n_stiffness + n_camber - 2
        self.warm: list[NDArray[np.float64] | None] = [None] * len(cases)
        self.warm_active: list[NDArray[np.bool_] | None] = [None] * len(cases)
        self.n_data = int(sum(c.x.size for c in cases))

    # -- parameters
    def split(self, p: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return p[: self.n_e], self.q_z @ p[self.n_e :]

    def ei_at(self, theta_e: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.exp(_design(self.t_e, x) @ theta_e)

    def z0_at(self, theta_z: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
        return _design(self.t_z, x) @ theta_z

    # -- beam
    def _stiffness(self, theta_e: NDArray[np.float64]):
        ei_q = np.exp(self.phi_q @ theta_e)  # (n_el, nq)
        w = (self.wq * ei_q)[..., None, None]
        ke = np.sum(w * self.bq[..., :, None] * self.bq[..., None, :], axis=1)
        ab = banded_upper(ke, self.n)
        for dof in (2 * self.clamp, 2 * self.clamp + 1):
            ab[:, dof] = 0.0
            for j in range(dof, min(dof + 4, 2 * self.n)):
                ab[3 + dof - j, j] = 0.0
            ab[3, dof] = 1.0
        return ab, ei_q

    def _clamp(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        f = f.copy()
        f[2 * self.clamp : 2 * self.clamp + 2] = 0.0
        return f

    def evaluate(
        self, p: NDArray[np.float64], *, jacobian: bool, cases: Sequence[int] | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        """σ-normalised weighted residuals (model - data) of the chosen cases, and their
        Jacobian (rows of all bins, columns of p) if asked."""
        theta_e, theta_z = self.split(p)
        theta_e = np.clip(theta_e, -10.0, 25.0)  # coefficients of log EI: no overflow
        ab, ei_q = self._stiffness(theta_e)
        n = self.n
        rhs = np.zeros((2 * n, n))
        rhs[2 * np.arange(n), np.arange(n)] = 1.0
        rhs[2 * self.clamp, self.clamp] = 0.0
        flex_full = solveh_banded(ab, rhs, check_finite=False)
        flex = flex_full[0::2, :]
        flex = 0.5 * (flex + flex.T)
        z0n = self.phi_z_nodes @ theta_z
        idx_cases = range(len(self.cases)) if cases is None else cases
        res_parts, jac_parts = [], []
        f_all = np.stack([self._clamp(self.cases[k].f_boot) for k in idx_cases], axis=1)
        u_boot_all = solveh_banded(ab, f_all, check_finite=False)
        for col, k in enumerate(idx_cases):
            c = self.cases[k]
            u_boot = u_boot_all[:, col]
            g = z0n + u_boot[0::2]
            href = max(float(np.ptp(z0n)), 1e-3)
            lcp = BeamLcp(flex=flex, g=g, x=self.nodes, f_total=c.f_total, m_total=c.m_total,
                       tol_r=1e-10 * c.force, tol_h=1e-10 * href)  # fmt: skip
            ok = False
            prev = self.warm_active[k]
            if prev is not None and prev.sum() >= 2:  # a few block exchanges from the last set
                sol_ = lcp.block_pivoting(prev, max_iterations=6)
                ok = sol_.converged
            r0 = self.warm[k]
            if ok:
                pass
            elif r0 is None or np.any(r0 < 0):
                r0 = np.zeros(n)
                xc = c.m_total / c.f_total
                i, j = lower_hull_bracket(self.nodes, g, xc)
                r0[i] = c.f_total * (self.nodes[j] - xc) / (self.nodes[j] - self.nodes[i])
                r0[j] = c.f_total * (xc - self.nodes[i]) / (self.nodes[j] - self.nodes[i])
            if not ok:
                sol_ = lcp.primal_active_set(r0, 500)
                ok = sol_.converged
            if not ok:
                raise ConvergenceError(
                    f"beam contact of load case m = {c.mass:g} kg, x_m = {c.position * 1e3:g} mm "
                    "did not converge during the identification"
                )
            active, r, a, b = sol_.active, sol_.reactions, sol_.translation, sol_.rotation
            self.warm[k] = r
            self.warm_active[k] = active.copy()
            act = np.flatnonzero(active)
            u = u_boot + flex_full[:, act] @ r[act]
            hmod = self.phi_z_cases[k] @ theta_z + a + b * c.x + c.hermite @ u
            res_parts.append(c.w * (hmod - c.h) / self.sigma)
            if not jacobian:
                continue
            # tangent: K du = E_A dr - dK u ; gap rows; balances
            na = act.size
            kkt = np.zeros((na + 2, na + 2))
            kkt[:na, :na] = flex[np.ix_(act, act)]
            kkt[:na, na] = 1.0
            kkt[:na, na + 1] = self.nodes[act]
            kkt[na, :na] = 1.0
            kkt[na + 1, :na] = self.nodes[act]
            # dK/dθ_j u: curvature at Gauss points
            ue = np.stack([u[0:-2:2], u[1:-2:2], u[2::2], u[3::2]], axis=1)  # (n_el, 4)
            kappa = np.einsum("eqa,ea->eq", self.bq, ue)
            coef = self.wq * ei_q * kappa  # (n_el, nq)
            contrib = np.einsum("eq,eqa,eqj->eaj", coef, self.bq, self.phi_q)  # (n_el, 4, nE)
            g_mat = np.zeros((2 * n, self.n_e))
            for a_ in range(4):
                np.add.at(g_mat, 2 * np.arange(n - 1) + a_, contrib[:, a_, :])
            g_mat[2 * self.clamp : 2 * self.clamp + 2] = 0.0
            v = solveh_banded(ab, g_mat, check_finite=False)  # K^-1 dK u  (2n, nE)
            rhs_e = np.zeros((na + 2, self.n_e))
            rhs_e[:na] = v[2 * act]
            phi_za = self.q_z_nodes[act]  # (na, nφ)
            rhs_z = np.zeros((na + 2, self.n_z - 2))
            rhs_z[:na] = -phi_za
            sol = np.linalg.lstsq(kkt, np.concatenate([rhs_e, rhs_z], axis=1), rcond=None)[0]
            dr, da, db = sol[:na], sol[na], sol[na + 1]
            du = flex_full[:, act] @ dr  # (2n, nP)
            du[:, : self.n_e] -= v
            dh = c.hermite @ du + da[None, :] + c.x[:, None] * db[None, :]
            dh[:, self.n_e :] += self.q_z_cases[k]
            jac_parts.append((c.w / self.sigma)[:, None] * dh)
        res = np.concatenate(res_parts)
        jac = np.concatenate(jac_parts) if jacobian else None
        return res, jac

    def penalty_matrix(self, lam: float) -> NDArray[np.float64]:
        """Rows of the penalty residual sqrt(λ) D₂ θ_E, sqrt(λ₁) D₁ θ_E, sqrt(λ_z) D₂ θ_z / z_ref
        (linear in p). The weak first-difference term (λ₁ = 1) fixes the log-EI trend where
        the bench carries no bending moment (the free overhangs): there the data leave log EI
        undetermined, and without it a Gauss–Newton step runs off along that null direction."""
        rows_e = np.sqrt(lam) * np.concatenate(
            [self.d2_e, np.zeros((self.n_e - 2, self.n_z - 2))], axis=1
        )
        d1 = np.diff(np.eye(self.n_e), axis=0)
        rows_e = np.concatenate(
            [rows_e, np.sqrt(_LAMBDA_1) * np.concatenate(
                [d1, np.zeros((self.n_e - 1, self.n_z - 2))], axis=1)],
            axis=0,
        )  # fmt: skip
        rows_z = np.sqrt(_LAMBDA_Z) * np.concatenate(
            [np.zeros((self.n_z - 2, self.n_e)), self.d2_z @ self.q_z], axis=1
        )
        return np.concatenate([rows_e, rows_z], axis=0)


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, kw_only=True)
class IdentificationResult:
    """An identified ski and how it was obtained (SI units).

    Attributes
    ----------
    ski
        The identified :class:`Ski` (EI(x), z0(x) resting on the plane, their standard
        deviations ``stiffness_log_sd``/``camber_sd``, provenance).
    regularisation
        The chosen λ (penalty on second differences of log-EI coefficients).
    criterion
        How λ was chosen (``'gcv'`` or ``'given'``).
    gcv
        ``((λ, GCV score, misfit rms / σ, effective degrees of freedom), ...)`` of the search.
    noise
        Bench noise σ [m] used to normalise residuals (estimated from the scatter inside bins,
        or given).
    residual_rms
        RMS of model - data over all samples [m] (from the bins and their scatter).
    n_cases, n_samples, n_parameters
        Load cases, bench samples and fitted parameters.
    n_evaluations, converged, message
        Optimiser evaluations of the final fit, its status and message.
    seconds
        Wall time of the identification.
    """

    ski: Ski
    regularisation: float
    criterion: str
    gcv: tuple[tuple[float, float, float, float], ...]
    noise: float
    residual_rms: float
    n_cases: int
    n_samples: int
    n_parameters: int
    n_evaluations: int
    converged: bool
    message: str
    seconds: float


# --------------------------------------------------------------------------- entry point


def _zero_load_profile(cases: list[_Case]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A start for z0: the two lightest profiles at the load position with the most profiles,
    extrapolated linearly to zero load station by station (the deflection grows about linearly
    with the load while the contact set changes little; the rigid part is the gauge)."""
    positions = [c.position for c in cases]
    pos = max(set(positions), key=positions.count)
    at = sorted((c for c in cases if c.position == pos), key=lambda c: c.mass)
    if len(at) < 2:
        light = min(cases, key=lambda c: c.mass)
        return light.x, light.h
    a, b = at[0], at[1]
    hb = np.interp(a.x, b.x, b.h)
    return a.x, a.h - a.mass * (hb - a.h) / (b.mass - a.mass)


def _bench_cases(bench: Any, name: str) -> list[tuple[float, float, NDArray, NDArray]]:
    t = bench.table[bench.table["ski"] == name]
    out = []
    for (m, p), grp in t.groupby(["mass_kg", "load_position_mm"], sort=True):
        out.append(
            (float(m), float(p) * 1e-3, grp["x_mm"].to_numpy() * 1e-3,
             grp["height_mm"].to_numpy() * 1e-3)
        )  # fmt: skip
    return out


def identify_ski(
    bench: Any,
    *,
    ski: str | None = None,
    name: str | None = None,
    kind: str | None = None,
    x_tail: float | None = None,
    x_tip: float | None = None,
    width: float | None = None,
    kick_zone: tuple[float, float] | str | None = "bench",
    boot_length: float | None = None,
    n_stiffness: int = 14,
    n_camber: int = 100,
    bin_width: float = 0.005,
    element_length: float = 0.005,
    noise: float | None = None,
    regularisation: float | None = None,
    lambdas: Sequence[float] = DEFAULT_LAMBDAS,
    initial: Ski | None = None,
    max_nfev: int = 60,
    continuation: Sequence[float] = (1 / 3, 2 / 3),
    progress: Callable[[str], None] | None = None,
    source: str = "",
) -> IdentificationResult:
    """Identify EI(x) and z0(x) of a ski from a camber-bench sequence (all load cases at once).

    Nonlinear least squares of the free-floating beam in unilateral contact with the bench stone
    (Kalliorinne et al. 2023, §3.1, eq. 1) against every profile of the bench; see the module
    docstring for the parametrisation, the exact Jacobian, the GCV choice of the regularisation
    and the Gauss–Newton uncertainty.

    Parameters
    ----------
    bench
        :class:`~skisnow.io.BenchData` (any masses and load positions; profiles may miss the
        tip and the tail).
    ski
        Which ski of a multi-ski bench.
    name, kind, width, kick_zone
        Of the identified ski; default from the bench metadata (``kind``, ``width_mm``,
        ``kick_zone_mm``), else ``'<bench ski> (identified)'``, ``'classic'``, 44 mm, none.
    x_tail, x_tip
        Ends of the running surface [m] from the balance point; default the metadata's
        ``x_tail_mm``/``x_tip_mm``, else the measured extent. Beyond the measured extent, EI and
        z0 are continued smoothly (the regularisation) and carry wide bands.
    boot_length
        Length [m] of the bench's boot plate; default the metadata's ``boot_length_mm``, else
        :data:`~skisnow.ski._beam.DEFAULT_BOOT_LENGTH`.
    n_stiffness, n_camber
        Cubic B-spline coefficients of log EI and of z0.
    bin_width
        Profiles are averaged over bins of this width [m] (weights keep the full-data fit).
    element_length
        Beam element length [m] of the forward model.
    noise
        Bench noise σ [m]; default estimated from the scatter inside the bins.
    regularisation
        λ; default chosen by GCV over ``lambdas``.
    initial
        A starting ski; default z0 from the two lightest profiles extrapolated to zero load
        and the constant EI that fits best on it.
    max_nfev
        Evaluation limit of each least-squares fit (each λ warm-started from the previous).
    continuation
        Fractions of the bench's masses fitted first, in turn (lightest first).
    progress
        Called with a short message after each stage.
    source
        Where the bench came from (file name), recorded in the provenance.

    Returns
    -------
    IdentificationResult
        The identified ski and the fit's record.

    Raises
    ------
    InputError
        Too little data (fewer than two load cases or profiles shorter than the spline
        resolution), bad options.
    """
    t_start = time.perf_counter()
    say = progress or (lambda _msg: None)
    from skisnow.io import BenchData

    if not isinstance(bench, BenchData):
        raise InputError(f"bench must be a skisnow.io.BenchData, got {type(bench).__name__}")
    label = bench.ski_name(ski)
    md = bench.metadata if bench.metadata.get("ski") == label else {}
    raw = _bench_cases(bench, label)
    if len(raw) < 2:
        raise InputError(f"bench of ski {label!r}: need at least 2 load cases, got {len(raw)}")
    for opt, val, lo in (("n_stiffness", n_stiffness, 5), ("n_camber", n_camber, 6)):
        if not (isinstance(val, int) and val >= lo):
            raise InputError(f"{opt} must be an integer >= {lo}, got {val!r}")
    for opt, val in (("bin_width", bin_width), ("element_length", element_length)):
        if not (np.isfinite(val) and 0 < val < 0.1):
            raise InputError(f"{opt} must be in (0, 0.1) m, got {val}")
    xmin = min(float(c[2].min()) for c in raw)
    xmax = max(float(c[2].max()) for c in raw)
    x_tail = float(md.get("x_tail_mm", xmin * 1e3)) * 1e-3 if x_tail is None else float(x_tail)
    x_tip = float(md.get("x_tip_mm", xmax * 1e3)) * 1e-3 if x_tip is None else float(x_tip)
    if not (x_tail < 0 < x_tip) or x_tail > xmin + 1e-9 or x_tip < xmax - 1e-9:
        raise InputError(
            f"the running surface [{x_tail * 1e3:g}, {x_tip * 1e3:g}] mm must contain the balance "
            f"point and the measured stations [{xmin * 1e3:g}, {xmax * 1e3:g}] mm"
        )
    if boot_length is None:
        boot_length = float(md.get("boot_length_mm", DEFAULT_BOOT_LENGTH * 1e3)) * 1e-3
    n_el = max(8, round((x_tip - x_tail) / element_length))
    nodes = np.linspace(x_tail, x_tip, n_el + 1)

    cases, scatter, n_samples, scatter_dof = [], 0.0, 0, 0
    for m, p, xs, hs in raw:
        xb, hb, cnt, ss, dof_ = _bins(xs, hs, bin_width)
        scatter += ss
        scatter_dof += dof_
        n_samples += xs.size
        force = m * STANDARD_GRAVITY
        f_boot = boot_load_vector(nodes, force, p, boot_length, "uniform")
        cases.append(
            _Case(
                mass=m, position=p, x=xb, h=hb, w=np.sqrt(cnt), force=force, f_boot=f_boot,
                f_total=-float(np.sum(f_boot[0::2])),
                m_total=-float(np.sum(f_boot[0::2] * nodes + f_boot[1::2])),
                hermite=_hermite_matrix(nodes, xb),
            )
        )  # fmt: skip
    if noise is None:
        dof = scatter_dof
        if dof < 10:
            raise InputError(
                "cannot estimate the bench noise from the scatter inside bins (too few samples "
                "per bin): give noise= or a smaller bin_width"
            )
        sigma = max(np.sqrt(scatter / dof), 1e-7)
    else:
        if not (np.isfinite(noise) and noise > 0):
            raise InputError(f"noise must be > 0 m, got {noise}")
        sigma = float(noise)
    problem = _Problem(cases, nodes, n_stiffness, n_camber, sigma)

    # -- start: constant EI, z0 = the lightest profile (least squares on the z0 basis)
    if initial is not None:
        theta_e0 = np.linalg.lstsq(
            _design(problem.t_e, nodes), np.log(initial.stiffness(nodes)), rcond=None
        )[0]
        z_start_x, z_start = nodes, initial.free_camber(nodes)
    else:
        z_start_x, z_start = _zero_load_profile(cases)
    # full-basis fit, then drop its linear part (invisible to the bench): Q is orthonormal
    a_z = _design(problem.t_z, z_start_x)
    c_z = np.linalg.lstsq(a_z, z_start, rcond=None)[0]
    phi0 = problem.q_z.T @ c_z
    if initial is None:
        # a constant EI: the best on this z0, by a bounded scalar search of log EI
        def misfit(log_ei: float) -> float:
            r, _ = problem.evaluate(
                np.concatenate([np.full(n_stiffness, log_ei), phi0]), jacobian=False
            )
            return float(r @ r)

        best_log = minimize_scalar(
            misfit, bounds=(np.log(30.0), np.log(3e4)), method="bounded",
            options={"xatol": 0.02},
        ).x  # fmt: skip
        theta_e0 = np.full(n_stiffness, float(best_log))
        say(f"start: constant EI {np.exp(best_log):.0f} N m², z0 extrapolated to zero load")
    p = np.concatenate([theta_e0, phi0])

    # EI between 1 and 1e6 N m² (a ski is 100-10000): keeps the trust region off overflow
    lower = np.concatenate([np.full(n_stiffness, -10.0), np.full(n_camber - 2, -np.inf)])
    upper = np.concatenate([np.full(n_stiffness, 25.0), np.full(n_camber - 2, np.inf)])

    def fit(
        p0: NDArray[np.float64], lam: float, subset: list[int] | None = None, nfev: int = max_nfev
    ):
        pen = problem.penalty_matrix(lam)

        def fun(pp):
            r, _ = problem.evaluate(pp, jacobian=False, cases=subset)
            return np.concatenate([r, pen @ pp])

        def jac(pp):
            _, j = problem.evaluate(pp, jacobian=True, cases=subset)
            return np.concatenate([j, pen], axis=0)

        sol = least_squares(
            fun, p0, jac=jac, method="trf", bounds=(lower, upper), max_nfev=nfev,
            x_scale="jac",
        )  # fmt: skip
        if subset is not None:
            return sol
        r, j = problem.evaluate(sol.x, jacobian=True)
        jtj = j.T @ j
        ptp = pen.T @ pen
        a_inv = np.linalg.pinv(jtj + ptp)
        edf = float(np.trace(a_inv @ jtj))
        rss = float(r @ r)
        gcv = problem.n_data * rss / max(problem.n_data - edf, 1.0) ** 2
        return sol, gcv, rss, edf, a_inv, jtj, r

    records, fits = [], []
    grid = [float(regularisation)] if regularisation is not None else [float(v) for v in lambdas]
    if any(not (np.isfinite(v) and v >= 0) for v in grid) or not grid:
        raise InputError(f"regularisation / lambdas must be finite and >= 0, got {grid}")
    # Continuation in load: the light loads touch the stone at two short zones (the fit is
    # smooth there); heavier loads flatten the glide zones onto the stone, where the contact
    # set reacts to small changes of z0 and the misfit has kinks. Fitting the load cases up to
    # a third, then two thirds of the mass range first brings the contact sets close before
    # the whole sequence is fitted.
    order = sorted({c.mass for c in cases})
    for frac in continuation:
        m_max = order[min(len(order) - 1, int(np.ceil(frac * len(order))) - 1)]
        subset = [k for k, c in enumerate(cases) if c.mass <= m_max]
        if 2 <= len(subset) < len(cases):
            p = fit(p, grid[0], subset).x
            say(f"continuation: load cases up to {m_max:g} kg fitted")
    for lam in grid:  # each further λ starts from the previous fit
        sol, gcv, rss, edf, a_inv, jtj, r = fit(p, lam)
        records.append((lam, gcv, float(np.sqrt(rss / problem.n_data)), edf))
        fits.append((sol, a_inv, jtj, r))
        p = fits[int(np.argmin([rec[1] for rec in records]))][0].x  # next λ from the best
        say(f"λ = {lam:.3g}: GCV {gcv:.4g}, misfit rms {records[-1][2]:.3g} σ, edf {edf:.1f}")
    best = int(np.argmin([rec[1] for rec in records]))
    lam = records[best][0]
    sol, a_inv, jtj, r = fits[best]
    cov = a_inv @ jtj @ a_inv  # σ-normalised residuals: the covariance of p

    # -- the identified ski
    theta_e, theta_z = problem.split(sol.x)
    ex = np.unique(np.concatenate([np.arange(x_tail, x_tip, 0.02), [x_tip]]))
    ei = problem.ei_at(theta_e, ex)
    be = _design(problem.t_e, ex)
    cov_e = cov[:n_stiffness, :n_stiffness]
    sd_log_ei = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", be, cov_e, be), 0.0))
    cx = np.unique(np.concatenate([np.arange(x_tail, x_tip, 0.005), [x_tip]]))
    zc = problem.z0_at(theta_z, cx)
    i, j = lower_hull_bracket(cx, zc, 0.0)
    s1, s2 = cx[i], cx[j]
    line = zc[i] + (zc[j] - zc[i]) * (cx - s1) / (s2 - s1)
    z_rest = np.maximum(zc - line, 0.0)
    bz = _design(problem.t_z, cx)
    bz_g = bz - (np.outer((s2 - cx) / (s2 - s1), bz[i]) + np.outer((cx - s1) / (s2 - s1), bz[j]))
    tz = bz_g @ problem.q_z
    cov_z = cov[n_stiffness:, n_stiffness:]
    sd_z = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", tz, cov_z, tz), 0.0))
    seconds = time.perf_counter() - t_start
    rms = float(np.sqrt((float(r @ r) * sigma**2 + scatter) / n_samples))
    kz: Any = kick_zone
    if isinstance(kz, str):
        kz_mm = md.get("kick_zone_mm")
        kz = None if kz_mm is None else (float(kz_mm[0]) * 1e-3, float(kz_mm[1]) * 1e-3)
    kind_ = kind or md.get("kind") or ("classic" if kz is not None else "skate")
    masses = sorted({c.mass for c in cases})
    positions = sorted({round(c.position * 1e3, 6) for c in cases})
    identified = Ski(
        name=name or f"{label} (identified)",
        kind=kind_,
        x_tail=x_tail,
        x_tip=x_tip,
        width=float(md.get("width_mm", 44.0)) * 1e-3 if width is None else float(width),
        stiffness_x=ex,
        stiffness_values=ei,
        camber_x=cx,
        camber_values=z_rest,
        kick_zone=kz,
        stiffness_log_sd=sd_log_ei,
        camber_sd=sd_z,
        description=(
            f"Identified from the camber bench of ski {label!r}: {len(cases)} load cases "
            f"({len(masses)} masses {masses[0]:g}-{masses[-1]:g} kg at {len(positions)} "
            f"positions {positions[0]:g}..{positions[-1]:g} mm), stations "
            f"{xmin * 1e3:.0f}..{xmax * 1e3:.0f} mm. Bands: 95 % (Gauss-Newton, noise only)."
        ),
        provenance=Provenance(
            method="identified from camber-bench data (skisnow.ski.identify_ski: nonlinear "
            "least squares of the beam on the bench stone, GCV regularisation)",
            data=(source or f"bench of ski {label!r}")
            + f"; {len(cases)} profiles, {n_samples} samples",
            sources=(
                "Kalliorinne, K., et al. (2023): the camber bench and its load sequence (§3.1)",
                "Craven, P., Wahba, G. (1979): generalized cross-validation",
            ),
            created=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            software=f"skisnow {_version()}",
            details=(
                ("lambda", lam),
                ("criterion", "given" if regularisation is not None else "gcv"),
                ("n_stiffness", n_stiffness),
                ("n_camber", n_camber),
                ("noise_mm", sigma * 1e3),
                ("residual_rms_mm", rms * 1e3),
                ("boot_length_mm", boot_length * 1e3),
                ("measured_x_mm", f"{xmin * 1e3:.1f}..{xmax * 1e3:.1f}"),
                ("seconds", round(seconds, 2)),
            ),
        ),
    )
    return IdentificationResult(
        ski=identified,
        regularisation=lam,
        criterion="given" if regularisation is not None else "gcv",
        gcv=tuple(records),
        noise=sigma,
        residual_rms=rms,
        n_cases=len(cases),
        n_samples=n_samples,
        n_parameters=problem.n_params,
        n_evaluations=int(sol.nfev),
        converged=bool(sol.status > 0),
        message=str(sol.message),
        seconds=seconds,
    )


def _version() -> str:
    from skisnow import __version__

    return __version__
