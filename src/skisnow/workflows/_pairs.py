"""Matching skis into pairs: the pairing of a fleet that minimises a stated distance.

The distance between two skis i and j is the root sum of squares of three dimensionless terms,
each a difference divided by a stated practitioner tolerance:

* camber: rms over the common running surface of the free-camber difference z0_i − z0_j,
  divided by :data:`CAMBER_TOLERANCE` (0.1 mm, the thickness of the paper test that marks the
  wax pocket);
* stiffness: rms of ln EI_i − ln EI_j (relative stiffness difference), divided by
  :data:`STIFFNESS_TOLERANCE` (5 %);
* contact: ½∫|q_i − q_j| dx / W, the fraction of the athlete's load carried at different
  places along the ski (q the line load of the predicted contact at the athlete's body mass on
  the day's snow; 0 identical, 1 disjoint), divided by :data:`CONTACT_TOLERANCE` (0.1).

d_ij = sqrt(d_camber² + d_stiffness² + d_contact²) (one unit = "as different as the tolerance").

Skis identified from a bench (issue 25) carry which stations their bench determines and the
bands there: camber and stiffness are compared only where both skis are determined (beyond the
outermost contacts of a bench no load bends the ski, and its EI there is the prior's guess, not a
measurement), and a pair is *a tie within uncertainty* (``within_uncertainty``) when the
differences of z0 (modulo a line, a rigid rotation no bench or snow sees) and of log EI pass a
simultaneous 95 % test of "same ski" (:mod:`skisnow.workflows._same_ski`: the largest
difference in units of the combined band, hypot(sd_i, sd_j), against its 95 % quantile under
the skis' posteriors, the sup-t band; a ski without bands, a shipped definition, counts with a
zero band). A distance above the tolerances that is a tie within uncertainty says that the
benches cannot tell the skis apart, not that they differ. (Before, the rule asked for the
differences within the pointwise 95 % bands at 95 % of the stations: with calibrated bands the
expected share *is* 95 %, so a ski and its own identification failed it a third of the time.)
A pair is a *poor match* when its distance exceeds :data:`POOR_MATCH_DISTANCE` (1: together, the
two skis differ by more than one tolerance); the *worst* pair is the poor match of largest
distance — never a pair tied with the best one, and none at all when every pair is within the
tolerances.
The pairing is a minimum-weight perfect matching of the complete graph with these weights
(networkx ``min_weight_matching``, the blossom algorithm — not a hand-written search); with an
odd number of skis one is left as the spare (the matching that leaves it out is the best over
all choices of the spare).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from skisnow._errors import InputError, SkisnowError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.ski import Ski
from skisnow.workflows._fleet import DEFAULT_LOAD_POSITION
from skisnow.workflows._same_ski import SameSkiTest, same_ski_test
from skisnow.workflows._skis import FleetSki, resolve_fleet
from skisnow.workflows._solve import choose_route, loaded_profiles, solve_loaded, stations

__all__ = [
    "CAMBER_TOLERANCE",
    "CONTACT_TOLERANCE",
    "POOR_MATCH_DISTANCE",
    "STIFFNESS_TOLERANCE",
    "PairDistance",
    "Pairing",
    "match_pairs",
    "pair_distance",
    "same_ski",
]

CAMBER_TOLERANCE = 0.1e-3
STIFFNESS_TOLERANCE = 0.05
CONTACT_TOLERANCE = 0.1
#: Distance above which a pair is flagged as a poor match (one unit: as different as the
#: tolerances, in root sum of squares).
POOR_MATCH_DISTANCE = 1.0
_DX = 1e-3  # the common grid [m] on which curves and line loads are compared


@dataclass(frozen=True, kw_only=True)
class PairDistance:
    """Distance between two skis and its three terms (dimensionless; raw values in SI)."""

    camber: float
    stiffness: float
    contact: float
    camber_rms: float  # [m]
    stiffness_rms: float  # rms of ln EI difference
    load_moved: float  # fraction of the load carried at different places
    #: whether the camber and stiffness differences pass the simultaneous 95 % "same ski?" test
    #: (:mod:`skisnow.workflows._same_ski`; ``None``: neither ski carries bands)
    within_uncertainty: bool | None = None
    #: ``(start, end)`` [m] of the compared stations (both skis determined there)
    compared: tuple[float, float] | None = None
    #: the test itself (statistic, critical value, method; ``None``: no bands)
    uncertainty_test: SameSkiTest | None = None

    @property
    def total(self) -> float:
        """sqrt(camber² + stiffness² + contact²)."""
        return float(np.sqrt(self.camber**2 + self.stiffness**2 + self.contact**2))


@dataclass(frozen=True, kw_only=True)
class _Curves:
    x: np.ndarray  # common grid
    z0: np.ndarray
    log_ei: np.ndarray
    sd_z0: np.ndarray | None  # bands on the grid (None: a ski without bands)
    sd_log_ei: np.ndarray | None
    modes_z0: np.ndarray | None  # the posterior's modes on the grid, (k, grid) (None: none)
    modes_log_ei: np.ndarray | None
    determined: np.ndarray  # stations where both EI and z0 are determined by the data
    line_load_x: np.ndarray
    line_load: np.ndarray  # [N/m]
    load: float
    converged: bool  # the contact solve of the line load


def _curves(
    fs: FleetSki, *, body_mass: float, load_position: float, snow_modulus: float, n_points: int
) -> _Curves:
    ski = fs.ski
    x = stations(fs, n_points)
    m, p = np.array([body_mass]), np.array([load_position])
    route, _ = choose_route(fs, m, p, x)
    (h,) = loaded_profiles(fs, m, p, x, route=route)
    case = solve_loaded(
        fs,
        x,
        h,
        mass=body_mass,
        load_position=load_position,
        snow_modulus=snow_modulus,
        route=route,
    )
    return _Curves(
        **_shape(ski),
        line_load_x=x,
        line_load=case.solution.line_load,
        load=body_mass * STANDARD_GRAVITY,
        converged=bool(case.converged),
    )


def _shape(ski: Any) -> dict[str, Any]:
    """The camber and stiffness of ``ski`` on the common grid, its bands, modes and what its
    data determine (the fields of :class:`_Curves` that do not depend on the snow)."""
    grid = np.arange(np.ceil(ski.x_tail / _DX), np.floor(ski.x_tip / _DX) + 1) * _DX
    determined = np.ones(grid.size, dtype=bool)
    for what in ("stiffness", "camber"):
        span = ski.determined_span(what)
        if getattr(ski, f"{what}_determined") is not None:
            determined &= (
                np.zeros(grid.size, bool) if span is None else (grid >= span[0]) & (grid <= span[1])
            )
    has_bands = ski.stiffness_log_sd is not None and ski.camber_sd is not None
    modes = ski.has_posterior and has_bands
    return dict(
        x=grid,
        z0=ski.free_camber(grid),
        log_ei=np.log(ski.stiffness(grid)),
        sd_z0=np.interp(grid, ski.camber_x, ski.camber_sd) if has_bands else None,
        sd_log_ei=np.interp(grid, ski.stiffness_x, ski.stiffness_log_sd) if has_bands else None,
        modes_z0=_on_grid(ski.camber_x, ski.camber_modes, grid) if modes else None,
        modes_log_ei=_on_grid(ski.stiffness_x, ski.stiffness_modes, grid) if modes else None,
        determined=determined,
    )


def _on_grid(xs, modes, grid: np.ndarray) -> np.ndarray:
    """Posterior modes at the ski's stations, PCHIP onto ``grid`` (as the ski's own curves)."""
    from scipy.interpolate import PchipInterpolator

    return PchipInterpolator(np.asarray(xs), np.asarray(modes), axis=1)(grid)


def _compare_shapes(a: Any, b: Any):
    """``(stations, Δz0, Δ log EI, test)`` over the stations where both skis are determined
    (``test``: the "same ski?" test, ``None`` when neither ski carries bands)."""
    lo, hi = max(a.x[0], b.x[0]), min(a.x[-1], b.x[-1])
    if hi - lo < 0.5:
        raise InputError("two skis overlap over less than 0.5 m of running surface")
    ia = (a.x >= lo - 1e-9) & (a.x <= hi + 1e-9)
    ib = (b.x >= lo - 1e-9) & (b.x <= hi + 1e-9)
    n = min(ia.sum(), ib.sum())
    both = a.determined[ia][:n] & b.determined[ib][:n]
    if both.sum() < 0.5 / _DX:
        raise InputError(
            "two skis are both determined by their data over less than 0.5 m of running surface "
            "(stations beyond a bench's outermost contacts are not determined by it)"
        )
    xs = a.x[ia][:n][both]
    dz = (a.z0[ia][:n] - b.z0[ib][:n])[both]
    dk = (a.log_ei[ia][:n] - b.log_ei[ib][:n])[both]
    if a.sd_z0 is None and b.sd_z0 is None:
        return xs, dz, dk, None

    def on(v: np.ndarray | None, ic: np.ndarray) -> np.ndarray | None:
        return None if v is None else v[..., ic][..., :n][..., both]

    def band(sd: np.ndarray | None, ic: np.ndarray) -> np.ndarray:
        return np.zeros(int(both.sum())) if sd is None else on(sd, ic)

    def modes(what: str) -> np.ndarray | None:
        ms = [on(getattr(c, what), ic) for c, ic in ((a, ia), (b, ib))]
        with_sd = [c.sd_z0 is not None for c in (a, b)]
        if any(m is None and w for m, w in zip(ms, with_sd, strict=True)):
            return None  # a ski with bands but no modes: the Bonferroni bound
        return np.vstack([m for m in ms if m is not None])

    test = same_ski_test(
        x=xs, dz=dz, dk=dk,
        sd_z=np.hypot(band(a.sd_z0, ia), band(b.sd_z0, ib)),
        sd_k=np.hypot(band(a.sd_log_ei, ia), band(b.sd_log_ei, ib)),
        modes_z=modes("modes_z0"), modes_k=modes("modes_log_ei"),
    )  # fmt: skip
    return xs, dz, dk, test


def same_ski(a: Ski, b: Ski) -> SameSkiTest | None:
    """The simultaneous "same ski?" test of two skis' camber and stiffness over the stations
    both are determined by their data (:mod:`skisnow.workflows._same_ski`); ``None`` when
    neither carries bands. No contact is solved (the test is the one of
    :func:`pair_distance`)."""
    from types import SimpleNamespace

    return _compare_shapes(SimpleNamespace(**_shape(a)), SimpleNamespace(**_shape(b)))[3]


def _distance(a: _Curves, b: _Curves) -> PairDistance:
    xs, dz, dk, test = _compare_shapes(a, b)
    camber_rms = float(np.sqrt(np.mean(dz**2)))
    stiff_rms = float(np.sqrt(np.mean(dk**2)))
    # line loads on one grid spanning both skis (zero off a ski)
    grid = np.linspace(
        min(a.line_load_x[0], b.line_load_x[0]),
        max(a.line_load_x[-1], b.line_load_x[-1]),
        max(a.line_load_x.size, b.line_load_x.size) * 2,
    )
    qa = np.interp(grid, a.line_load_x, a.line_load, left=0.0, right=0.0)
    qb = np.interp(grid, b.line_load_x, b.line_load, left=0.0, right=0.0)
    w = 0.5 * (a.load + b.load)
    moved = float(0.5 * np.trapezoid(np.abs(qa - qb), grid) / w)
    return PairDistance(
        camber=camber_rms / CAMBER_TOLERANCE,
        stiffness=stiff_rms / STIFFNESS_TOLERANCE,
        contact=moved / CONTACT_TOLERANCE,
        camber_rms=camber_rms,
        stiffness_rms=stiff_rms,
        load_moved=moved,
        within_uncertainty=None if test is None else test.tie,
        compared=(float(xs[0]), float(xs[-1])),
        uncertainty_test=test,
    )


def pair_distance(
    a: str | FleetSki,
    b: str | FleetSki,
    *,
    body_mass: float,
    snow_modulus: float,
    load_position: float = DEFAULT_LOAD_POSITION,
    n_points: int = 4096,
) -> PairDistance:
    """The distance between two skis (see the module docstring for its definition)."""
    skis, failures = resolve_fleet([a, b])
    if failures:
        raise InputError("; ".join(f"{s}: {m}" for s, m in failures))
    ca, cb = (
        _curves(
            fs,
            body_mass=body_mass,
            load_position=load_position,
            snow_modulus=snow_modulus,
            n_points=n_points,
        )
        for fs in skis
    )
    return _distance(ca, cb)


@dataclass(frozen=True, kw_only=True)
class Pairing:
    """The best pairing of a fleet.

    Attributes
    ----------
    skis
        Labels of the skis that entered the matching.
    pairs
        ``(ski_a, ski_b, PairDistance)``, best-matched first.
    spare
        The unpaired ski of an odd fleet (``None`` if even).
    distances
        The full symmetric matrix of total distances (skis × skis).
    failures
        ``(spec, message)`` of skis that could not be read or solved.
    warnings
        ``(ski, message)``: what the identification of a bench file said about its ski (issue
        25: a fit above the noise and its cause, stretches its bench does not determine).
    converged
        Whether every contact solve behind the contact terms converged.
    """

    skis: tuple[str, ...]
    pairs: tuple[tuple[str, str, PairDistance], ...]
    spare: str | None
    distances: np.ndarray
    failures: tuple[tuple[str, str], ...]
    warnings: tuple[tuple[str, str], ...] = ()
    converged: bool = True

    @property
    def worst(self) -> tuple[str, str, PairDistance] | None:
        """The worst-matched pair: the poor match (distance above :data:`POOR_MATCH_DISTANCE`)
        of largest distance, strictly larger than the smallest pair distance; ``None`` when no
        pair is a poor match or all pairs tie."""
        if not self.pairs:
            return None
        last, first = self.pairs[-1], self.pairs[0]
        if last[2].total > POOR_MATCH_DISTANCE and last[2].total > first[2].total:
            return last
        return None

    def poor(self, pair: tuple[str, str, PairDistance]) -> bool:
        """Whether ``pair`` is a poor match (distance above :data:`POOR_MATCH_DISTANCE`)."""
        return pair[2].total > POOR_MATCH_DISTANCE

    def messages(self) -> list[str]:
        """The warnings of the pairing: what the identification of each bench file said, and
        every poor match that is a tie within uncertainty (the benches cannot tell the two
        skis apart: the distance is not a difference)."""
        out = [f"{s}: {w}" for s, w in self.warnings]
        out += [
            f"{a} / {b}: distance {d.total:.3g} but a tie within uncertainty (the camber and "
            "stiffness differences lie within the skis' simultaneous 95 % band: the benches "
            "cannot tell them apart)"
            for a, b, d in self.pairs
            if d.within_uncertainty and self.poor((a, b, d))
        ]
        return out

    @property
    def total(self) -> float:
        """Sum of the pair distances (what the matching minimises)."""
        return float(sum(d.total for _, _, d in self.pairs))


def match_pairs(
    skis: Sequence[str | FleetSki],
    *,
    body_mass: float,
    snow_modulus: float,
    load_position: float = DEFAULT_LOAD_POSITION,
    n_points: int = 4096,
    progress: Callable[[int, int], None] | None = None,
) -> Pairing:
    """Pair the skis of a fleet so that the sum of the pair distances is minimal.

    Parameters
    ----------
    skis
        At least two skis (shipped names, ski files, bench files).
    body_mass, snow_modulus, load_position
        The athlete [kg], the snow [Pa] and the load position [m] of the contact term.

    Returns
    -------
    Pairing
        Pairs best first, the worst last (flag it), the spare of an odd fleet.
    """
    import networkx as nx

    if not (np.isfinite(body_mass) and 20.0 <= body_mass <= 150.0):
        raise InputError(f"body mass must be within 20..150 kg, got {body_mass:g} kg")
    resolved, failures = resolve_fleet(list(skis))
    curves, ok = [], []
    for done, fs in enumerate(resolved, start=1):
        try:
            curves.append(
                # the call of pair_distance, repeated on purpose: the curves are defined once
                _curves(
                    fs,
                    body_mass=body_mass,
                    load_position=load_position,
                    snow_modulus=snow_modulus,
                    n_points=n_points,
                )
            )
            ok.append(fs)
        except SkisnowError as exc:
            failures.append((fs.label, str(exc)))
        if progress is not None:
            progress(done, len(resolved))
    if len(ok) < 2:
        raise InputError(
            "pairing needs at least two readable skis"
            + ("; " + "; ".join(f"{s}: {m}" for s, m in failures) if failures else "")
        )
    n = len(ok)
    dist: dict[tuple[int, int], PairDistance] = {}
    matrix = np.zeros((n, n))
    for i, j in itertools.combinations(range(n), 2):
        d = _distance(curves[i], curves[j])
        dist[i, j] = d
        matrix[i, j] = matrix[j, i] = d.total
    if n % 2 == 0:
        graph = nx.Graph()
        graph.add_weighted_edges_from((i, j, d.total) for (i, j), d in dist.items())
        matching = nx.min_weight_matching(graph)
        spare = None
    else:
        # the best matching over every choice of the spare ski
        best = None
        for s in range(n):
            graph = nx.Graph()
            graph.add_weighted_edges_from(
                (i, j, d.total) for (i, j), d in dist.items() if s not in (i, j)
            )
            m = nx.min_weight_matching(graph) if graph.number_of_edges() else set()
            cost = sum(dist[min(e), max(e)].total for e in m)
            if best is None or cost < best[0]:
                best = (cost, m, s)
        assert best is not None
        _, matching, s = best
        spare = ok[s].label
    pairs = sorted(
        ((ok[min(e)].label, ok[max(e)].label, dist[min(e), max(e)]) for e in matching),
        key=lambda t: t[2].total,
    )
    return Pairing(
        skis=tuple(fs.label for fs in ok),
        pairs=tuple(pairs),
        spare=spare,
        distances=matrix,
        failures=tuple(failures),
        warnings=tuple((fs.label, w) for fs in ok for w in fs.warnings),
        converged=all(c.converged for c in curves),
    )
