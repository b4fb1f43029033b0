"""The forward model of the ski identification: the bench beam, its spline parameters, its Jacobian.

The bench itself (Kalliorinne et al. 2023, §3.1, eq. 1 h = f(x, m, x_m)) as a function of the
parameters of :func:`~skisnow.identify.identify_ski`: an Euler–Bernoulli beam with stiffness EI(x)
and stress-free shape z0(x), free-floating in unilateral contact with the rigid stone, loaded by m·g
through the boot plate at x_m (:mod:`skisnow.ski._beam`, same Hermite elements and exact LCP). This
module holds the binned data of a load case, the cubic B-spline parametrisation (log EI and z0 on
uniform knots, z0 without its linear part, which the bench cannot see) and the residuals of all load
cases with their exact Jacobian by the tangent of the beam at its active set (one banded solve per
stiffness parameter and one small KKT solve per load case), plus the penalty rows of the
regularisation. The fit itself is in :mod:`skisnow.identify._fit`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import BSpline
from scipy.sparse import csr_matrix

from skisnow._errors import ConvergenceError
from skisnow.identify._banded_kernel import banded_cholesky, banded_solve
from skisnow.ski import (
    GAUSS4_W,
    GAUSS4_X,
    SubGrid,
    banded_upper,
    hermite_rows,
    shape_functions,
    solve_point_contact,
)

_Z_REF = 1e-3  # [m]: scale of the z0 smoothness term
_LAMBDA_Z = 1.0
_LAMBDA_1 = 1.0

#: The prior of a ski's stiffness that the fit's penalty completes (a proper prior: the
#: smoothness terms leave the level of log EI free): each log-EI spline coefficient normal about
#: ln(1000 N m²) with a standard deviation of 1.5 (EI within 50-20000 N m² at 95 %: the range
#: of cross-country skis, soft tips to stiff cambers). It keeps a stiffness the bench does not
#: see (a stretch pressed flat on the stone at every load, an overhang) at a ski's, where the
#: fit otherwise ran it to its bound (measured: a shop bench from the default start, EI ×1000 in
#: the glide zones at 10.6 σ), and it is the band there (the prior's width).
PRIOR_LOG_EI_MEAN = float(np.log(1000.0))
#: The prior of the free camber's spline coefficients (without their linear part): normal
#: about 0 with 10 mm standard deviation (a ski's camber, pocket and shovel are within 0-35 mm
#: of the plane it rests on). Against the data it weighs as one bin of 10 mm error: nothing
#: where a station measures z0; beyond the measured stations it is the band.
PRIOR_Z0_SD = 10e-3

#: The penetration left between contact points during the fit [m]: 0.1 nm moves the loaded
#: heights by at most 0.18 µm against 0.01 nm (five skis, four load cases each: issue 25's ski,
#: the shipped skis, two random ones) and needs fewer exchange rounds per evaluation; the final
#: fit is checked at the tighter default and on a finer mesh (the discretisation error).
FIT_TOL_PENETRATION = 1e-10
PRIOR_LOG_EI_SD = 1.5


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
    hermite: Any  # sparse (n_bins, 2n): the bin mean of the Hermite rows of its stations
    #: the stations [m] and the sparse (n_bins, n_stations) matrix of the bins' means: the
    #: model is averaged over each bin's stations as the data are (None: evaluated at x)
    stations: NDArray[np.float64] | None = None
    average: Any = None


def _bin_index(x: NDArray[np.float64], width: float) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Each station's bin (``width`` wide, in order along the ski) and each bin's station count:
    the one grouping of :func:`_bins` (the data) and :func:`_bin_average` (the model)."""
    key = np.floor(x / width + 1e-9).astype(np.int64)
    _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
    return inv, counts


def _bins(x: NDArray[np.float64], h: NDArray[np.float64], width: float):
    """Bin means (x̄, h̄, count) and the scatter about a straight line inside each bin (the
    profile's slope removed): sum of squares and degrees of freedom (count - 2 per bin of >= 3
    samples). The profile's curvature is not removed: near the shovel it bends h by µm across a
    bin, so the model is compared as the same bin mean (:func:`_bin_average`), not at x̄."""
    inv, counts = _bin_index(x, width)
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


