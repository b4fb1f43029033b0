"""What an identification's result is worth, and why not more: the causes behind its warnings.

A fit is *converged* when it explains the bench down to its noise — its χ² within the
discrepancy bound of its own residual degrees of freedom (:func:`~skisnow.identify._homotopy.
restart_bound`) — and its forward model's discretisation error is below a fifth of the noise.
Otherwise the warning names the cause, checked in this order (the first that applies is the
main cause; every one that applies is listed):

* ``mesh``: the discretisation error (:mod:`skisnow.identify._mesh_error`) is above a fifth of
  the noise — a finer beam (``element_length``, ``--mesh-mm``) is needed;
* ``noise``: the given noise differs from the noise the profiles show by more than a factor 1.5,
  or the load cases' own misfits are not at their noise (some above 1.5 σ while the rest are
  at the noise: their noise is underestimated, or they hold readings the others do not);
* ``evaluations``: the fit stopped at its evaluation limit above the noise (``max_nfev``);
* ``model``: the fit ends above the noise with none of the above: a local minimum of the
  misfit, or a ski the splines cannot follow (``n_stiffness``, ``n_camber``);
* ``information`` (a warning, not a failure): the bench leaves parts of the ski undetermined
  — where no load case bends it (beyond the outermost contacts) or no station measures it;
  the warning names the span and the load cases that would add the information.

At the noise but stopped by the evaluation limit the fit is converged (the limit is said in its
message, no warning): a fit at the noise is what the data can tell.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["Diagnosis", "diagnose"]


class Diagnosis:
    """``converged``, ``warnings`` (text) and ``causes`` (keys, main first)."""

    __slots__ = ("causes", "converged", "warnings")

    def __init__(self, converged: bool, warnings: tuple[str, ...], causes: tuple[str, ...]):
        self.converged, self.warnings, self.causes = converged, warnings, causes


def _span(x: np.ndarray, flags: np.ndarray) -> list[tuple[float, float]]:
    """Runs of undetermined stations [m] (False flags)."""
    bad = np.flatnonzero(~flags)
    if bad.size == 0:
        return []
    cuts = np.flatnonzero(np.diff(bad) > 1) + 1
    return [(float(x[run[0]]), float(x[run[-1]])) for run in np.split(bad, cuts)]


def diagnose(
    *,
    chi2: float,
    bound: float,
    misfit: float,
    lm_status: int,
    noise: float,
    noise_given: float | None,
    noise_data: float,
    case_misfits: Sequence[tuple[float, float, float]],
    mesh_rms: float,
    element_length: float,
    ei_x: np.ndarray,
    ei_determined: np.ndarray,
    bent: tuple[float, float],
    cases: Sequence[tuple[float, float]],
) -> Diagnosis:
    """The diagnosis of a fit (module docstring). ``case_misfits``: ``(mass [kg], x_m [m],
    misfit σ)`` per load case; ``bent``: the span between the outermost contact points of the
    bench [m] (beyond it no bench can bend a ski: not a want of information, no warning);
    ``cases``: ``(mass, x_m)`` of the bench."""
    at_noise = chi2 <= bound
    mesh_ok = mesh_rms <= noise / 5.0
    warnings: list[str] = []
    causes: list[str] = []
    if not np.isfinite(mesh_rms):
        causes.append("mesh")
        warnings.append(
            "model/mesh error: the beam's discretisation error could not be estimated (the "
            "finer beam did not solve at the fitted ski: the fit is far from any ski the bench "
            "could have measured); see the other causes"
        )
    elif not mesh_ok:
        causes.append("mesh")
        warnings.append(
            f"model/mesh error: the beam's discretisation error is {mesh_rms * 1e6:.2g} µm rms "
            f"against a bench noise of {noise * 1e6:.2g} µm (more than a fifth of it); use "
            f"shorter elements than {element_length * 1e3:.3g} mm (--mesh-mm / "
            "element_length)"
        )
    if noise_given is not None and not 1 / 1.5 <= noise_given / max(noise_data, 1e-12) <= 1.5:
        causes.append("noise")
        warnings.append(
            f"noise misestimate: the given noise {noise_given * 1e6:.3g} µm is "
            f"{noise_given / max(noise_data, 1e-12):.2g} times the noise the profiles show "
            f"({noise_data * 1e6:.3g} µm, from their scatter about local cubics); the fit's "
            "weights and bands follow the given value — give the bench's noise or leave it out"
        )
    high = [(m, p, s) for m, p, s in case_misfits if s > 1.5]
    if not at_noise and high and len(high) < len(case_misfits):
        if "noise" not in causes:
            causes.append("noise")
        names = ", ".join(f"{m:g} kg at {p * 1e3:g} mm ({s:.2f} σ)" for m, p, s in high[:6])
        warnings.append(
            f"noise misestimate or odd load cases: {len(high)} of {len(case_misfits)} load "
            f"cases end far above their noise ({names}{', ...' if len(high) > 6 else ''}) while "
            "the others are at it: their noise is larger than estimated, or they hold readings "
            "the others do not"
        )
    if not at_noise and lm_status == 0:
        causes.append("evaluations")
        warnings.append(
            f"evaluation limit: the fit stopped at its evaluation limit at {misfit:.3g} σ, "
            "above the bench noise; allow more evaluations (--max-nfev / max_nfev)"
        )
    if not at_noise and not causes:
        causes.append("model")
        warnings.append(
            f"the fit ended at {misfit:.3g} σ (χ² {chi2:.0f}, above the discrepancy bound "
            f"{bound:.0f}): a local minimum of the misfit, or a ski the splines cannot follow "
            "(more coefficients: --n-stiffness / --n-camber)"
        )
    inside = (ei_x > bent[0] + 0.02) & (ei_x < bent[1] - 0.02)
    spans = [  # stretches of 40 mm or more inside the span a bench can bend
        (a, b) for a, b in _span(ei_x[inside], ei_determined[inside]) if b - a >= 0.04
    ]
    if spans:
        causes.append("information")
        masses = sorted({m for m, _ in cases})
        positions = sorted({p for _, p in cases})
        text = ", ".join(f"{a * 1e3:.0f}..{b * 1e3:.0f} mm" for a, b in spans)
        advice = (
            f"these stretches lie flat on the stone at every load of the bench or carry too "
            f"little bending: masses below {masses[0]:g} kg (the ski then rests on its "
            f"outermost points and bends over its whole length) or load positions away from "
            f"{', '.join(f'{p * 1e3:g}' for p in positions)} mm"
        )
        warnings.append(
            f"too little information: the bench does not determine the stiffness over {text} "
            f"(no load case bends the ski there); those stations are marked not determined and "
            f"carry the prior's band. Load cases that would add it: {advice}"
        )
    converged = bool(at_noise and mesh_ok)
    return Diagnosis(converged, tuple(warnings), tuple(causes))
