"""The load cases of an identification: a bench's profiles, binned on the beam mesh."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow.constants import STANDARD_GRAVITY
from skisnow.identify._model import _bin_average, _bins, _Case, _hermite_matrix
from skisnow.ski import boot_load_vector

__all__ = ["load_cases"]


def _bench_cases(bench: Any, name: str) -> list[tuple[float, float, NDArray, NDArray]]:
    t = bench.table[bench.table["ski"] == name]
    out = []
    for (m, p), grp in t.groupby(["mass_kg", "load_position_mm"], sort=True):
        out.append(
            (float(m), float(p) * 1e-3, grp["x_mm"].to_numpy() * 1e-3,
             grp["height_mm"].to_numpy() * 1e-3)
        )  # fmt: skip
    return out


def load_cases(
    raw: Sequence[tuple[float, float, NDArray[np.float64], NDArray[np.float64]]],
    nodes: NDArray[np.float64],
    boot_length: float,
    bin_width: float,
) -> tuple[list[_Case], float, int, int]:
    """The binned load cases of the fit from raw profiles ``(mass [kg], x_m [m], x [m], h [m])``
    on the beam mesh ``nodes``: ``(cases, scatter sum of squares, samples, scatter degrees of
    freedom)``; each bin's model is the mean of the model at its stations, as the data are
    (also used by :func:`~skisnow.identify.predict_identification_uncertainty`)."""
    cases, scatter, n_samples, scatter_dof = [], 0.0, 0, 0
    for m, p, xs, hs in raw:
        xb, hb, cnt, ss, dof_ = _bins(xs, hs, bin_width)
        scatter += ss
        scatter_dof += dof_
        n_samples += xs.size
        force = m * STANDARD_GRAVITY
        f_boot = boot_load_vector(nodes, force, p, boot_length, "uniform")
        # the bin means of the model's rows where a bin holds several stations; one station per
        # bin (shop plans) keeps the rows at the stations themselves, bit for bit (a fit is
        # sensitive to the last bit: a different summation order of the same rows moved ski
        # 1002's shop fit from EI 10.1 % to 28.8 % off: docs/validation, seventh pass)
        average = _bin_average(xs, bin_width) if cnt.max() > 1 else None
        cases.append(
            _Case(
                mass=m, position=p, x=xb, h=hb, w=np.sqrt(cnt), force=force, f_boot=f_boot,
                f_total=-float(np.sum(f_boot[0::2])),
                m_total=-float(np.sum(f_boot[0::2] * nodes + f_boot[1::2])),
                hermite=_hermite_matrix(nodes, xb) if average is None
                else (average @ _hermite_matrix(nodes, xs)).tocsr(),
                stations=None if average is None else xs, average=average,
            )
        )  # fmt: skip
    return cases, scatter, n_samples, scatter_dof
