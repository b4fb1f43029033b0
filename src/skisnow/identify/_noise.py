"""The bench noise, estimated from the data of each load case without a model.

A difference-based estimator (Rice 1984; Gasser, Sroka & Jennen-Steinmetz 1986; Hall, Kay &
Titterington 1990): along a profile sampled at stations x_i, the combination of five consecutive
heights that annihilates every cubic, Σ_j w_j h_{i+j} with Σ w_j = Σ w_j x_j = Σ w_j x_j² =
Σ w_j x_j³ = 0 and Σ w_j² = 1 (on equally spaced stations the fourth difference
(1, -4, 6, -4, 1) / √70), has the variance σ² of the noise wherever the profile is a cubic over
the five stations. The scale is the median absolute pseudo-residual / 0.6745 (Hampel 1974):
robust to the few stations at contact points, at sharp stiffness steps and to outliers.

**Across profiles** (issue 25, fourth pass). A loaded profile is the free camber z0(x) plus the
beam's deflection; the deflection is a cubic between loads and contact points, z0 is not: a
base's waviness of 15 µm on a 60 mm wavelength has fourth differences of ~16 µm at 20 mm
stations, and a single profile's estimate read 1.53 times the true noise there on average
(up to 3.7 times; 12 skis of the independent reference bench × 20 noise seeds,
``benchmarks/bench_noise_estimator.py``). Profiles measured at
the same stations share z0 exactly, so the estimator is applied to each profile's deviation
from the mean of its group (all load cases with the same stations): z0 cancels, what is left is
a difference of smooth deflections and the noise. With m profiles of noise σ_k, the deviation of
profile k has the variance v_k = σ_k² (1 - 2/m) + Σ_j σ_j² / m², a linear system solved for the
σ_k² (m >= 3; m = 2 gives one σ² for both). A load case whose stations no other case shares
keeps the single-profile estimator. Unbiased within 1 % at 2-20 mm stations on the same
benches (docs/validation/identification-uncertainty.md, "Fourth pass").

Per load case: each case's estimate is kept where it differs from the pooled one by more than
three of its standard errors (a case measured by another sensor, on another day), else the
pooled estimate is used (with ~200 stations a profile's own estimate scatters by ~10 %, which
would only add noise to the weights).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["NoiseEstimate", "estimate_noise"]

#: Standard error of log σ̂ from n pseudo-residuals, as c / √n: the MAD of a Gaussian sample
#: has an asymptotic relative efficiency of 37 % (Hampel 1974), and neighbouring fourth
#: differences overlap (correlation -0.8 between neighbours): measured 1.6 by simulation
#: (2000 profiles of 200 stations of white noise).
_SE_FACTOR = 1.6

#: The MAD of a Gaussian sample over its standard deviation (Hampel 1974).
_MAD_SCALE = 1.4826


class NoiseEstimate:
    """Per-case noise [m] (``sigma``), the pooled noise, the per-case raw estimates and the
    number of pseudo-residuals behind each (``count``); ``own`` marks the cases that keep their
    own estimate; ``across`` the cases estimated across profiles (module docstring);
    ``interval`` the 95 % interval of the pooled noise [m] (``_SE_FACTOR`` / √n on log σ)."""

    __slots__ = ("across", "count", "interval", "own", "pooled", "raw", "sigma")

    def __init__(self, sigma, pooled, raw, count, own, across=None, interval=None) -> None:
        self.sigma, self.pooled, self.raw, self.count, self.own = sigma, pooled, raw, count, own
        self.across = np.zeros(len(raw), dtype=bool) if across is None else across
        self.interval = (pooled, pooled) if interval is None else interval


def pseudo_residuals(x: NDArray[np.float64], h: NDArray[np.float64]) -> NDArray[np.float64]:
    """The unit-variance combinations of five consecutive heights that annihilate cubics
    (module docstring), at every window of stations ``x`` (sorted)."""
    order = np.argsort(x, kind="stable")
    x, h = np.asarray(x, dtype=float)[order], np.asarray(h, dtype=float)[order]
    if x.size < 5:
        return np.zeros(0)
    win = np.lib.stride_tricks.sliding_window_view(np.arange(x.size), 5)
    xw = x[win] - x[win][:, 2:3]
    scale = np.maximum(np.ptp(xw, axis=1, keepdims=True), 1e-12)
    t = xw / scale
    vand = np.stack([np.ones_like(t), t, t**2, t**3], axis=1)  # (m, 4, 5)
    _, _, vt = np.linalg.svd(vand)
    w = vt[:, -1, :]  # the null vector of each window (unit norm)
    return np.einsum("mj,mj->m", w, h[win])


def _groups(profiles: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]]) -> list[list[int]]:
    """Indices of the profiles measured at the same stations (to 1 µm), in groups."""
    keys: dict[bytes, list[int]] = {}
    for k, (x, _) in enumerate(profiles):
        keys.setdefault(
            np.round(np.sort(np.asarray(x, dtype=float)) * 1e6).astype(np.int64).tobytes(), []
        ).append(k)
    return list(keys.values())


def _mad(e: NDArray[np.float64]) -> float:
    return _MAD_SCALE * float(np.median(np.abs(e))) if e.size else np.nan


def estimate_noise(
    profiles: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]],
    *,
    across: bool = True,
) -> NoiseEstimate:
    """The noise of each profile ``(x [m], h [m])`` of a bench (module docstring);
    ``across=False``: each profile on its own (the estimator before issue 25's fourth pass).

    Raises ``ValueError`` when no profile has five stations."""
    n_prof = len(profiles)
    raw, count = np.full(n_prof, np.nan), np.zeros(n_prof)
    # how much solving for the cases' own variances amplifies the scatter of each estimate
    gain = np.ones(n_prof)
    # independent pseudo-residuals each case brings to the pooled estimate
    share = np.zeros(n_prof)
    pooled_resid: list[NDArray[np.float64]] = []
    n_eff = 0.0  # independent pseudo-residuals behind the pooled estimate
    is_across = np.zeros(n_prof, dtype=bool)
    groups = _groups(profiles) if across else [[k] for k in range(n_prof)]
    for grp in groups:
        m = len(grp)
        if m == 1:
            k = grp[0]
            e = pseudo_residuals(*profiles[k])
            raw[k], count[k] = _mad(e), e.size
            pooled_resid.append(e)
            n_eff += e.size
            share[k] = e.size
            continue
        # the deviations of each profile from the group's mean at the same stations: z0 cancels
        order = np.argsort(profiles[grp[0]][0], kind="stable")
        x = np.asarray(profiles[grp[0]][0], dtype=float)[order]
        hs = np.stack([np.asarray(profiles[k][1], dtype=float)[np.argsort(profiles[k][0],
                       kind="stable")] for k in grp])  # fmt: skip
        dev = hs - hs.mean(axis=0)
        e = [pseudo_residuals(x, d) for d in dev]
        v = np.array([_mad(ek) ** 2 for ek in e])
        # v_k = σ_k² (1 - 2/m) + S / m², S = Σ σ_j²: Σ v = S (1 - 1/m)
        s_tot = float(np.sum(v)) / (1.0 - 1.0 / m)
        if m >= 3:
            var = np.maximum((v - s_tot / m**2) / (1.0 - 2.0 / m), 0.01 * s_tot / m)
        else:
            var = np.full(m, s_tot / m)
        for i, k in enumerate(grp):
            raw[k], count[k] = float(np.sqrt(var[i])), e[i].size
            # the solve amplifies the scatter of v_k by v_k / ((1 - 2/m) σ_k²): (m - 1) /
            # (m - 2) for equal noises, more for a quiet case among noisy ones
            gain[k] = v[i] / ((1.0 - 2.0 / m) * var[i]) if m >= 3 else 1.0
            share[k] = e[i].size * (m - 1) / m
        is_across[grp] = True
        # for the pooled scale: homoscedastic deviations have the variance σ² (1 - 1/m)
        pooled_resid += [ek / np.sqrt(1.0 - 1.0 / m) for ek in e]
        # m deviations from their mean carry m - 1 independent noise profiles
        n_eff += sum(ek.size for ek in e) * (m - 1) / m
    if not np.any(count > 0):
        raise ValueError("no profile has five stations: the noise cannot be estimated")
    allr = np.concatenate(pooled_resid)
    # a first pooled scale over every pseudo-residual, then the cases that differ from it by
    # more than three of their standard errors keep their own estimate, and the pooled noise
    # is the count-weighted rms of the others' (a noisier case's noise reaches the others'
    # deviations through the mean; the solved variances have it removed)
    pooled = _mad(allr)
    se = gain * _SE_FACTOR / np.sqrt(np.maximum(count, 1.0))
    ok = count > 0
    own = np.zeros(n_prof, dtype=bool)
    for _ in range(2 if across else 1):
        with np.errstate(divide="ignore", invalid="ignore"):
            own = ok & (count >= 20) & (np.abs(np.log(raw / pooled)) > 3.0 * se)
        keep = ok & ~own
        if not (across and keep.any()):
            break  # the estimator before the fourth pass: the MAD over every case
        pooled = float(np.sqrt(np.sum(count[keep] * raw[keep] ** 2) / np.sum(count[keep])))
    n_kept = float(np.sum(share[ok & ~own])) if (ok & ~own).any() else n_eff
    half = 1.96 * _SE_FACTOR / np.sqrt(max(n_kept, 1.0))
    interval = (pooled * float(np.exp(-half)), pooled * float(np.exp(half)))
    sigma = np.where(own, raw, pooled)
    return NoiseEstimate(sigma=sigma, pooled=pooled, raw=raw, count=count, own=own,
                         across=is_across, interval=interval)  # fmt: skip
