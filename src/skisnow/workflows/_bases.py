"""Skis × bases on one snow, ranked by a friction proxy of the real contact.

The apparent contact does not depend on the texture (every :class:`~skisnow.multiscale.Base`
of a comparison has the same macro base material), so each ski is solved once per load and the
micro curves of every base × snow are evaluated on its pressure
(:func:`skisnow.multiscale.real_contact`). The ranking follows the fleet's rule
(:func:`~skisnow.workflows.competition_ranks`: 1 + the entries strictly better, ties share a
rank). The proxies rank glide, and a glide test on snow resolves differences between skis
only down to its precision: a custom skitester on real snow measured glide with a relative
variation of 0.6–1.1 % (Lemmettylä et al. 2021, "The Development and Precision of a Custom-Made
Skitester", Front. Mech. Eng. 7:661947). Each proxy value v therefore stands for the interval
v·(1 ± :data:`GLIDE_TEST_PRECISION`) (the worse end, 1.1 %), and two entries whose intervals
overlap — a relative difference below about 2.2 % — are *a tie within glide-test precision*:
a predicted difference no glide test could confirm.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from skisnow._errors import InputError

__all__ = [
    "GLIDE_TEST_PRECISION",
    "GLIDE_TEST_PRECISION_RANGE",
    "PROXIES",
    "Proxy",
    "rank_real",
    "real_table",
]

#: Relative variation of glide measured by a skitester on snow (Lemmettylä et al. 2021: 0.6–1.1 %
#: over three conditions).
GLIDE_TEST_PRECISION_RANGE: tuple[float, float] = (0.006, 0.011)
#: The precision the glide rankings use: the worse end of the range (a tie is not broken by a
#: difference that the less precise of the reported conditions could not resolve).
GLIDE_TEST_PRECISION: float = GLIDE_TEST_PRECISION_RANGE[1]


@dataclass(frozen=True)
class Proxy:
    """A friction proxy of the real contact: the record column and which way is better."""

    name: str
    column: str
    better: Literal["lower", "higher"]
    description: str


#: The proxies a ranking may use (all of the whole ski at the case's load).
PROXIES: dict[str, Proxy] = {
    p.name: p
    for p in (
        Proxy("mu", "mu", "lower", "µ = (τ·A_r + η·v·∫1/u dA)/W, dry real contact"),
        Proxy(
            "mu-lubricated",
            "mu_lubricated",
            "lower",
            "µ = (η·v·A_r/u_c + η·v·∫1/u dA)/W, contact spots sheared through the film",
        ),
        Proxy("viscous", "viscous_force_n", "lower", "η·v·∫1/u dA, the meltwater film's drag"),
        Proxy("dry", "dry_force_n", "lower", "τ·A_r, the dry/adhesive term"),
        Proxy(
            "real-area",
            "real_area_grains_mm2",
            "lower",
            "real contact area, bearing model of ice grains",
        ),
        Proxy("real-area-flat", "real_area_mm2", "lower", "real contact area, flat-ice model"),
        Proxy(
            "reciprocal",
            "reciprocal_separation_m",
            "lower",
            "total reciprocal separation ∫1/u dA (viscous drag per η·v)",
        ),
    )
}


def real_table(
    solutions: Mapping[str, Any],
    bases: Sequence[Any],
    snow: Any,
    *,
    friction: Any = None,
    cache_dir: Any = None,
) -> list[dict[str, Any]]:
    """One record per ski × base (field units): the real contact of the whole ski.

    ``solutions`` maps a ski label to its :class:`~skisnow.contact.ContactSolution` (the
    apparent contact at the load of interest); ``bases`` are what
    :func:`~skisnow.multiscale.make_base` accepts; ``snow`` a :class:`~skisnow.snow.Snow`.
    """
    from skisnow.multiscale import FrictionParameters, make_base, micro_curves, real_contact

    if not bases:
        raise InputError("no base to compare")
    f = friction if friction is not None else FrictionParameters()
    records = []
    for spec in bases:
        b = make_base(spec)
        curves = micro_curves(b, snow, cache_dir=cache_dir)
        resolved = f.resolve(temperature_c=snow.temperature_c, hardness=curves.hardness)
        for label, sol in solutions.items():
            r = real_contact(sol, curves, resolved)
            t = r.total
            est = r.friction_estimate()
            records.append(
                {
                    "ski": label,
                    "base": b.name,
                    **t.as_dict(),
                    "mu": est["mu"],
                    "mu_lubricated": est["mu_lubricated"],
                }
            )
            records[-1].pop("name")
    return records


def rank_real(
    records: Sequence[dict[str, Any]], proxy: str, *, precision: float = GLIDE_TEST_PRECISION
) -> list[dict[str, Any]]:
    """The records from best to worst by ``proxy`` (a key of :data:`PROXIES`; NaN last), with
    competition ranks (ties share a rank) and the entries each ties with: equal values, or
    values within the glide-test precision of each other (``precision``, relative; module
    docstring; ``within_glide_test_precision`` marks those ties; 0: only equal values tie)."""
    from skisnow.workflows._ties import competition_ranks, tied_with

    if proxy not in PROXIES:
        raise InputError(f"unknown proxy {proxy!r}; choose one of {', '.join(PROXIES)}")
    if not (np.isfinite(precision) and 0.0 <= precision < 1.0):
        raise InputError(f"glide-test precision must be a fraction in [0, 1), got {precision!r}")
    p = PROXIES[proxy]
    v = np.array([float(r[p.column]) for r in records])
    half = np.abs(v) * precision
    bounds = np.column_stack([v - half, v + half])
    ranks = competition_ranks(v, better=p.better, intervals=bounds)
    ties = tied_with(v, better=p.better, intervals=bounds)
    key = np.where(np.isnan(v), np.inf, v if p.better == "lower" else -v)
    order = np.argsort(key, kind="stable")
    label = [f"{r['ski']} × {r['base']}" for r in records]
    return [
        {"rank": int(ranks[i]), "ski": records[i]["ski"], "base": records[i]["base"],
         p.column: v[i], "ties_with": [label[j] for j in ties[i]],
         "within_glide_test_precision": any(v[j] != v[i] for j in ties[i])}
        for i in order
    ]  # fmt: skip
