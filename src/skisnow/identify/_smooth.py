"""A smoothed contact for the first iterations of the ski identification (a homotopy to the LCP).

With the exact unilateral contact (:mod:`skisnow.ski._lcp`) the bench residuals are piecewise
smooth in the parameters: each node of a glide zone pressed flat on the stone enters or leaves
the contact set with µm changes of z0, and the misfit has a kink at every such switch. Far from
the solution a Gauss–Newton model built at one contact set is then valid only for tiny steps and
the damped steps collapse (measured on the first-release classic: the damping grows by 10⁴ while
the Gauss–Newton decrement stays 30 σ² above the noise). Here the stone is replaced by a smooth,
stiff, unilateral foundation (a penalty regularisation of the complementarity, e.g. Wriggers
2006, §6.3; the softplus is the smoothed positive part of Chen & Mangasarian 1996):

    r_i = k ε · softplus(-h_i / ε),   k = F / (N_ref ε),   N_ref = 20,

a nodal reaction that is exponentially small above the stone, ≈ k·(-h_i) below it, with a
transition of width ε; k makes the penetration under the mean reaction of N_ref nodes equal to ε.
The contact problem is then the minimum of the strictly convex energy

    Π(u, a, b) = ½ uᵀKu - fᵀu + F a + M b + Σ_i k ε² F₂(-h_i/ε),   F₂' = softplus,

(u the deflection of the beam clamped at the balance point, a and b its rigid translation and
rotation, h = z0 + a + b x + u_w), solved by Newton's method with a backtracking line search on
Π; the Hessian is the banded clamped stiffness plus the foundation's diagonal, bordered by the
two rigid modes (one banded solve and a 2 × 2 Schur complement). The residuals are smooth in
the parameters, and their exact Jacobian follows from the implicit function theorem with the
same Hessian. As ε → 0 the solution tends to that of the LCP, but slowly where a glide zone
lies flat on the stone: there the reactions of the exact contact are extremely sensitive to the
gaps (a short-wave redistribution of force costs the beam almost no deflection), so even a
0.1 µm smoothing redistributes them and tilts the ski by µm (measured on the full bench of the
first-release classic at the true parameters: misfit 1.48 σ at ε = 0.1 µm against 1.02 σ on the
exact contact). The smoothed stone is therefore only the path: the fit runs a decreasing
sequence of ε and ends on the exact LCP model (:mod:`skisnow.identify._fit`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.special import expit, spence

from skisnow._errors import ConvergenceError
from skisnow.identify._banded_kernel import banded_cholesky, banded_solve
from skisnow.identify._model import _Problem

__all__ = ["SmoothedBench"]

_N_REF = 20.0  # nodes sharing the load at the penetration ε


def _softplus(t: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.logaddexp(0.0, t)


def _f2(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """∫_{-∞}^t softplus = -Li₂(-eᵗ) (Li₂(z) = spence(1 - z)), stable for both signs of t."""
    out = np.empty_like(t)
    neg = t <= 0.0
    out[neg] = -spence(1.0 + np.exp(t[neg]))
    tp = t[~neg]
    out[~neg] = 0.5 * tp * tp + np.pi**2 / 6.0 + spence(1.0 + np.exp(-tp))
    return out


def _banded_matvec(ab: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """K x for the symmetric matrix K in upper banded storage ab[3 + i - j, j] = K[i, j]."""
    y = ab[3] * x
    for d in (1, 2, 3):
        band = ab[3 - d, d:]  # K[j - d, j]
        y[:-d] += band * x[d:]
        y[d:] += band * x[:-d]
    return y


class SmoothedBench:
    """Residuals and exact Jacobian of the bench with the smoothed stone of width ε."""

    def __init__(self, problem: _Problem) -> None:
        self.problem = problem
        self.state: list[tuple[NDArray[np.float64], float, float] | None] = [None] * len(
            problem.cases
        )

    def evaluate(
        self,
        p: NDArray[np.float64],
        eps: float,
        *,
        jacobian: bool,
        cases: Sequence[int] | None = None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        """σ-normalised residuals of the chosen cases and (if asked) their Jacobian."""
        pr = self.problem
        theta_e, theta_z = pr.split(p)
        theta_e = np.clip(theta_e, -10.0, 25.0)
        beam = pr.beam(theta_e)
        ab, ei_q = beam.ab, beam.ei_q
        n, cl = pr.n, pr.clamp
        x = pr.nodes
        z0n = pr.phi_z_nodes @ theta_z
        idx = range(len(pr.cases)) if cases is None else cases
        res, jac = [], []
        trans = 2 * np.arange(n)
        free = np.ones(n, dtype=bool)
        free[cl] = False
        for k in idx:
            c = pr.cases[k]
            f = pr._clamp(c.f_boot)
            kc = c.force / (_N_REF * eps)
            state = None
            if self.state[k] is not None:
                state = self._newton(ab, z0n, f, c.f_total, c.m_total, kc, eps, self.state[k])
            if state is None:  # no previous state, or Newton failed from it: the exact contact
                pr.evaluate(p, jacobian=False, cases=[k])
                state = self._newton(ab, z0n, f, c.f_total, c.m_total, kc, eps, pr.last_state[k])
            if state is None:
                raise ConvergenceError(
                    f"smoothed contact of load case m = {c.mass:g} kg did not converge",
                    result=None,
                )
            u, a, b = state
            self.state[k] = (u, a, b)
            hmod = pr.phi_z_cases[k] @ theta_z + a + b * c.x + c.hermite @ u
            res.append(c.w * (hmod - c.h) / pr.sigma)
            if not jacobian:
                continue
            h = z0n + a + b * x + u[0::2]
            t = -h / eps
            d = kc * expit(t)
            hess = ab.copy()
            hess[3, trans[free]] += d[free]
            # ∂(∇Π)/∂θ_E: dK/dθ_j u;  ∂(∇Π)/∂φ: the foundation's d at the nodes of z0
            ue = np.stack([u[0:-2:2], u[1:-2:2], u[2::2], u[3::2]], axis=1)
            kappa = np.einsum("eqa,ea->eq", pr.bq, ue)
            coef = pr.wq * ei_q * kappa
            contrib = np.einsum("eq,eqa,eqj->eaj", coef, pr.bq, pr.phi_q)  # (n_el, 4, nE)
            # the right-hand side -[dK/dθ_E u, E D Q] built in place (Fortran order, two
            # trailing columns left for the bordered solve's C)
            n_e, n_p = pr.n_e, pr.n_e + pr.n_z - 2
            rhs_u = np.zeros((2 * n, n_p + 2), order="F")
            rhs_u[: 2 * n - 2, :n_e] += contrib[:, 0:2, :].reshape(2 * n - 2, n_e)
            rhs_u[2:, :n_e] += contrib[:, 2:4, :].reshape(2 * n - 2, n_e)
            dq = d[:, None] * pr.q_z_nodes  # (n, nφ)
            rhs_u[trans, n_e:n_p] = dq
            rhs_u[2 * cl : 2 * cl + 2] = 0.0
            np.negative(rhs_u, out=rhs_u)
            rhs_ab = -np.concatenate(
                [np.zeros((2, pr.n_e)), np.stack([dq.sum(axis=0), x @ dq])], axis=1
            )
            du, da, db = self._solve(hess, d, free, rhs_u, rhs_ab, room=True)
            dh = c.hermite @ du + da[None, :] + c.x[:, None] * db[None, :]
            dh[:, pr.n_e :] += pr.q_z_cases[k]
            jac.append((c.w / pr.sigma)[:, None] * dh)
        r_all = np.concatenate(res)
        return r_all, (np.concatenate(jac) if jacobian else None)

    def _newton(self, ab, z0n, f, f_total, m_total, kc, eps, start):
        """Newton's method with backtracking on Π from ``start`` = (u, a, b); None if it fails
        (a start far off can overflow: that is a failure, not a warning)."""
        with np.errstate(over="ignore", invalid="ignore"):
            return self._newton_steps(ab, z0n, f, f_total, m_total, kc, eps, start)

    def _newton_steps(self, ab, z0n, f, f_total, m_total, kc, eps, start):
        pr = self.problem
        n, cl, x = pr.n, pr.clamp, pr.nodes
        trans = 2 * np.arange(n)
        free = np.ones(n, dtype=bool)
        free[cl] = False
        u, a, b = start
        u = u.copy()
        for _ in range(100):
            h = z0n + a + b * x + u[0::2]
            t = -h / eps
            r = kc * eps * _softplus(t)
            d = kc * expit(t)
            g_u = _banded_matvec(ab, u) - f
            g_u[trans] -= r
            g_u[2 * cl : 2 * cl + 2] = 0.0
            g_a = f_total - float(r.sum())
            g_b = m_total - float(r @ x)
            hess = ab.copy()
            hess[3, trans[free]] += d[free]
            step_u, step_a, step_b = self._solve(
                hess, d, free, -g_u[:, None], -np.array([[g_a], [g_b]])
            )
            su, sa, sb = step_u[:, 0], float(step_a[0]), float(step_b[0])
            dh = su[0::2] + sa + sb * x
            slope = float(g_u @ su + g_a * sa + g_b * sb)
            step_h = float(np.max(np.abs(dh)))
            if not np.isfinite(step_h):
                return None
            # converged (quadratically): the last step. Its floor is the roundoff of the
            # bordered solve, which with a few stiff foundation nodes (a light load case on
            # two short patches) lies near 1e-9 m, above 1e-6 ε: a step below a thousandth of
            # the bench noise changes no residual (measured on the classic's full sequence at
            # 5 µm, seeds 2 and 4, the 10 kg case at ε = 3 µm: force balance to 1e-10 N after
            # four iterations, then steps of 0.1-7 nm to the iteration limit: a "failure")
            if step_h < max(1e-6 * eps, 1e-8 * float(np.max(np.abs(u))), 1e-3 * pr.sigma):
                return u + su, a + sa, b + sb
            if slope >= 0.0:  # not a descent direction above the roundoff floor
                return None
            # backtracking (Armijo) on Π; its change along the step is evaluated directly
            # (the elastic part is quadratic), not as a difference of two large energies
            lin = slope + float(r @ dh)  # the elastic and load part of the slope
            quad = float(su @ _banded_matvec(ab, su))
            f2_0 = _f2(t)
            alpha = 1.0
            while True:
                t1 = -(h + alpha * dh) / eps
                d_pi = (
                    alpha * lin
                    + 0.5 * alpha**2 * quad
                    + kc * eps**2 * float(np.sum(_f2(t1) - f2_0))
                )
                if d_pi <= 1e-4 * alpha * slope:
                    break
                alpha *= 0.5
                if alpha < 1e-10:
                    return None
            u, a, b = u + alpha * su, a + alpha * sa, b + alpha * sb
        return None

    def _solve(self, hess, d, free, rhs_u, rhs_ab, room=False):
        """Solve the bordered system [[A, C], [Cᵀ, S0]] [y; (a, b)] = [rhs_u; rhs_ab] with A
        banded (clamped stiffness + foundation) and C = E D [1, x] (Schur complement).
        ``room``: ``rhs_u`` is a Fortran-ordered array with two trailing columns to spare,
        overwritten by C and the solution (no copy of a Jacobian's right-hand sides)."""
        pr = self.problem
        x = pr.nodes
        n = pr.n
        cmat = np.zeros((2 * n, 2))
        cmat[2 * np.flatnonzero(free), 0] = d[free]
        cmat[2 * np.flatnonzero(free), 1] = d[free] * x[free]
        if room:
            m = rhs_u.shape[1] - 2
            b = rhs_u
        else:
            m = rhs_u.shape[1]
            b = np.empty((2 * n, m + 2), order="F")
            b[:, :m] = rhs_u
        b[:, m:] = cmat
        y = banded_solve(banded_cholesky(hess), b, overwrite_b=True)
        yr, yc = y[:, :m], y[:, m:]
        s0 = np.array([[d.sum(), d @ x], [d @ x, d @ (x * x)]])
        schur = s0 - cmat.T @ yc
        rhs = rhs_ab - cmat.T @ yr
        try:
            sol = np.linalg.solve(schur, rhs)
        except np.linalg.LinAlgError:
            sol = np.linalg.lstsq(schur, rhs, rcond=None)[0]
        return yr - yc @ sol, sol[0], sol[1]
