"""λ by leave-one-load-case-out cross-validation on the Gauss–Newton linearisation of a fit.

GCV (Craven & Wahba 1979) treats every bin of every profile as an independent datum. A bench's
heights also hold errors that are correlated along a profile and differ from one load case to
the next — the bench's own model error (its stone, its contact resolution: the independent
reference bench at 1 mm differs from the converged beam by 0.2-6.9 µm rms per load case on
issue 25's ski, correlated over 80-200 mm) — which no single ski explains. With a few hundred
bins per profile GCV reads such an error as signal and undersmooths (Opsomer, Wang & Yang 2001:
cross-validation under correlated errors chooses too little smoothing); with the 16 000 bins of
a full plan it chose λ = 1 on issue 25's ski where λ = 100 halved the EI error
(docs/validation/identification-uncertainty.md, fourth pass).

The unit of independence is the load case: leave-one-curve-out cross-validation (Rice &
Silverman 1991, for curves with correlated errors within each curve). For every case k the
penalised linear step is taken without its bins,

    δ₋ₖ = −(A − Jₖᵀ Jₖ)⁻¹ (g − Jₖᵀ rₖ),   A = JᵀJ + PᵀP,   g = Jᵀ r + Pᵀ (P p − t),

and the case is predicted from the others, rₖ + Jₖ δ₋ₖ; the score is the mean square of the
predictions over all bins. An error particular to one case cannot be predicted from the others,
so fitting it gains nothing; what the cases share (the ski) is rewarded. The score is measured
in the same σ-normalised units whatever the number of stations, so the choice does not drift
with the size of the plan. Cost: one solve of the parameters' size per case and λ.

The choice (:func:`choose`): the smoothest λ whose score is not worse than the best one's by
more than one standard error of their difference over the load cases (the one-standard-error
rule, Breiman et al. 1984, §3.4.3; Hastie, Tibshirani & Friedman 2009, §7.10; paired over the
same cases). On a full plan the scores of λ = 1…1000 differ by 1 % (issue 25's ski: the stiffness
of the glide zones pressed flat on the stone hardly changes the heights), a difference no larger
than its own scatter over the cases; the rule then takes the prior's smoothness instead of
fitting the cases' own errors. As the data grow the standard error shrinks and the rule tends to
the minimum.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np
from numpy.typing import NDArray

from skisnow.identify._bands import _penalised_step
from skisnow.identify._lm import _LmResult

__all__ = ["case_cv", "choose"]


def case_cv(
    sol: _LmResult, pen, lam: float, *, sizes: Sequence[int]
) -> tuple[float, float, float, float, NDArray[np.float64], NDArray[np.float64]]:
    """Leave-one-load-case-out cross-validation of λ on the linearisation at ``sol`` (module
    docstring; Rice & Silverman 1991): ``(λ, score, misfit rms / σ, edf, step, per_case)``
    like :func:`~skisnow.identify._bands._gcv`, plus each case's share of the score (they sum to
    it). ``sizes``: the number of bins of each load case, in the order of the residuals; ``pen``
    the penalty rows of λ (or ``(rows, target)``)."""
    r, jtj, _, a, a_inv, step, rl, _ = _penalised_step(sol, pen)
    g = -(a @ step)
    j = sol.jac
    cuts = np.cumsum([0, *sizes])
    if cuts[-1] != r.size:
        raise ValueError(f"case sizes sum to {cuts[-1]}, the residuals have {r.size}")
    shares = np.zeros(len(sizes))
    for i, (k0, k1) in enumerate(pairwise(cuts)):
        jk, rk = j[k0:k1], r[k0:k1]
        a_k = a - jk.T @ jk
        try:
            d_k = -np.linalg.solve(a_k, g - jk.T @ rk)
        except np.linalg.LinAlgError:
            d_k = -np.linalg.lstsq(a_k, g - jk.T @ rk, rcond=None)[0]
        e = rk + jk @ d_k
        shares[i] = float(e @ e) / max(r.size, 1)
    edf = float(np.trace(a_inv @ jtj))
    return lam, float(shares.sum()), float(np.sqrt(float(rl @ rl) / r.size)), edf, step, shares


def choose(records: Sequence[tuple]) -> int:
    """The index of the chosen λ among ``records`` of :func:`case_cv` (module docstring): the
    largest λ whose score exceeds the lowest by at most one standard error of the paired
    difference of their per-case shares (K cases: the sample standard deviation of K·(shareₖ(λ)
    − shareₖ(λ_min)) over √K)."""
    scores = np.array([rec[1] for rec in records])
    best = int(np.argmin(scores))
    base = np.asarray(records[best][5])
    k = base.size
    chosen = best
    for i, rec in enumerate(records):
        d = k * (np.asarray(rec[5]) - base)
        se = float(np.std(d, ddof=1) / np.sqrt(k)) if k > 1 else 0.0
        if float(d.mean()) <= se and rec[0] > records[chosen][0]:
            chosen = i
    return chosen
