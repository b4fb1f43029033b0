"""Correlated-residual band variants on cached fits (issue 25, seventh pass: the default bands).

Each variant maps the cached linearisation of a fit (``bench_band_variants.py --fit``) to a
parameter covariance; :func:`profiles` turns it into the stations' bands. The variants are the
three candidates of the seventh pass:

* ``hac-L``: a heteroscedasticity-and-autocorrelation-consistent sandwich (Newey & West 1987,
  Bartlett weights; Andrews 1991 for the automatic bandwidth ``hac-auto``) of the residuals
  along each profile, in place of the white-noise JᵀJ of the Laplace posterior: A⁻¹ (S + PᵀP)
  A⁻¹, S = Σ_k J_kᵀ (r_k r_kᵀ ∘ K_L) J_k, residuals scaled by (1 - h_ii)^-1/2 (leverage, HC2);
* ``gp-…``: a smooth model discrepancy (Kennedy & O'Hagan 2001) of the fit's own excess δ
  (the diagnosis's δ² = (χ² - dof)/n, or its upper bound) with a correlation length, added to
  the noise covariance: A⁻¹ Jᵀ Σ_d J A⁻¹ on top of the Laplace posterior;
* ``neff``: the Laplace posterior's data part inflated by n / n_eff, the ratio of nominal to
  effective samples from the residuals' pooled autocorrelation (Bartlett-weighted sum).
"""

from __future__ import annotations

import numpy as np

from skisnow.identify import _bands as B
from skisnow.identify._result import DEFAULT_LAMBDAS


def _split(v, sizes):
    return np.split(v, np.cumsum(sizes)[:-1])


def autocov(r, sizes, max_lag):
    """Pooled autocovariances c_0..c_max_lag of the σ-normalised residuals over the cases."""
    c = np.zeros(max_lag + 1)
    n = np.zeros(max_lag + 1)
    for part in _split(r, sizes):
        for lag in range(min(max_lag + 1, part.size)):
            c[lag] += float(part[: part.size - lag] @ part[lag:])
            n[lag] += part.size - lag
    return c / np.maximum(n, 1)


def andrews_bandwidth(r, sizes):
    """Andrews (1991) AR(1) plug-in bandwidth of the Bartlett kernel, in bins."""
    c = autocov(r, sizes, 1)
    rho = float(np.clip(c[1] / c[0], -0.97, 0.97))
    alpha = 4 * rho**2 / ((1 - rho) ** 2 * (1 + rho) ** 2)
    n = float(np.median(sizes))
    return max(1, int(np.ceil(1.1447 * (alpha * n) ** (1 / 3))))


def hac_middle(jac, r, sizes, lag, leverage=None):
    """Σ_k J_kᵀ (r_k r_kᵀ ∘ K) J_k with Bartlett weights K_ij = max(0, 1 - |i-j|/(lag+1))."""
    if leverage is not None:
        r = r / np.sqrt(np.maximum(1 - leverage, 0.05))
    p = jac.shape[1]
    s = np.zeros((p, p))
    start = 0
    for m in sizes:
        jk, rk = jac[start : start + m], r[start : start + m]
        start += m
        i = np.arange(m)
        kern = np.maximum(0.0, 1.0 - np.abs(i[:, None] - i[None, :]) / (lag + 1.0))
        s += jk.T @ ((np.outer(rk, rk) * kern) @ jk)
    return s


def base(g):
    sol, problem, lam = g["sol"], g["problem"], g["lam"]
    lam_u = min(lam / B.UNDERSMOOTHING, min(DEFAULT_LAMBDAS))
    smooth = B.smoothing_bias(sol, problem.penalty(lam_u)) if lam > 0 else None
    return sol, problem, smooth


