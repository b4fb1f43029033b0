"""Skis × bases on one snow, ranked by a friction proxy of the real contact.

The apparent contact does not depend on the texture (every :class:`~skisnow.multiscale.Base`
of a comparison has the same macro base material), so each ski is solved once per load and the
micro curves of every base × snow are evaluated on its pressure
(:func:`skisnow.multiscale.real_contact`). The ranking follows the fleet's rule
(:func:`~skisnow.workflows.competition_ranks`: 1 + the entries strictly better, ties share a
rank); the proxies are deterministic, so entries tie only when equal, until uncertainty
intervals (issue 25) are plugged into the same rule.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from skisnow._errors import InputError

__all__ = ["PROXIES", "Proxy", "rank_real", "real_table"]


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


def rank_real(records: Sequence[dict[str, Any]], proxy: str) -> list[dict[str, Any]]:
    """The records from best to worst by ``proxy`` (a key of :data:`PROXIES`; NaN last), with
    competition ranks (ties share a rank) and the entries each ties with."""
    from skisnow.workflows._ties import competition_ranks, tied_with

    if proxy not in PROXIES:
        raise InputError(f"unknown proxy {proxy!r}; choose one of {', '.join(PROXIES)}")
    p = PROXIES[proxy]
    v = np.array([float(r[p.column]) for r in records])
    ranks = competition_ranks(v, better=p.better)
    ties = tied_with(v, better=p.better)
    key = np.where(np.isnan(v), np.inf, v if p.better == "lower" else -v)
    order = np.argsort(key, kind="stable")
    label = [f"{r['ski']} × {r['base']}" for r in records]
    return [
        {"rank": int(ranks[i]), "ski": records[i]["ski"], "base": records[i]["base"],
         p.column: v[i], "ties_with": [label[j] for j in ties[i]]}
        for i in order
    ]  # fmt: skip
