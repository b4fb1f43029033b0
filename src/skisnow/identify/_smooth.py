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

    Π(u, a, b) = ½ uᵀKu - fᵀu + F a + M b + Σ_s w_s k ε² F₂(-h_s/ε),   F₂' = softplus,

(u the deflection of the beam clamped at the balance point, a and b its rigid translation and
rotation, h_s = z0(x_s) + a + b x_s + N_s u), solved by Newton's method with a backtracking line
search on Π; the Hessian is the banded clamped stiffness plus the foundation's element matrices
Σ w_s d_s N_s N_sᵀ (the same band), bordered by the two rigid modes (one banded solve and a
2 × 2 Schur complement). The residuals are smooth in
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
from scipy.sparse import csr_matrix
from scipy.special import expit, spence

from skisnow._errors import ConvergenceError
from skisnow.identify._banded_kernel import banded_cholesky, banded_solve, smoothed_hessian
from skisnow.identify._model import _Problem
from skisnow.identify._smooth_kernel import newton_smoothed

__all__ = ["SmoothedBench"]

_N_REF = 20.0  # nodes sharing the load at the penetration ε


def _softplus(t: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.logaddexp(0.0, t)


#: Below this t, 1 + eᵗ rounds to 1 exactly (eᵗ < 2⁻⁵³) and F₂(t) = -spence(1) = -0.0.
_F2_ZERO = -40.0


def _f2(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """∫_{-∞}^t softplus = -Li₂(-eᵗ) (Li₂(z) = spence(1 - z)), stable for both signs of t.

    ``spence`` is evaluated only where t > :data:`_F2_ZERO` (sub-grid points within 40 ε of
    the stone, a few percent of them): below, its argument is 1 exactly and the value -0.0,
    written directly (the same numbers, bitwise; it was a fifth of the smoothed contact's
    time)."""
    out = np.full_like(t, -0.0)
    near = t > _F2_ZERO
    tn = t[near]
    vals = np.empty_like(tn)
    neg = tn <= 0.0
    vals[neg] = -spence(1.0 + np.exp(tn[neg]))
    tp = tn[~neg]
    vals[~neg] = 0.5 * tp * tp + np.pi**2 / 6.0 + spence(1.0 + np.exp(-tp))
    out[near] = vals
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

    #: Newton's method compiled (True) or in NumPy (the reference; :meth:`_newton`)
    compiled: bool = True

    def __init__(self, problem: _Problem) -> None:
        self.problem = problem
        self.state: list[tuple[NDArray[np.float64], float, float] | None] = [None] * len(
            problem.cases
        )
        grid = problem.subgrid
        n_el, m = grid.x.shape
        w = np.ones(m)
        w[[0, -1]] = 0.5
        self.weights = np.broadcast_to(w / (m - 1), (n_el, m)).copy()  # one per element
        self.shape = np.ascontiguousarray(grid.shape)  # (n_el, m, 4)
        self.xs = grid.x
        self.nmat = grid.matrix  # (S, 2n) sparse
        self.nmat_t = grid.matrix.T.tocsr()
        self.phi_sub = csr_matrix(problem.phi_z_sub)  # (S, n_z), four B-splines per point

    # -- the sub-grid foundation
    def _gaps(self, z0s, u, a, b):
        return z0s + a + b * self.xs + (self.nmat @ u).reshape(self.xs.shape)

    def _assemble_vector(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Σ_s q_s N_s over the sub-grid, assembled on the DOFs (2n,)."""
        return self.nmat_t @ q.ravel()

    def _assemble_z0(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Σ_s q_s N_s ⊗ ∂z0(x_s)/∂φ, assembled (2n, n_z - 2): in the sparse B-spline basis,
        then projected off the linear part."""
        return (self.nmat_t @ (self.phi_sub.multiply(q.ravel()[:, None]))) @ self.problem.q_z

    def _hessian(self, ab, d):
        """The clamped stiffness plus the foundation's element matrices Σ_s d_s N_s N_sᵀ, the
        clamped DOFs the identity (compiled: :func:`~skisnow.identify._banded_kernel.
        smoothed_hessian`)."""
        return smoothed_hessian(ab, d, self.shape, self.problem.clamp)

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
        z0s = (pr.phi_z_sub @ theta_z).reshape(self.xs.shape)
        idx = range(len(pr.cases)) if cases is None else cases
        res, jac = [], []
        for k in idx:
            c = pr.cases[k]
            f = pr._clamp(c.f_boot)
            kc = c.force / (_N_REF * eps)
            state = None
            if self.state[k] is not None:
                state = self._newton(ab, z0s, f, c.f_total, c.m_total, kc, eps, self.state[k])
            if state is None:  # no previous state, or Newton failed from it: the exact contact
                pr.evaluate(p, jacobian=False, cases=[k])
                state = self._newton(ab, z0s, f, c.f_total, c.m_total, kc, eps, pr.last_state[k])
            if state is None:
                raise ConvergenceError(
                    f"smoothed contact of load case m = {c.mass:g} kg did not converge",
                    result=None,
                )
            u, a, b = state
            self.state[k] = (u, a, b)
            hmod = pr.phi_z_cases[k] @ theta_z + a + b * c.x + c.hermite @ u
            bw = c.w * pr.bin_weights[k] / pr.sigma_cases[k]
            res.append(bw * (hmod - c.h))
            if not jacobian:
                continue
            t = -self._gaps(z0s, u, a, b) / eps
            d = self.weights * kc * expit(t)  # (n_el, m)
            hess = self._hessian(ab, d)
            # ∂(∇Π)/∂θ_E: dK/dθ_j u;  ∂(∇Π)/∂φ: the foundation's d times z0's basis there
            ue = np.stack([u[0:-2:2], u[1:-2:2], u[2::2], u[3::2]], axis=1)
            kappa = np.einsum("eqa,ea->eq", pr.bq, ue)
            coef = pr.wq * ei_q * kappa
            contrib = np.matmul((coef[:, :, None] * pr.bq).transpose(0, 2, 1), pr.phi_q)
            n_e, n_p = pr.n_e, pr.n_e + pr.n_z - 2
            rhs_u = np.zeros((2 * n, n_p + 2), order="F")
            rhs_u[: 2 * n - 2, :n_e] += contrib[:, 0:2, :].reshape(2 * n - 2, n_e)
            rhs_u[2:, :n_e] += contrib[:, 2:4, :].reshape(2 * n - 2, n_e)
            rhs_u[:, n_e:n_p] = self._assemble_z0(d)
            rhs_u[2 * cl : 2 * cl + 2] = 0.0
            np.negative(rhs_u, out=rhs_u)
            dq_sum = (self.phi_sub.T @ d.ravel()) @ pr.q_z
            dq_x = (self.phi_sub.T @ (d * self.xs).ravel()) @ pr.q_z
            rhs_ab = -np.concatenate([np.zeros((2, pr.n_e)), np.stack([dq_sum, dq_x])], axis=1)
            du, da, db = self._solve(hess, d, rhs_u, rhs_ab, room=True)
            dh = c.hermite @ du + da[None, :] + c.x[:, None] * db[None, :]
            dh[:, pr.n_e :] += pr.q_z_cases[k]
            jac.append(bw[:, None] * dh)
        r_all = np.concatenate(res)
        return r_all, (np.concatenate(jac) if jacobian else None)

    def _newton(self, ab, z0s, f, f_total, m_total, kc, eps, start):
        """Newton's method with backtracking on Π from ``start`` = (u, a, b); None if it fails
        (a start far off can overflow: that is a failure, not a warning). Compiled
        (:func:`~skisnow.identify._smooth_kernel.newton_smoothed`) unless :attr:`compiled` is
        False: then the NumPy route of :meth:`_newton_steps`, the same steps and tests, kept as
        the reference the compiled one is tested against."""
        if self.compiled:
            return newton_smoothed(
                ab=ab, shape=self.shape, xs=self.xs, weights=self.weights, z0s=z0s, f=f,
                f_total=f_total, m_total=m_total, kc=kc, eps=eps, start=start,
                clamp=self.problem.clamp, floor_h=1e-3 * self.problem.sigma,
            )  # fmt: skip
        with np.errstate(over="ignore", invalid="ignore"):
            return self._newton_steps(ab, z0s, f, f_total, m_total, kc, eps, start)

    def _newton_steps(self, ab, z0s, f, f_total, m_total, kc, eps, start):
        pr = self.problem
        cl = pr.clamp
        xs, wts = self.xs, self.weights
        u, a, b = start
        u = u.copy()
        for _ in range(100):
            h = self._gaps(z0s, u, a, b)
            t = -h / eps
            r = wts * kc * eps * _softplus(t)  # (n_el, m) weighted reactions
            d = wts * kc * expit(t)
            g_u = _banded_matvec(ab, u) - f - self._assemble_vector(r)
            g_u[2 * cl : 2 * cl + 2] = 0.0
            g_a = f_total - float(r.sum())
            g_b = m_total - float(np.sum(r * xs))
            hess = self._hessian(ab, d)
            step_u, step_a, step_b = self._solve(hess, d, -g_u[:, None], -np.array([[g_a], [g_b]]))
            su, sa, sb = step_u[:, 0], float(step_a[0]), float(step_b[0])
            dh = (self.nmat @ su).reshape(xs.shape) + sa + sb * xs
            slope = float(g_u @ su + g_a * sa + g_b * sb)
            step_h = float(np.max(np.abs(dh)))
            if not np.isfinite(step_h):
                return None
            # converged (quadratically): the last step. Its floor is the roundoff of the
            # bordered solve, which with a few stiff foundation points (a light load case on
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
            lin = slope + float(np.sum(r * dh))  # the elastic and load part of the slope
            quad = float(su @ _banded_matvec(ab, su))
            f2_0 = _f2(t)
            alpha = 1.0
            while True:
                t1 = -(h + alpha * dh) / eps
                d_pi = (
                    alpha * lin
                    + 0.5 * alpha**2 * quad
                    + kc * eps**2 * float(np.sum(wts * (_f2(t1) - f2_0)))
                )
                if d_pi <= 1e-4 * alpha * slope:
                    break
                alpha *= 0.5
                if alpha < 1e-10:
                    return None
            u, a, b = u + alpha * su, a + alpha * sa, b + alpha * sb
        return None

    def _solve(self, hess, d, rhs_u, rhs_ab, room=False):
        """Solve the bordered system [[A, C], [Cᵀ, S0]] [y; (a, b)] = [rhs_u; rhs_ab] with A
        banded (clamped stiffness + foundation) and C = Σ_s d_s N_s [1, x_s] (Schur
        complement). ``room``: ``rhs_u`` is a Fortran-ordered array with two trailing columns
        to spare, overwritten by C and the solution (no copy of a Jacobian's right-hand
        sides)."""
        pr = self.problem
        n = pr.n
        xs = self.xs
        cmat = np.stack([self.nmat_t @ d.ravel(), self.nmat_t @ (d * xs).ravel()], axis=1)
        cmat[2 * pr.clamp : 2 * pr.clamp + 2] = 0.0
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
        sd, sdx, sdxx = float(d.sum()), float(np.sum(d * xs)), float(np.sum(d * xs * xs))
        s0 = np.array([[sd, sdx], [sdx, sdxx]])
        schur = s0 - cmat.T @ yc
        rhs = rhs_ab - cmat.T @ yr
        try:
            sol = np.linalg.solve(schur, rhs)
        except np.linalg.LinAlgError:
            sol = np.linalg.lstsq(schur, rhs, rcond=None)[0]
        return yr - yc @ sol, sol[0], sol[1]