def covariance(g, variant):
    """The parameter covariance of a variant (module docstring); also returns a note."""
    sol, problem, smooth = base(g)
    post = B.posterior(sol, g["model_error"], smooth)
    if variant == "current":
        return post, ""
    sizes = [c.x.size for c in problem.cases]
    jac, r = sol.jac, sol.fun
    jtj, ptp = sol.jtj, sol.pen.T @ sol.pen
    a_inv = np.linalg.pinv(jtj + ptp)
    extra = post.covariance - post.inflation * a_inv  # bias, smoothing terms
    n = r.size
    if variant.startswith("hac"):
        tag = variant.split("-", 1)[1]
        lev = np.einsum("ij,jk,ik->i", jac, a_inv, jac)
        lag = andrews_bandwidth(r, sizes) if tag == "auto" else int(tag)
        s = hac_middle(jac, r, sizes, lag, lev)
        cov = a_inv @ (s + ptp) @ a_inv
        # never narrower than the Laplace posterior: max in the Loewner sense is not cheap;
        # the HAC replaces only the data part
        return _with(post, cov + extra), f"L={lag}"
    if variant.startswith("neff"):
        lag = 20 if variant == "neff" else int(variant.split("-")[1])
        c = autocov(r, sizes, lag)
        rho = c[1:] / c[0]
        w = 1 - np.arange(1, lag + 1) / (lag + 1)
        f = max(1.0, 1 + 2 * float(np.sum(w * rho)))
        cov = post.inflation * a_inv @ (f * jtj + ptp) @ a_inv
        return _with(post, cov + extra), f"f={f:.2f}"
    if variant == "option":
        # identify_ski(discrepancy_bands=True): the diagnosis's δ (dof of the discrepancy
        # bound) as a smooth discrepancy of DISCREPANCY_LENGTH
        from skisnow.identify._homotopy import restart_bound

        dof = restart_bound(jac, sol.pen, jtj=jtj)[1]
        delta = float(np.sqrt(max(float(r @ r) - dof, 0.0) / n))
        if delta == 0:
            return post, "δ=0"
        rows = [(c.x, c.w * problem.bin_weights[k] / problem.sigma_cases[k])
                for k, c in enumerate(problem.cases)]  # fmt: skip
        rms = B.discrepancy_rms(delta, rows)
        disc = B.discrepancy_covariance(sol, rows, rms=rms)
        post = B.posterior(sol, g["model_error"], smooth, disc)
        return post, f"δ={delta:.3f}σ, {rms * 1e6:.2f} µm"
    if variant.startswith("gp"):
        # gp-<delta rule>-<length mm>[-common rho]
        parts = variant.split("-")
        rule, length = parts[1], float(parts[2]) * 1e-3
        rho_c = float(parts[3]) if len(parts) > 3 else 0.0
        dof = float(n - np.trace(a_inv @ jtj))
        chi2 = float(r @ r)
        if rule == "d":
            d2 = max(chi2 - dof, 0.0) / n
        elif rule == "du":  # the upper bound: the excess the misfit cannot exclude (2 sd)
            d2 = max(chi2 - dof + 2 * np.sqrt(2 * dof), 0.0) / n
        elif rule == "dc":
            from skisnow.identify._diagnosis import correlated_excess

            d2 = correlated_excess(r, sizes)
        else:
            d2 = float(rule) ** 2
        xs = [c.x for c in problem.cases]
        wts = [c.w * problem.bin_weights[k] for k, c in enumerate(problem.cases)]
        x = np.concatenate(xs)
        w = np.concatenate(wts)
        case = np.concatenate([np.full(m, k) for k, m in enumerate(sizes)])
        kern = np.exp(-0.5 * ((x[:, None] - x[None, :]) / length) ** 2)
        same = case[:, None] == case[None, :]
        kern = np.where(same, kern, rho_c * kern)
        # δ² is the excess per bin in residual units; a bin of c stations carries a height
        # error's residual √c times: the height process's variance is δ² / mean(w²)
        jw = w[:, None] * jac
        mid = d2 / float(np.mean(w**2)) * (jw.T @ (kern @ jw))
        return _with(post, post.covariance + a_inv @ mid @ a_inv), f"δ={np.sqrt(d2):.3f}σ"
    raise ValueError(variant)


def _with(post, cov):
    from dataclasses import replace

    return replace(post, covariance=cov)


def profiles(g, post):
    return B.identified_profiles(g["problem"], g["sol"].x, post, g["x_tail"], g["x_tip"],
                                 bent=g["bent"], measured=g["measured"])  # fmt: skip
