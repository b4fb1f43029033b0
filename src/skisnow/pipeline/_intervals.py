"""Intervals on a case's answers from the posterior of an identified ski (issue 25, item 4).

An identified ski carries the square root of its Laplace posterior (log EI and z0 at its
stations, :func:`skisnow.identify.identify_ski`); :func:`skisnow.ski.sample_skis` draws skis
from it with the correlations along the ski kept. Any answer of the one-case chain (Kalliorinne
et al. 2023: loaded profile, eq. 1, elastic half-space with force and moment balance, eq. 2–3,
zones) computed on each sample spreads as the ski's uncertainty makes it spread: the interval at
``level`` is the pair of sample quantiles (1 − level)/2 and (1 + level)/2 (Monte Carlo
propagation; Gelman et al. 2013, *Bayesian Data Analysis*, §1.9 and §10.5), extended to the
point estimate (the answer of the identified ski itself) when a skewed, non-linear answer puts
the estimate outside them — so an interval always contains its estimate, and a ski with
zero-width bands gives zero-width intervals.

How many samples: the Monte Carlo standard error of each end is estimated by bootstrapping the
samples (Efron & Tibshirani 1993, §6) and carried with the intervals
(:attr:`Intervals.mc_error`, as a fraction of the interval's width); at 200 samples the ends
move by about 7.5 % (worst 10 %) of the width from seed to seed on an identified classic
(``benchmarks/bench_interval_samples.py`` measures it against the sample count; the bootstrap
estimate reads about a third lower), small beside the width itself. A sample whose case
cannot be solved (the load unsupported, :class:`~skisnow.UnsupportedLoadError`) is counted in
:attr:`Intervals.failed`, not silently dropped.

The quantities of a case (:func:`case_quantities`): per zone (rear, middle, front, total,
kick) its length [m], area [m²], mean and peak pressure [Pa] and load share, SI, keys
``"<zone>.<quantity>"``. A pressure is undefined (NaN) where a zone has no contact; its interval
is taken over the samples where the zone has contact.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from skisnow._errors import InputError, UnsupportedLoadError

if TYPE_CHECKING:
    from skisnow.pipeline._case import Case
    from skisnow.ski import Ski

__all__ = [
    "DEFAULT_LEVEL",
    "DEFAULT_SAMPLES",
    "INTERVAL_ZONES",
    "MIXED_SHARE",
    "PATCH_ZONES",
    "ZONE_QUANTITIES",
    "Intervals",
    "Topology",
    "case_intervals",
    "case_quantities",
    "sample_intervals",
    "topology_shares",
    "topology_text",
    "zone_topology",
]

#: Posterior samples per answer by default (Monte Carlo error of the ends ~7.5 % of the width).
DEFAULT_SAMPLES: int = 200
#: The intervals' probability.
DEFAULT_LEVEL: float = 0.95
#: Zones whose answers carry intervals (``kick``: between the kick-zone marks).
INTERVAL_ZONES: tuple[str, ...] = ("rear", "middle", "front", "total", "kick")
#: Per zone: the attribute of :class:`skisnow.contact.Zone` (SI units).
ZONE_QUANTITIES: tuple[str, ...] = ("length", "area", "mean_pressure", "max_pressure", "load_share")
_BOOTSTRAP = 200
#: The paper's zones made of whole patches (whose answers can jump with the patch topology).
PATCH_ZONES: tuple[str, ...] = ("rear", "middle", "front")
#: Share of posterior samples in another topology above which an answer is said to straddle
#: two topologies (the tail an interval at 95 % leaves out on each side).
MIXED_SHARE: float = 0.025
#: The patch topology of a contact: patches per paper zone, and whether the footprint is merged
#: (the zones are then the regions), ``(("rear", 1), ("middle", 0), ("front", 1), ("merged",
#: 0))``.
Topology = tuple[tuple[str, int], ...]


@dataclass(frozen=True, kw_only=True)
class Intervals:
    """Intervals of named answers from posterior samples (SI units, as the answers).

    Attributes
    ----------
    estimate
        The answer of the identified ski itself, per name.
    low, high
        The ends of each interval (``low <= estimate <= high``).
    samples, seed, level
        Posterior samples drawn, their seed, the intervals' probability.
    failed
        Samples whose answer could not be computed (e.g. the load not supported).
    unconverged
        Samples whose contact solve did not reach its tolerance (their answers are kept).
    mc_error
        Per name: the bootstrap Monte Carlo standard error of the interval's ends (the larger
        of the two), as a fraction of the interval's width (0 for a zero-width interval,
        round-off included).
    topology, sample_topologies
        The patch topology of the estimate's contact and of each solved sample's
        (:func:`zone_topology`; empty when the answers are not a case's zones).
    """

    estimate: Mapping[str, float]
    low: Mapping[str, float]
    high: Mapping[str, float]
    samples: int
    seed: int
    level: float
    failed: int = 0
    unconverged: int = 0
    mc_error: Mapping[str, float] = field(default_factory=dict)
    topology: Topology | None = None
    sample_topologies: tuple[Topology, ...] = ()

    def topology_shares(self, zones: Sequence[str] = PATCH_ZONES) -> dict[str, float]:
        """The share of the solved samples in each patch topology of ``zones`` (text of
        :func:`topology_text` → share), the estimate's first."""
        return topology_shares(self.sample_topologies, self.topology, zones)

    def topology_note(self, zones: Sequence[str] = PATCH_ZONES) -> str | None:
        """A warning when more than :data:`MIXED_SHARE` of the samples have another patch
        topology of ``zones`` than the estimate: their answers jump between topologies (a
        glide patch joined to the kick contact or split from it), so their intervals join
        two different definitions; the regions' answers do not jump. ``None`` otherwise."""
        shares = self.topology_shares(zones)
        if not shares or 1.0 - next(iter(shares.values())) <= MIXED_SHARE:
            return None
        parts = ", ".join(f"{100 * v:.1f} % '{k}'" for k, v in shares.items())
        return (
            f"the posterior samples differ in patch topology ({parts}; the first is the "
            f"estimate's): the {'/'.join(zones)} zones' answers jump between a glide patch "
            "joined to the kick contact and split from it, so their intervals span two "
            "definitions; the regions (rear_glide, kick_zone, front_glide) do not jump: "
            "compare by their shares (rear_glide.load_share, ...)"
        )

    def interval(self, name: str) -> tuple[float, float]:
        """``(low, high)`` of ``name``."""
        return self.low[name], self.high[name]

    def worst_mc_error(self) -> float:
        """The largest Monte Carlo error of an end over all answers (fraction of the width)."""
        vals = [v for v in self.mc_error.values() if np.isfinite(v)]
        return float(max(vals)) if vals else 0.0


def zone_topology(zones: Any) -> Topology:
    """The patch topology of a contact's zones (:class:`skisnow.contact.ZoneMetrics`): the
    number of patches of the rear, middle and front zones and whether they are merged.

    Under the paper's rule (:func:`skisnow.contact.paper_zones`) a glide patch reaching into the
    kick zone stays whole in its glide zone; once the kick contact separates from it, the kick
    part becomes a ``middle`` patch, and once a patch runs from glide zone to glide zone the
    zones become the regions (``merged``): the zones' answers jump between these topologies,
    the regions' do not."""
    return (*((z, int(zones[z].patches)) for z in PATCH_ZONES), ("merged", int(zones.merged)))


def topology_text(top: Topology, zones: Sequence[str] = PATCH_ZONES) -> str:
    """``'rear 1 patch, middle 0 patches'`` for the ``zones`` of ``top`` (``', merged into the
    regions'`` when merged)."""
    d = dict(top)
    text = ", ".join(f"{z} {d[z]} patch{'' if d[z] == 1 else 'es'}" for z in zones)
    return text + (", merged into the regions" if d["merged"] else "")


def topology_shares(
    samples: Sequence[Topology], estimate: Topology | None, zones: Sequence[str] = PATCH_ZONES
) -> dict[str, float]:
    """Share of ``samples`` per topology text of ``zones``, the estimate's first (also when no
    sample has it); empty without samples."""
    if not samples:
        return {}
    texts = [topology_text(t, zones) for t in samples]
    out: dict[str, float] = {}
    if estimate is not None:
        out[topology_text(estimate, zones)] = 0.0
    for t in texts:
        out[t] = out.get(t, 0.0) + 1.0 / len(texts)
    return out


def case_quantities(case: Case) -> dict[str, float]:
    """The answers of a case that carry intervals: ``"<zone>.<quantity>"`` → value (SI)."""
    z = case.zones
    return {
        f"{zone}.{q}": float(getattr(z[zone], q))
        for zone in INTERVAL_ZONES
        for q in ZONE_QUANTITIES
    }


def _quantiles(values: np.ndarray, level: float) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper sample quantiles over axis -1 (NaN ignored; all NaN → NaN)."""
    a = (1.0 - level) / 2.0
    with np.errstate(all="ignore"), _quiet():
        return _nanquantile(values, a), _nanquantile(values, 1.0 - a)


def _nanquantile(values: np.ndarray, q: float) -> np.ndarray:
    """``np.nanquantile(values, q, axis=-1)``, bitwise, at the cost of ``np.quantile``.

    NumPy's ``nanquantile`` of a 2- or 3-D array calls a 1-D quantile per row in Python
    (``apply_along_axis``: ~2,500 calls for a bootstrap of the answers, ~0.25 s a case); the rows
    without NaN take ``np.quantile`` over the axis at once (the same partition and linear
    interpolation per row: equal to the bit, checked in ``tests/pipeline/test_intervals.py``),
    the rows with a NaN keep ``nanquantile``."""
    values = np.asarray(values, dtype=float)
    has_nan = np.isnan(values).any(axis=-1)
    out = np.empty(values.shape[:-1])
    if not has_nan.all():
        out[~has_nan] = np.quantile(values[~has_nan], q, axis=-1)
    if has_nan.any():
        out[has_nan] = np.nanquantile(values[has_nan], q, axis=-1)
    return out


class _quiet:
    """Silence NumPy's "All-NaN slice" warning (an answer undefined in every sample)."""

    def __enter__(self) -> None:
        import warnings

        self._cm = warnings.catch_warnings()
        self._cm.__enter__()
        warnings.simplefilter("ignore", RuntimeWarning)

    def __exit__(self, *exc: object) -> None:
        self._cm.__exit__(*exc)


def sample_intervals(
    ski: Ski,
    answers: Callable[[Ski], Mapping[str, float]],
    *,
    estimate: Mapping[str, float],
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    level: float = DEFAULT_LEVEL,
) -> Intervals:
    """Intervals of ``answers(ski)`` over ``samples`` skis drawn from the posterior of ``ski``.

    Monte Carlo propagation of the ski's Laplace posterior (module docstring): ``answers`` is
    called on each sample (:func:`skisnow.ski.sample_skis`, seeded) and must return the same
    names as ``estimate`` (the answers of ``ski`` itself). A sample raising
    :class:`~skisnow.UnsupportedLoadError` is counted as failed.

    Raises
    ------
    InputError
        ``ski`` carries no posterior, ``samples`` < 2, or ``level`` not in (0, 1).
    """
    from skisnow.ski import sample_skis

    if not (isinstance(samples, int) and samples >= 2):
        raise InputError(f"samples: need an integer >= 2 posterior samples, got {samples!r}")
    if not 0.0 < level < 1.0:
        raise InputError(f"level: need a probability in (0, 1), got {level!r}")
    names = list(estimate)
    rows, failed = [], 0
    for s in sample_skis(ski, samples, seed=seed):
        try:
            got = answers(s)
        except UnsupportedLoadError:
            failed += 1
            continue
        rows.append([float(got[n]) for n in names])
    if not rows:
        raise UnsupportedLoadError(
            f"no posterior sample of {ski.name!r} could carry the load ({samples} tried)"
        )
    values = np.asarray(rows, dtype=float).T  # (names, samples)
    lo, hi = _quantiles(values, level)
    point = np.array([float(estimate[n]) for n in names])
    lo = np.fmin(lo, point)  # the interval always holds its estimate (NaN-safe)
    hi = np.fmax(hi, point)
    # Monte Carlo error of the ends: bootstrap the samples (seeded, independent of the draws)
    rng = np.random.default_rng([seed, 1])
    idx = rng.integers(0, values.shape[1], size=(_BOOTSTRAP, values.shape[1]))
    blo, bhi = _quantiles(values[:, idx], level)  # (names, bootstrap)
    with np.errstate(all="ignore"), _quiet():
        se = np.fmax(np.nanstd(blo, axis=1), np.nanstd(bhi, axis=1))
        width = hi - lo
        wide = width > 1e-9 * np.abs(point)  # round-off widths count as zero
        frac = np.where(wide, se / np.where(wide, width, 1.0), 0.0)
    return Intervals(
        estimate=dict(zip(names, point.tolist(), strict=True)),
        low=dict(zip(names, lo.tolist(), strict=True)),
        high=dict(zip(names, hi.tolist(), strict=True)),
        samples=samples,
        seed=seed,
        level=level,
        failed=failed,
        mc_error=dict(zip(names, np.nan_to_num(frac, nan=0.0).tolist(), strict=True)),
    )


def case_intervals(
    case: Case,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    level: float = DEFAULT_LEVEL,
    **case_kwargs: Any,
) -> Intervals | None:
    """Intervals of a solved case's answers (:func:`case_quantities`) from its ski's posterior.

    Each posterior sample is solved through :func:`skisnow.pipeline.solve_case` with the same
    mass, load position, snow and ``case_kwargs`` (model, stations, base, ...; the beam route,
    since a sample is a new ski no network was trained on), warm-started from the case's
    pressure. Returns ``None`` when the case's ski carries no posterior (a shipped definition,
    a ski file without bands): there is no uncertainty recorded to propagate.
    """
    from skisnow.pipeline._case import solve_case

    ski = case.ski
    if ski is None or not ski.has_posterior:
        return None
    kw: dict[str, Any] = {
        "mass": case.mass,
        "load_position": case.load_position,
        "model": case.model,
        "n_points": case.n_points,
        "ski_model": case.ski_model,
        **case_kwargs,
    }
    if case.snow is not None:
        kw.setdefault("snow", case.snow)
    else:
        kw.setdefault("snow_modulus", case.snow_modulus)
    if case.ski_model == "rigid":
        kw["profile_source"] = "beam"
    warm = case.model == "strip" and case.ski_model == "rigid"
    start = np.asarray(case.solution.pressure) if warm else None
    unconverged = 0
    tops: list[Topology] = []

    def answers(s: Ski) -> dict[str, float]:
        nonlocal unconverged
        c = solve_case(s, start=start, **kw)
        unconverged += not c.converged
        tops.append(zone_topology(c.zones))
        return case_quantities(c)

    out = sample_intervals(
        ski, answers, estimate=case_quantities(case), samples=samples, seed=seed, level=level
    )
    return dataclasses.replace(out, unconverged=unconverged, topology=zone_topology(case.zones),
                               sample_topologies=tuple(tops))  # fmt: skip
