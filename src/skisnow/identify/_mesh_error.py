"""The discretisation error of the identification's forward model, estimated at its fit.

The fit's beam (Hermite elements of ``element_length``, contact resolved between nodes to
:data:`~skisnow.identify._model.FIT_TOL_PENETRATION`) is solved once more at the fitted
parameters on a mesh of half the element length with the tighter penetration tolerance of
:func:`~skisnow.ski.solve_beam` (:data:`~skisnow.ski.DEFAULT_TOL_PENETRATION`): the change of
every bin's model height is the estimate of the discretisation error (the finer solve's own
error is of higher order: measured against the independent finite-difference bench,
:func:`skisnow.bench.reference_profile`, 0.01-0.26 µm rms at 200-800 elements). Its rms and
largest value are reported with the fit, in the ski file's provenance, and its effect on the
parameters enters the bands (:func:`~skisnow.identify._bands.posterior`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import ConvergenceError
from skisnow.identify._cases import load_cases
from skisnow.identify._model import _Problem
from skisnow.ski import DEFAULT_TOL_PENETRATION

__all__ = ["MeshError", "mesh_error"]


@dataclass(frozen=True, kw_only=True, eq=False)
class MeshError:
    """The discretisation error at a fit: rms and largest change [m] of the model heights of
    the bins on the finer mesh, the σ-normalised change of each bin (``residual_change``), and
    the element lengths [m] compared (fit, finer)."""

    rms: float
    max: float
    residual_change: NDArray[np.float64] | None
    element_length: float
    finer_element_length: float


def mesh_error(
    problem: _Problem,
    parameters: NDArray[np.float64],
    raw: Sequence[Any],
    *,
    boot_length: float,
    bin_width: float,
) -> MeshError:
    """The discretisation error of ``problem`` at ``parameters`` (module docstring); ``raw``
    the load cases as :func:`~skisnow.identify._cases.load_cases` takes them."""
    nodes = problem.nodes
    fine_nodes = np.linspace(nodes[0], nodes[-1], 2 * (nodes.size - 1) + 1)
    cases, *_ = load_cases(raw, fine_nodes, boot_length, bin_width)
    fine = _Problem(cases, fine_nodes, problem.n_e, problem.n_z, problem.sigma_cases)
    fine.tol_penetration = DEFAULT_TOL_PENETRATION
    fine.bin_weights = list(problem.bin_weights)
    le = float(nodes[1] - nodes[0])
    try:
        r_fit, _ = problem.evaluate(parameters, jacobian=False)
        r_fine, _ = fine.evaluate(parameters, jacobian=False)
    except (ConvergenceError, np.linalg.LinAlgError):
        return MeshError(rms=np.inf, max=np.inf, residual_change=None, element_length=le,
                         finer_element_length=le / 2)  # fmt: skip
    delta = r_fine - r_fit
    scale = np.concatenate(
        [
            problem.sigma_cases[k] / (c.w * problem.bin_weights[k])
            for k, c in enumerate(problem.cases)
        ]
    )
    counts = np.concatenate([c.w**2 for c in problem.cases])
    dh = delta * scale
    rms = float(np.sqrt(np.sum(counts * dh**2) / np.sum(counts)))
    return MeshError(
        rms=rms, max=float(np.max(np.abs(dh))), residual_change=delta, element_length=le,
        finer_element_length=le / 2,
    )  # fmt: skip
