"""A parametric bootstrap of an identification: bands for what the Laplace posterior misses.

Why (issue 25, fourth pass, measured in docs/validation/identification-uncertainty.md): the
cost of the fit is not quadratic along the directions that trade z0 against EI. Along the line
from a fit to the truth it rose to +390 and fell back to +117 (χ² units) where the Gauss–Newton
model predicted +3000; the linearised response of the fit to its own noise was 3 µm of z0 where
the fit missed the truth by 16 µm; changing the noise estimate by 3 % moved the same fit's z0
error from 16 to 8 µm. The fit lands in one of several basins, and which one depends on the
noise draw: a variance no linearisation at one fit can see (every Gaussian variant of the
bands tried - the undersmoothed posterior, separate prior scales by the evidence, the smoothing
bias of every penalty term - moved the z0 coverage by less than a point).

The parametric bootstrap (Efron & Tibshirani 1993, ch. 6) sees it: benches simulated from the
identified ski at the bench's own masses, load positions and stations (the fit's forward
model, :func:`~skisnow.ski.solve_beam` with contact between nodes, Gaussian noise of each load
case's estimated σ), each identified again from the default start, so each replicate takes its
own path into its own basin. Their scatter about the identified ski, (ẑ* - ẑ) modulo the line
the bench cannot see and log EI* - log ÊI, is added to the Laplace variance at every station
(the two are independent in origin: the posterior's width within a basin, the bootstrap's the
choice of basin). Its cost is ``replicates`` identifications (6-17 s CPU each on the shop plan).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["bootstrap_bands"]


def _simulated_bench(result: Any, bench: Any, label: str, seed: int) -> Any:
    """A bench of the identified ski at the stations of ``bench``'s profiles of ``label``,
    with Gaussian noise of each load case's σ (seeded).

    Not :func:`skisnow.bench.run_bench`: the virtual bench samples every profile on one regular
    grid with one noise level, while a replicate must keep the measured bench's own stations
    (irregular, different per case) and each case's estimated σ."""
    import pandas as pd

    from skisnow.bench import BenchData
    from skisnow.ski import solve_beam

    rng = np.random.default_rng(seed)
    t = bench.table[bench.table["ski"] == label]
    boot = float(bench.metadata.get("boot_length_mm", 100.0)) * 1e-3
    sigma = {(round(m, 9), round(p * 1e3, 6)): s for m, p, s, _ in result.noise_cases}
    parts = []
    for (m, p_mm), grp in t.groupby(["mass_kg", "load_position_mm"], sort=True):
        x = grp["x_mm"].to_numpy() * 1e-3
        sol = solve_beam(result.ski, mass=float(m), load_position=float(p_mm) * 1e-3,
                         boot_length=boot, contact="continuous", n_elements=800)  # fmt: skip
        s = sigma.get((round(float(m), 9), round(float(p_mm), 6)), result.noise)
        h = sol.sample(x) + rng.normal(0.0, s, x.size)
        parts.append(pd.DataFrame({"ski": label, "mass_kg": float(m), "load_position_mm": p_mm,
                                   "x_mm": x * 1e3, "height_mm": h * 1e3}))  # fmt: skip
    return BenchData(table=pd.concat(parts, ignore_index=True), metadata=dict(bench.metadata))


def _line_free(d: NDArray[np.float64], x: NDArray[np.float64], w: NDArray[np.float64]):
    """``d`` less its least-squares line (weights ``w``)."""
    a = np.stack([np.ones(x.size), x], axis=1)
    coef = np.linalg.lstsq(a * w[:, None], d * w, rcond=None)[0]
    return d - a @ coef


def bootstrap_bands(
    result: Any,
    bench: Any,
    *,
    replicates: int = 8,
    seed: int = 101,
    ski: str | None = None,
    stiffness: bool = False,
    **identify_options: Any,
) -> Any:
    """``result`` (an identification of ``bench``) with its z0 bands (and with ``stiffness``
    its EI bands) widened by a parametric bootstrap (module docstring).

    Parameters
    ----------
    result
        The :class:`~skisnow.identify.IdentificationResult` of ``bench``.
    bench
        The :class:`~skisnow.bench.BenchData` it was identified from.
    replicates
        Simulated benches identified again (each one identification's cost).
    seed
        Seed of the first replicate's noise (the others follow).
    ski
        Which ski of a multi-ski bench.
    stiffness
        Widen the EI bands as well (off: the Laplace bands with the smoothing bias already
        cover EI at 90-95 % of the determined stations).
    identify_options
        Passed to every replicate's :func:`~skisnow.identify.identify_ski`.

    Returns
    -------
    IdentificationResult
        The same result, its ski's ``camber_sd`` (and ``stiffness_log_sd``) at the determined
        stations sqrt(Laplace² + bootstrap²), ``bootstrap`` the number of replicates that
        ended and the median bootstrap standard deviations.
    """
    from skisnow._errors import InputError
    from skisnow.identify._identify import identify_ski

    if not (isinstance(replicates, int) and replicates >= 2):
        raise InputError(f"replicates must be an integer >= 2, got {replicates!r}")
    label = bench.ski_name(ski)
    s = result.ski
    cx, dz = np.asarray(s.camber_x), np.asarray(s.camber_determined, dtype=bool)
    ex, de = np.asarray(s.stiffness_x), np.asarray(s.stiffness_determined, dtype=bool)
    sd_z, sd_e = np.asarray(s.camber_sd, dtype=float), np.asarray(s.stiffness_log_sd, dtype=float)
    z_fit, log_e = np.asarray(s.camber_values), np.log(np.asarray(s.stiffness_values))
    w = 1.0 / np.maximum(sd_z[dz], 1e-7)
    dev_z, dev_e = [], []
    for b in range(replicates):
        rep_bench = _simulated_bench(result, bench, label, seed + b)
        try:
            rep = identify_ski(rep_bench, ski=label, **identify_options)
        except Exception:
            continue
        r = rep.ski
        zr = np.interp(cx, np.asarray(r.camber_x), np.asarray(r.camber_values))
        dev_z.append(_line_free(zr[dz] - z_fit[dz], cx[dz], w))
        er = np.interp(ex, np.asarray(r.stiffness_x), np.log(np.asarray(r.stiffness_values)))
        dev_e.append(er[de] - log_e[de])
    if len(dev_z) < 2:
        note = "bootstrap: fewer than two replicates ended; the bands are the Laplace ones"
        return dataclasses.replace(result, warnings=(*result.warnings, note))
    boot_z = np.sqrt(np.mean(np.square(dev_z), axis=0))
    boot_e = np.sqrt(np.mean(np.square(dev_e), axis=0))
    new_z = sd_z.copy()
    new_z[dz] = np.hypot(sd_z[dz], boot_z)
    new_e = sd_e.copy()
    if stiffness:
        new_e[de] = np.hypot(sd_e[de], boot_e)
    details = (*s.provenance.details, ("bootstrap_replicates", len(dev_z)))
    prov = dataclasses.replace(s.provenance, details=details)
    new_ski = dataclasses.replace(s, camber_sd=new_z, stiffness_log_sd=new_e, provenance=prov)
    summary = (len(dev_z), float(np.median(boot_z)) if boot_z.size else 0.0,
               float(np.median(boot_e)) if boot_e.size else 0.0)  # fmt: skip
    return dataclasses.replace(result, ski=new_ski, bootstrap=summary)
