"""Report section of the ski passport: EI(x) and z0(x) with their bands, and where they came
from (the ski file's provenance). Renders :func:`skisnow.bench.ski_passport`; computes nothing."""

from __future__ import annotations

from skisnow.report._html import Figure, Section, Table
from skisnow.ski import Ski

__all__ = ["passport_section"]


def passport_section(ski: Ski, *, step: float = 0.1) -> Section:
    """EI(x) and z0(x) every ``step`` [m] with their 95 % bands (identified skis), the figure,
    and the provenance."""
    from skisnow.bench import ski_passport
    from skisnow.plot import plot_passport

    pp = ski_passport(ski, step=step, metrics=False)
    t = pp.table()
    if pp.has_bands:
        cols = ["x [mm]", "EI [N m²]", "EI 95 % band", "z0 [mm]", "z0 95 % band [mm]"]
        keys = ("x_mm", "ei_nm2", "ei_low_nm2", "ei_high_nm2", "z0_mm", "z0_low_mm", "z0_high_mm")
        rows = [
            (x, e, f"{lo:.4g} .. {hi:.4g}", z, f"{zl:.4g} .. {zh:.4g}")
            for x, e, lo, hi, z, zl, zh in zip(*(t[k] for k in keys), strict=True)
        ]
    else:
        cols = ["x [mm]", "EI [N m²]", "z0 [mm]"]
        rows = list(zip(t["x_mm"], t["ei_nm2"], t["z0_mm"], strict=True))
    prov = ski.provenance
    notes = (
        "The ski as an Euler–Bernoulli beam (Kalliorinne et al. 2023, §3.1): bending stiffness "
        "EI(x) and free camber z0(x), x from the balance point."
        + (" Bands: 95 % (Gauss–Newton, bench noise only)." if pp.has_bands else ""),
        f"How it was made: {prov.method or 'not stated'}. Data: {prov.data or 'not stated'}.",
    )
    figure = Figure.of(plot_passport(ski), f"Passport of the {ski.name} ski.")
    return Section("The ski's passport: EI(x) and z0(x)", notes,
                   (Table(cols, rows, floatfmt=".4g"), figure))  # fmt: skip
