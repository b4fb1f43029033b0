"""Are two skis the same within their uncertainty? A simultaneous (curve-wise) test (issue 25).

Two skis, one or both identified from a bench, are compared over the stations where both are
determined by their data (:mod:`skisnow.workflows._pairs`). Under the hypothesis *same ski*
the differences Δz0(x) and Δ log EI(x) are the estimation errors of the identifications: a
Gaussian with the sum of the skis' posterior covariances (the Laplace posterior of
:func:`skisnow.identify.identify_ski`, carried in the ski file as modes M, covariance MᵀM; a
ski without bands, a shipped definition, adds none).

**The test is simultaneous, not pointwise.** The rule before it (the differences within the
pointwise combined 95 % band at ≥ 95 % of the stations) is miscalibrated by construction: with
perfectly calibrated pointwise bands the expected covered fraction *is* 95 %, so a ski paired
with its own identification fails it whenever the covered share falls below its mean (measured
on Gaussian differences whose bands are calibrated by construction: a tie only 60-66 % of the
time, ``tests/workflows/test_same_ski.py`` and ``benchmarks/bench_pair_ties.py``). Here the
statistic is the largest standardised difference over both curves,

    T = max_x max(|Δz0(x)| / s_z(x), |Δ log EI(x)| / s_E(x)),

and the pair is *a tie within uncertainty* when T ≤ c, c the ``level`` quantile of the same
maximum under the hypothesis: the *sup-t* simultaneous band (Montiel Olea & Plagborg-Møller
2019, "Simultaneous confidence bands: theory, implementation, and an application to SVARs",
J. Appl. Econometrics 34, eq. 6; Ruppert, Wand & Carroll 2003, *Semiparametric Regression*,
§6.5: the critical value of max |Z(x)|/sd(x) by simulation from the estimator's covariance). A
ski identical to the truth under calibrated bands ties with probability ``level`` whatever the
number and correlation of the stations.

* **Scale**: s(x) is the skis' combined 95 % band / 2, hypot(sd_a, sd_b), from the ski files'
  bands. The modes an identified ski carries are the posterior's square root truncated (since
  the seventh pass of issue 25 by singular values of its correlation form, ≤ 60 modes: a median
  98 % of each band on the shipped classic's shop bench; files written before kept the
  directions of the raw joint variance, whose z0 sd was a median 0.48 of the band); the bands
  are the full posterior's, so they set the scale and the modes only the correlation along the
  ski (what the critical value depends on).
* **Critical value**: the hypothesis is the Gaussian with the modes' correlation and the bands'
  sd (each mode rescaled per station by band sd / modes' sd); c is the ``level`` quantile of T
  over ``draws`` draws of it (ξ ~ N(0, I) times the modes, standardised per station) at a fixed
  seed, so the verdict is reproducible. At the default 4000 draws the Monte Carlo error of the
  achieved level is ±0.34 % (binomial, sqrt(0.95·0.05/4000)), small beside the calibration of
  the bands themselves, which is the limit (the Laplace z0 bands under-cover). Without modes
  (bands only: a ski file written before them) c is the Bonferroni bound
  z_{1-(1-level)/(2m)} over the m compared values (conservative: a tie at least ``level`` of
  the time under calibrated bands).
* **z0 as rested**: both skis' z0 rest on the plane through their lowest points (the lower
  hull), and the bands are those of the rested z0 (the identification's linearisation moves the
  resting line with the fit), so the rested curves are compared as they are. A line in z0 is a
  rigid rotation no bench or snow sees, but removing it needs the full covariance of z0: the
  truncated modes, tried, put the rested z0 near the rear support within 0.5 µm after removing
  a line (band 2.7 µm) and called the shipped classic and its own bench apart at 8.6 sd.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.special import ndtri

from skisnow._errors import InputError

__all__ = ["DEFAULT_TIE_DRAWS", "DEFAULT_TIE_LEVEL", "SameSkiTest", "same_ski_test"]

#: The test's level: a ski paired with its own identification ties with this probability when
#: its bands are calibrated.
DEFAULT_TIE_LEVEL = 0.95
#: Gaussian draws for the critical value (Monte Carlo error of the level ±0.34 %).
DEFAULT_TIE_DRAWS = 4000
_FLOOR = 1e-3  # scales below this fraction of their median are raised to it (round-off only)


@dataclass(frozen=True, kw_only=True)
class SameSkiTest:
    """The simultaneous "same ski?" test of two skis (module docstring).

    ``statistic``: the largest standardised difference T; ``critical``: c at ``level``;
    ``worst``: where T is reached (``'camber'`` or ``'stiffness'``, station [m]);
    ``method``: ``'sup-t'`` (posterior modes) or ``'bonferroni'`` (bands only); ``draws``: the
    Gaussian draws behind c (0 for Bonferroni); ``p_value``: the share of draws at least as
    extreme as T (NaN for Bonferroni).
    """

    statistic: float
    critical: float
    level: float
    method: str
    draws: int
    p_value: float
    worst: tuple[str, float]

    @property
    def tie(self) -> bool:
        """Whether the skis are a tie within uncertainty (T ≤ c)."""
        return bool(self.statistic <= self.critical)

    def text(self) -> str:
        """One line for outputs."""
        what = "a tie" if self.tie else "not a tie"
        return (
            f"{what} within uncertainty: largest standardised difference {self.statistic:.2f} "
            f"({self.worst[0]} at {self.worst[1] * 1e3:+.0f} mm) against the simultaneous "
            f"{100 * self.level:g} % critical value {self.critical:.2f} ({self.method})"
        )


def same_ski_test(
    *,
    x: NDArray[np.float64],
    dz: NDArray[np.float64],
    dk: NDArray[np.float64],
    sd_z: NDArray[np.float64],
    sd_k: NDArray[np.float64],
    modes_z: NDArray[np.float64] | None,
    modes_k: NDArray[np.float64] | None,
    level: float = DEFAULT_TIE_LEVEL,
    draws: int = DEFAULT_TIE_DRAWS,
    seed: int = 0,
) -> SameSkiTest:
    """The simultaneous test that two skis are the same (module docstring).

    Parameters
    ----------
    x
        The compared stations [m] (both skis determined), shape (n,).
    dz, dk
        Differences of z0 [m] and of log EI at ``x``.
    sd_z, sd_k
        The combined standard deviations hypot(sd_a, sd_b) at ``x`` (the bands / 2).
    modes_z, modes_k
        The combined posterior modes at ``x``, shape (k, n) each (the rows of both skis
        stacked; ``None``: no modes, the Bonferroni bound is used).
    level, draws, seed
        The test's level, the Gaussian draws for its critical value and their seed.
    """
    if not 0.0 < level < 1.0:
        raise InputError(f"level: need a probability in (0, 1), got {level!r}")
    if not (isinstance(draws, int) and draws >= 100):
        raise InputError(f"draws: need an integer >= 100 for a quantile, got {draws!r}")
    x = np.asarray(x, dtype=float)
    sz = np.maximum(np.asarray(sd_z, float), _FLOOR * max(float(np.median(sd_z)), 1e-300))
    sk = np.maximum(np.asarray(sd_k, float), _FLOOR * max(float(np.median(sd_k)), 1e-300))
    with_modes = modes_z is not None and modes_k is not None
    tz, tk = np.abs(np.asarray(dz, float)) / sz, np.abs(np.asarray(dk, float)) / sk
    iz, ik = int(np.argmax(tz)), int(np.argmax(tk))
    worst = ("camber", float(x[iz])) if tz[iz] >= tk[ik] else ("stiffness", float(x[ik]))
    stat = float(max(tz[iz], tk[ik]))
    if not with_modes:
        m = 2 * x.size
        return SameSkiTest(statistic=stat, critical=float(ndtri(1.0 - (1.0 - level) / (2 * m))),
                           level=level, method="bonferroni", draws=0, p_value=float("nan"),
                           worst=worst)  # fmt: skip
    rng = np.random.default_rng(seed)
    t = np.zeros(draws)
    # the hypothesis: a Gaussian with the modes' correlation and the bands' sd (each mode
    # rescaled per station by band sd / modes' sd); its draws standardised by that sd
    mz, mk = (np.asarray(m, float) for m in (modes_z, modes_k))
    own_z, own_k = _own_sd(mz), _own_sd(mk)
    for lo in range(0, draws, 500):  # blocks: (500, n) at a time
        xi = rng.standard_normal((min(500, draws - lo), mz.shape[0]))
        t[lo : lo + xi.shape[0]] = np.maximum(
            np.max(np.abs(xi @ mz) / own_z, axis=1), np.max(np.abs(xi @ mk) / own_k, axis=1)
        )
    return SameSkiTest(
        statistic=stat,
        critical=float(np.quantile(t, level)),
        level=level,
        method="sup-t",
        draws=draws,
        p_value=float(np.mean(t >= stat)),
        worst=worst,
    )


def _own_sd(modes: NDArray[np.float64]) -> NDArray[np.float64]:
    """The sd of the draws ξ·modes per station, floored (a station the modes do not reach)."""
    s = np.sqrt(np.sum(modes**2, axis=0))
    return np.maximum(s, _FLOOR * max(float(np.median(s)), 1e-300))