def _bin_average(x: NDArray[np.float64], width: float) -> Any:
    """The sparse (n_bins, n_stations) matrix whose rows average the stations ``x`` of each bin
    of :func:`_bins` (same bins, same order). The model's bin value is this mean of the model at
    the stations (exact: the model is linear in its Hermite and z0 rows at fixed contact); the
    model at the bin's mean position x̄ instead differs from it by h''·var(x)/2, measured 2.0 µm
    rms (9 µm at the tip) over the full plan of issue 25's ski (2 mm stations, 5 mm bins, 2 or 3
    stations each): the two-bin pattern of the full plan's residuals."""
    inv, counts = _bin_index(x, width)
    return csr_matrix((1.0 / counts[inv], (inv, np.arange(x.size))), shape=(counts.size, x.size))


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


class _Beam:
    """The clamped beam at one point of the fit: banded stiffness ``ab`` (upper storage), its
    Cholesky factor and EI at the Gauss points; on first use the flexibility of every DOF under
    a unit nodal force at each node (``flex_full``, 2n × n) and of the translations (``flex``,
    symmetrised), and the deflection under each case's boot load (``u_boot``, 2n × cases)."""

    def __init__(self, problem: _Problem, theta_e: NDArray[np.float64]) -> None:
        self.problem = problem
        self.ab, self.ei_q = problem._stiffness(theta_e)
        self.factor = banded_cholesky(self.ab)

    @cached_property
    def flex_full(self) -> NDArray[np.float64]:
        n, clamp = self.problem.n, self.problem.clamp
        rhs = np.zeros((2 * n, n), order="F")
        rhs[2 * np.arange(n), np.arange(n)] = 1.0
        rhs[2 * clamp, clamp] = 0.0
        return banded_solve(self.factor, rhs, overwrite_b=True)

    @cached_property
    def flex(self) -> NDArray[np.float64]:
        flex = self.flex_full[0::2, :]
        return 0.5 * (flex + flex.T)

    @cached_property
    def u_boot(self) -> NDArray[np.float64]:
        pr = self.problem
        if not pr.cases:
            return np.zeros((2 * pr.n, 0))
        f_all = np.stack([pr._clamp(c.f_boot) for c in pr.cases], axis=1)
        return banded_solve(self.factor, f_all)


