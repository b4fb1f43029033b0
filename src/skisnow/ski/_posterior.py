"""Samples of an identified ski from its posterior (the modes its file carries).

An identified ski (:func:`skisnow.identify.identify_ski`) carries the square root of the joint
Laplace posterior of log EI and z0 at its stations (``stiffness_modes``, ``camber_modes``: k
modes). A sample is the ski with log EI + Σ_i ξ_i m_i^E and z0 + Σ_i ξ_i m_i^z, ξ_i ~ N(0, 1)
independent (the modes are the posterior's principal directions scaled by their standard
deviations), rested on the plane again. Samples carry the answers' intervals downstream
(:mod:`skisnow.workflows`): a quantity computed on each sample spreads as the ski's uncertainty
makes it spread, with the correlations along the ski kept (independent draws per station would
make every sample a rough, impossible ski).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import InputError
from skisnow.ski._lcp import lower_hull_bracket
from skisnow.ski._skis import Ski

__all__ = ["sample_skis", "uncertainty_note"]


def _rest(x: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
    i, j = lower_hull_bracket(x, z, 0.0)
    return z - (z[i] + (z[j] - z[i]) * (x - x[i]) / (x[j] - x[i]))


def sample_skis(ski: Ski, n: int, *, seed: int = 0) -> list[Ski]:
    """``n`` skis drawn from the posterior of ``ski`` (module docstring), seeded.

    Raises :class:`~skisnow.InputError` when the ski carries no posterior (a definition such as
    a shipped ski, or a file written before issue 25): its numbers have no stated spread."""
    if not ski.has_posterior:
        raise InputError(
            f"ski {ski.name!r} carries no posterior (no modes in its file): a definition or an "
            "identification made before skisnow stored them; nothing to sample"
        )
    if not (isinstance(n, int) and n >= 1):
        raise InputError(f"n must be an integer >= 1, got {n!r}")
    me = np.asarray(ski.stiffness_modes, dtype=float)
    mz = np.asarray(ski.camber_modes, dtype=float)
    rng = np.random.default_rng(seed)
    xi = rng.standard_normal((n, me.shape[0]))
    log_ei = np.log(np.asarray(ski.stiffness_values))
    z0 = np.asarray(ski.camber_values)
    cx = np.asarray(ski.camber_x)
    out = []
    for k in range(n):
        out.append(
            dataclasses.replace(
                ski,
                name=f"{ski.name} (sample {k + 1})",
                stiffness_values=tuple(np.exp(log_ei + xi[k] @ me)),
                camber_values=tuple(_rest(cx, z0 + xi[k] @ mz)),
                stiffness_log_sd=None,
                camber_sd=None,
                stiffness_determined=None,
                camber_determined=None,
                stiffness_modes=None,
                camber_modes=None,
            )
        )
    return out


def uncertainty_note(ski: Ski) -> str:
    """What the uncertainty of ``ski``'s answers is worth, in words (one place for every output).

    An identified ski carries its posterior (intervals can be drawn). A shipped ski is a
    *calibration*, not an identification: its EI(x) and z0(x) were fitted to the captions of
    Kalliorinne et al. (2023), Figs. 4-7 (the plausible skis under the practitioners' limits, the
    reproduction skis to the captions alone), and carries no stated interval — no defensible
    source exists: the residuals of the calibration say how well the captions are reproduced,
    not how far the ski is from a real one, and a virtual bench of the ski itself would only say
    how well a bench determines it. Any other ski without bands is a definition as given.
    """
    from skisnow.ski._registry import PLAUSIBLE_SKIS, REPRODUCTION_SKIS, get_ski

    if ski.has_posterior:
        return f"ski {ski.name!r} carries the posterior of its identification"
    for names, kind in ((PLAUSIBLE_SKIS, "plausible"), (REPRODUCTION_SKIS, "reproduction")):
        if ski.name in names and get_ski(ski.name) == ski:
            return (
                f"no uncertainty recorded: {ski.name!r} is a shipped {kind} ski, calibrated to "
                "the captions of Kalliorinne et al. (2023), Figs. 4-7, not identified from a "
                "bench; it carries no stated interval (the calibration's residuals say how well "
                "the captions are reproduced, not how far the ski is from a real one), so its "
                "answers are those of the ski as defined, not exact"
            )
    method = ski.provenance.method or "a definition"
    return (
        f"no uncertainty recorded: ski {ski.name!r} carries no bands ({method}); its answers "
        "are those of the ski as given, not exact"
    )