class _Problem:
    """The bench sequence and the discretised beam; evaluates residuals and their Jacobian."""

    def __init__(
        self,
        cases: list[_Case],
        nodes: NDArray[np.float64],
        n_stiffness: int,
        n_camber: int,
        sigma: float | Sequence[float],
        prior: Any = None,
    ) -> None:
        self.cases = cases
        self.nodes = nodes
        n = nodes.size
        self.n = n
        self.clamp = int(np.argmin(np.abs(nodes)))
        sig = np.broadcast_to(np.asarray(sigma, dtype=float), (len(cases),)).copy()
        #: the noise of each load case [m] (estimated per case, or given)
        self.sigma_cases = sig
        #: the pooled noise [m] (rms over the bins of the cases' noises)
        nb = np.array([c.x.size for c in cases], dtype=float)
        self.sigma = float(np.sqrt(np.sum(nb * sig**2) / max(nb.sum(), 1.0))) if cases else 1.0
        x0, x1 = float(nodes[0]), float(nodes[-1])
        self.t_e, _ = _uniform_bspline(x0, x1, n_stiffness)
        self.t_z, _ = _uniform_bspline(x0, x1, n_camber)
        self.n_e, self.n_z = n_stiffness, n_camber
        # Gauss points of every element, and the B-spline of log EI there
        le = np.diff(nodes)[:, None]
        self.le = le
        xq = nodes[:-1, None] + le * GAUSS4_X[None, :]
        self.phi_q = _design(self.t_e, xq.ravel()).reshape(n - 1, 4, n_stiffness)
        xi = GAUSS4_X[None, :]
        self.bq = np.stack(
            [
                (-6.0 + 12.0 * xi) / le**2,
                (-4.0 + 6.0 * xi) / le,
                (6.0 - 12.0 * xi) / le**2,
                (-2.0 + 6.0 * xi) / le,
            ],
            axis=-1,
        )  # fmt: skip  (n_el, nq, 4): curvature per DOF
        self.wq = GAUSS4_W[None, :] * le  # (n_el, nq)
        # z0: basis at nodes and at the bins; gauge: no linear part
        self.phi_z_nodes = _design(self.t_z, nodes)
        greville = (self.t_z[1:-3] + self.t_z[2:-2] + self.t_z[3:-1]) / 3.0
        lin = np.stack([np.ones(n_camber), greville], axis=1)
        q, _ = np.linalg.qr(lin, mode="complete")
        self.q_z = q[:, 2:]  # (n_z, n_z - 2), orthogonal to linear coefficient vectors
        self.lin_z = lin
        self.q_z_nodes = self.phi_z_nodes @ self.q_z
        self.phi_z_cases = [
            _design(self.t_z, c.x)
            if c.average is None
            else np.asarray(c.average @ _design(self.t_z, c.stations))
            for c in cases
        ]  # fmt: skip  (z0 averaged over each bin's stations, as the data)
        self.q_z_cases = [phi @ self.q_z for phi in self.phi_z_cases]  # ∂z0(bin)/∂φ per case
        self.d2_e = _second_differences(n_stiffness)
        #: square roots of the weights of the log-EI smoothness rows (1: the quadratic penalty;
        #: below 1 where an edge-preserving penalty lets a stiffness step through,
        #: :mod:`skisnow.identify._edges`)
        self.stiffness_weights = np.ones(n_stiffness - 2)
        self.d2_z = _second_differences(n_camber) / _Z_REF
        self.n_params = n_stiffness + n_camber - 2
        self.warm: list[NDArray[np.float64] | None] = [None] * len(cases)
        self.warm_active: list[NDArray[np.bool_] | None] = [None] * len(cases)
        #: (interior points, reactions over nodes + points) of each case's last contact: a
        #: feasible start of the next evaluation's contact (the same load, the same points)
        self.warm_points: list[tuple[NDArray[np.float64], NDArray[np.float64]] | None] = [
            None
        ] * len(cases)
        #: the deepest remaining penetration [m] of each case's last contact
        self.penetration = np.zeros(len(cases))
        #: the square roots of the bins' Huber weights (1: least squares; skisnow.identify._robust)
        self.bin_weights = [np.ones(c.x.size) for c in cases]
        #: the active contact points [m] of each case at the last evaluation
        self.contacts: list[NDArray[np.float64]] = [np.zeros(0)] * len(cases)
        self.tol_penetration = FIT_TOL_PENETRATION
        #: hold every case's contact points where the last evaluation left them (no exchange
        #: rounds): the residuals are then smooth in p (for checks of the Jacobian)
        self.freeze_points = False
        # the sub-grid on which the contact is checked between nodes, and z0's basis there
        self.subgrid = SubGrid.of(nodes)
        self.phi_z_sub = csr_matrix(_design(self.t_z, self.subgrid.x.ravel()))
        #: (u, a, b) of the last contact solution of each case
        self.last_state: list[tuple[NDArray[np.float64], float, float] | None] = [None] * len(cases)
        self.n_data = int(sum(c.x.size for c in cases))
        self._beam_cache: list[tuple[bytes, _Beam]] = []
        #: an opt-in prior replacing the penalty (``rows(problem) -> (P, t)``, λ unused;
        #: :class:`skisnow.identify._prior.PopulationPrior`), and its rows on this basis
        self.prior = prior
        self.prior_rows = None if prior is None else prior.rows(self)

    def set_bin_weights(self, flat: NDArray[np.float64]) -> None:
        """Set the square roots of the bins' weights from one array over all bins."""
        cuts = np.cumsum([c.x.size for c in self.cases])[:-1]
        self.bin_weights = [np.asarray(w, dtype=float) for w in np.split(flat, cuts)]

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

    def beam(self, theta_e: NDArray[np.float64]) -> _Beam:
        """The clamped beam of the (clipped) log-EI coefficients ``theta_e``: stiffness, its
        factor, the flexibility and the deflections under every case's boot load. Kept for the
        last two points: the fit evaluates each accepted point twice (residuals, then with the
        Jacobian), and the smoothed contact falls back to the exact one case by case at one
        point. The same numbers as computed afresh."""
        key = theta_e.tobytes()
        for k, beam in self._beam_cache:
            if k == key:
                return beam
        beam = _Beam(self, theta_e)
        self._beam_cache = [(key, beam), *self._beam_cache[:1]]
        return beam

    def evaluate(
        self, p: NDArray[np.float64], *, jacobian: bool, cases: Sequence[int] | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        """σ-normalised weighted residuals (model - data) of the chosen cases, and their
        Jacobian (rows of all bins, columns of p) if asked.

        The contact of every case is resolved between the nodes
        (:func:`~skisnow.ski.solve_point_contact`): no penetration of the stone anywhere along
        the beam, contact points inside elements where the ski touches between nodes. The
        Jacobian is the tangent of the beam at the active contact points with their positions
        held (an active point sits at a local minimum of the gap, so moving it changes the gap
        to second order only)."""
        theta_e, theta_z = self.split(p)
        theta_e = np.clip(theta_e, -10.0, 25.0)  # coefficients of log EI: no overflow
        beam = self.beam(theta_e)
        ei_q, factor, flex_full, flex = beam.ei_q, beam.factor, beam.flex_full, beam.flex
        n = self.n
        z0n = self.phi_z_nodes @ theta_z
        z0_sub = (self.phi_z_sub @ theta_z).reshape(self.subgrid.x.shape)
        spline = BSpline(self.t_z, theta_z, 3, extrapolate=True)

        def solve(rhs: NDArray[np.float64]) -> NDArray[np.float64]:
            return banded_solve(factor, rhs)

        idx_cases = range(len(self.cases)) if cases is None else cases
        res_parts, jac_parts = [], []
        for k in idx_cases:
            c = self.cases[k]
            u_boot = beam.u_boot[:, k]
            href = max(float(np.ptp(z0n)), 1e-3)
            warm = self.warm_points[k]
            pc = solve_point_contact(
                nodes=self.nodes, solve=solve, clamp=self.clamp, flex_full=flex_full, flex=flex,
                u_boot=u_boot, z0_nodes=z0n, z0_at=spline, z0_sub=z0_sub, subgrid=self.subgrid,
                f_total=c.f_total, m_total=c.m_total, tol_r=1e-10 * c.force,
                tol_h=1e-10 * href, tol_penetration=self.tol_penetration,
                points=None if warm is None else warm[0],
                warm_reactions=None if warm is None else warm[1],
                max_rounds=1 if self.freeze_points else 40,
            )  # fmt: skip
            if self.freeze_points:
                pc = dataclasses.replace(pc, converged=True)
            if not pc.converged:
                raise ConvergenceError(
                    f"beam contact of load case m = {c.mass:g} kg, x_m = {c.position * 1e3:g} mm "
                    "did not converge during the identification",
                    result=None,
                )
            on = pc.active
            keep = on | pc.node  # the next evaluation starts from the active points
            if not self.freeze_points:
                self.warm_points[k] = (pc.x[n:][on[n:]], np.where(on, pc.reactions, 0.0)[keep])
            self.warm[k] = pc.nodal_reactions(self.nodes)
            self.warm_active[k] = on[:n].copy()
            act = np.flatnonzero(on)
            u, a, b = pc.u, pc.translation, pc.rotation
            self.last_state[k] = (u, float(a), float(b))
            self.penetration[k] = pc.penetration
            hmod = self.phi_z_cases[k] @ theta_z + a + b * c.x + c.hermite @ u
            self.contacts[k] = pc.x[on]
            bw = c.w * self.bin_weights[k] / self.sigma_cases[k]
            res_parts.append(bw * (hmod - c.h))
            if not jacobian:
                continue
            # tangent at the active points A: K du = U_A dr - dK u; the gaps at A stay zero;
            # both balances (the points held where they are)
            xa = pc.x[act]
            na = act.size
            kkt = np.zeros((na + 2, na + 2))
            kkt[:na, :na] = pc.flex[np.ix_(act, act)]
            kkt[:na, na] = 1.0
            kkt[:na, na + 1] = xa
            kkt[na, :na] = 1.0
            kkt[na + 1, :na] = xa
            # dK/dθ_j u: curvature at Gauss points
            ue = np.stack([u[0:-2:2], u[1:-2:2], u[2::2], u[3::2]], axis=1)  # (n_el, 4)
            kappa = np.einsum("eqa,ea->eq", self.bq, ue)
            coef = self.wq * ei_q * kappa  # (n_el, nq)
            contrib = np.matmul(
                (coef[:, :, None] * self.bq).transpose(0, 2, 1), self.phi_q
            )  # (n_el, 4, nE)
            g_mat = np.zeros((2 * n, self.n_e))  # assembled: element e holds DOFs 2e..2e+3
            g_mat[: 2 * n - 2] += contrib[:, 0:2, :].reshape(2 * n - 2, self.n_e)
            g_mat[2:] += contrib[:, 2:4, :].reshape(2 * n - 2, self.n_e)
            g_mat[2 * self.clamp : 2 * self.clamp + 2] = 0.0
            v = banded_solve(factor, g_mat)  # K^-1 dK u  (2n, nE)
            node_a = act[act < n]
            int_a = act[act >= n]
            rhs_e = np.zeros((na + 2, self.n_e))
            rhs_z = np.zeros((na + 2, self.n_z - 2))
            is_node = act < n
            rhs_e[:na][is_node] = v[2 * node_a]
            rhs_z[:na][is_node] = -self.q_z_nodes[node_a]
            if int_a.size:
                e_i, shp = hermite_rows(self.nodes, pc.x[int_a])
                dofs = np.stack([2 * e_i + j for j in range(4)], axis=1)  # (k, 4)
                rhs_e[:na][~is_node] = np.einsum("pa,pae->pe", shp, v[dofs])
                rhs_z[:na][~is_node] = -(_design(self.t_z, pc.x[int_a]) @ self.q_z)
            sol = np.linalg.lstsq(kkt, np.concatenate([rhs_e, rhs_z], axis=1), rcond=None)[0]
            dr, da, db = sol[:na], sol[na], sol[na + 1]
            du = pc.response[:, act] @ dr  # (2n, nP)
            du[:, : self.n_e] -= v
            dh = c.hermite @ du + da[None, :] + c.x[:, None] * db[None, :]
            dh[:, self.n_e :] += self.q_z_cases[k]
            jac_parts.append(bw[:, None] * dh)
        res = np.concatenate(res_parts)
        jac = np.concatenate(jac_parts) if jacobian else None
        return res, jac

    def penalty_matrix(self, lam: float, lam_z: float = _LAMBDA_Z) -> NDArray[np.float64]:
        """Rows P of the penalty residual P p - t (:meth:`penalty_target`): sqrt(λ) D₂ θ_E,
        sqrt(λ₁) D₁ θ_E, θ_E / s_E (the prior of :data:`PRIOR_LOG_EI_SD`), sqrt(λ_z) D₂ θ_z /
        z_ref, φ / s_z (:data:`PRIOR_Z0_SD`) (linear in p). The weak first-difference term
        (λ₁ = 1) fixes the log-EI trend where
        the bench carries no bending moment (the free overhangs): there the data leave log EI
        undetermined, and without it a Gauss–Newton step runs off along that null direction.
        Read as a Gaussian prior (Wahba 1978), PᵀP is its precision (σ-normalised). With an
        opt-in prior (``prior``), its rows instead."""
        if self.prior_rows is not None:
            return self.prior_rows[0]
        zeros_z = np.zeros((self.n_e, self.n_z - 2))
        rows_e = np.sqrt(lam) * np.concatenate(
            [self.stiffness_weights[:, None] * self.d2_e, np.zeros((self.n_e - 2, self.n_z - 2))],
            axis=1,
        )
        d1 = np.diff(np.eye(self.n_e), axis=0)
        rows_e = np.concatenate(
            [rows_e, np.sqrt(_LAMBDA_1) * np.concatenate(
                [d1, np.zeros((self.n_e - 1, self.n_z - 2))], axis=1),
             np.concatenate([np.eye(self.n_e) / PRIOR_LOG_EI_SD, zeros_z], axis=1)],
            axis=0,
        )  # fmt: skip
        rows_z = np.sqrt(lam_z) * np.concatenate(
            [np.zeros((self.n_z - 2, self.n_e)), self.d2_z @ self.q_z], axis=1
        )
        ridge_z = np.concatenate(
            [np.zeros((self.n_z - 2, self.n_e)), np.eye(self.n_z - 2) / PRIOR_Z0_SD], axis=1
        )
        return np.concatenate([rows_e, rows_z, ridge_z], axis=0)

    def penalty_target(self, lam: float, lam_z: float = _LAMBDA_Z) -> NDArray[np.float64]:
        """t of the penalty residual P p - t: the prior mean of log EI on its ridge rows."""
        if self.prior_rows is not None:
            return self.prior_rows[1]
        t = np.zeros(self.penalty_matrix(lam, lam_z).shape[0])
        start = (self.n_e - 2) + (self.n_e - 1)
        t[start : start + self.n_e] = PRIOR_LOG_EI_MEAN / PRIOR_LOG_EI_SD
        return t

    def penalty(self, lam: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(P, t)`` of the penalty residual P p - t at λ."""
        return self.penalty_matrix(lam), self.penalty_target(lam)
