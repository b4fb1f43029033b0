"""The grid of a sweep: which skis, masses, load positions and snow moduli, and how each point is
solved. Pure data; no Dask, no I/O.

A sweep is cut into *chunks* of one ski × one load position × one snow modulus × **all** masses:
coarse enough that a Dask task is worth its overhead (126 contact solves for the paper's Figure 8/9
grid), and ordered along the load path so that each solve is warm-started from the pressure of the
previous, slightly lighter, mass.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np

from skisnow._errors import FileFormatError, InputError
from skisnow._values import parse_values, sorted_unique  # noqa: F401  (parse_values re-exported)
from skisnow.materials import BASE

#: Contact models the sweep can ask the contact solver for.
MODELS: tuple[str, ...] = ("strip", "surface")
#: Where the loaded camber profile comes from (``skisnow.network.camber_profile(source=...)``).
PROFILE_SOURCES: tuple[str, ...] = ("network", "beam")
#: The zones reported for every contact solution (``skisnow.contact.contact_zones``).
ZONES: tuple[str, ...] = (
    "rear",
    "middle",
    "front",
    "total",
    "rear_glide",
    "kick_zone",
    "front_glide",
)

#: Ski base modulus E_base and Poisson ratio ν of Kalliorinne et al. 2023, §3.2 (used in eq. 2):
#: the default base material :data:`skisnow.materials.BASE`.
PAPER_BASE_MODULUS: float = BASE.modulus
PAPER_POISSON: float = BASE.poisson


def _as_sorted_unique(values: Any, name: str, unit: str, *, positive: bool) -> tuple[float, ...]:
    return tuple(float(v) for v in sorted_unique(values, name=name, unit=unit, positive=positive))


@dataclass(frozen=True, kw_only=True)
class SweepSpec:
    """What a sweep computes, in SI units.

    Attributes:
        skis: ski labels: shipped ski names (``skisnow.ski.SHIPPED_SKIS``) or paths of ski
            files (the label stays the path as given).
        ski_files: ``(label, ski-file JSON text)`` of every ski that is not a shipped one,
            filled in from the files when the spec is made: the workers get the definition,
            not a path they may not see, and a resumed sweep whose ski file changed is refused
            (the spec differs).
        masses: loads as masses [kg]; sorted ascending (the warm-start path).
        load_positions: load positions x_m [m] from the balance point, positive toward the tip.
        snow_moduli: elastic moduli of the snow E_counter [Pa].
        model: contact model of the solver, ``'strip'`` or ``'surface'``.
        profile_source: ``'beam'`` (default: the virtual ski, the truth of a ski defined by
            EI(x) and z0(x); :data:`skisnow.pipeline.DEFAULT_PROFILE_SOURCE`) or
            ``'network'`` (the shipped camber network, an emulator of the beam).
        n_points: grid points along the ski for the profile and the contact solve.
        base_modulus: E_base of the ski base [Pa]; with ``poisson`` it gives E' (eq. 2).
        poisson: Poisson ratio ν of both bodies (eq. 2).
        tol: tolerance of the contact solver (relative pressure change between iterations);
            1e-8 resolves areas and pressures far below what a map can show.
        warm_start: start each contact solve from the pressure of the previous (lighter) mass
            of the chunk; ``False`` solves every point cold (for benchmarking the warm starts).
        ski_model: ``'rigid'`` (the paper's method: the loaded profile pressed into the snow)
            or ``'flexible'`` (the ski's beam bends on the snow; no profile, no network).
        field_stations: ``0`` (default) stores the zone metrics only; ``n > 0`` also stores the
            fields along the ski on ``n`` display stations (block means of the ``n_points``
            cells, ``n`` dividing ``n_points``): pressure, ski base, snow surface, zone of each
            station (what the explorer page shows, :mod:`skisnow.explore`).
        base: ``""`` (default: no real contact) or a base texture (``'S1'``..``'S5'``,
            ``'smooth'``, a topography file): the sweep then also stores the real contact per
            zone and point (:data:`skisnow.sweep.REAL_VARIABLES`), from the micro curves of
            this base × ``snow`` (computed once, in the client, and cached).
        snow: the snow of the real contact as a snow-file JSON text (``skisnow.snow.
            snow_record``); its modulus is replaced by each of ``snow_moduli``.
        friction: overrides of the friction parameters, ``(name, SI value)`` pairs of
            :class:`skisnow.multiscale.FrictionParameters` (``()``: the cited defaults).
    """

    skis: tuple[str, ...]
    masses: tuple[float, ...]
    load_positions: tuple[float, ...]
    snow_moduli: tuple[float, ...]
    model: str = "strip"
    profile_source: str = "beam"
    n_points: int = 4096
    base_modulus: float = PAPER_BASE_MODULUS
    poisson: float = PAPER_POISSON
    tol: float = 1e-8
    warm_start: bool = True
    zones: tuple[str, ...] = field(default=ZONES)
    ski_files: tuple[tuple[str, str], ...] = ()
    ski_model: str = "rigid"
    field_stations: int = 0
    base: str = ""
    snow: str = ""
    friction: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        from skisnow.ski import SHIPPED_SKIS, get_ski, ski_to_json

        skis = (self.skis,) if isinstance(self.skis, str) else tuple(self.skis)
        if not skis or len(set(skis)) != len(skis) or not all(isinstance(s, str) for s in skis):
            raise InputError(f"skis: need distinct ski names, got {skis!r}")
        object.__setattr__(self, "skis", skis)
        files = {str(k): str(v) for k, v in self.ski_files}
        for label in skis:
            if label not in SHIPPED_SKIS and label not in files:
                files[label] = ski_to_json(get_ski(label))  # reads and validates the file
        unused = sorted(set(files) - set(skis))
        if unused:
            raise InputError(f"ski_files: {unused[0]!r} is not one of the skis {skis!r}")
        object.__setattr__(self, "ski_files", tuple((k, files[k]) for k in skis if k in files))
        from skisnow.pipeline import shipped_twin

        foreign = [
            k for k, _ in self.ski_files
            if self.profile_source == "network" and shipped_twin(self.ski(k)) is None
        ]  # fmt: skip
        if foreign:
            raise InputError(
                f"ski {foreign[0]!r} is a ski file: the camber network exists only for "
                f"the shipped skis ({', '.join(SHIPPED_SKIS)}); use profile_source 'beam'"
            )
        object.__setattr__(
            self, "masses", _as_sorted_unique(self.masses, "masses", "kg", positive=True)
        )
        object.__setattr__(
            self,
            "load_positions",
            _as_sorted_unique(self.load_positions, "load_positions", "m", positive=False),
        )
        object.__setattr__(
            self,
            "snow_moduli",
            _as_sorted_unique(self.snow_moduli, "snow_moduli", "Pa", positive=True),
        )
        if self.model not in MODELS:
            raise InputError(f"model: {self.model!r} is not one of {MODELS}")
        if self.profile_source not in PROFILE_SOURCES:
            raise InputError(
                f"profile_source: {self.profile_source!r} is not one of {PROFILE_SOURCES}"
            )
        if int(self.n_points) != self.n_points or self.n_points < 16:
            raise InputError(f"n_points: need an integer >= 16, got {self.n_points!r}")
        object.__setattr__(self, "n_points", int(self.n_points))
        if not (self.base_modulus > 0 and math.isfinite(self.base_modulus)):
            raise InputError(f"base_modulus: need a finite value > 0 Pa, got {self.base_modulus}")
        if not (-1.0 < self.poisson < 0.5):
            raise InputError(f"poisson: need -1 < ν < 0.5, got {self.poisson}")
        if not (0 < self.tol < 1):
            raise InputError(f"tol: need 0 < tol < 1, got {self.tol}")
        object.__setattr__(self, "zones", tuple(self.zones))
        if self.ski_model not in ("rigid", "flexible"):
            raise InputError(f"ski_model: {self.ski_model!r} is not one of ('rigid', 'flexible')")
        n = self.field_stations
        if int(n) != n or n < 0 or (n and (n < 16 or self.n_points % int(n))):
            raise InputError(
                f"field_stations: need 0 or an integer >= 16 that divides n_points = "
                f"{self.n_points}, got {n!r}"
            )
        object.__setattr__(self, "field_stations", int(n))
        if self.base and not self.snow:
            raise InputError("base: the real contact needs a snow (a snow-file JSON text)")
        object.__setattr__(self, "friction", tuple((str(k), float(v)) for k, v in self.friction))
        if self.base:
            self.friction_parameters()  # validated now, not on the workers
            self.snow_definition()

    def snow_definition(self) -> Any:  # a skisnow.snow.Snow
        """The :class:`~skisnow.snow.Snow` of the real contact (``None`` without ``snow``)."""
        return _snow_from_text(self.snow) if self.snow else None

    def texture(self) -> Any:  # a skisnow.multiscale.Base
        """The base texture of the real contact (``None`` without ``base``)."""
        if not self.base:
            return None
        from skisnow.multiscale import make_base

        return make_base(self.base)

    def friction_parameters(self) -> Any:
        """:class:`~skisnow.multiscale.FrictionParameters` with the spec's overrides."""
        from skisnow.multiscale import FrictionParameters

        try:
            return FrictionParameters(**dict(self.friction))
        except TypeError as exc:
            raise InputError(f"friction: {exc}") from None

    def micro_curves(self) -> Any:
        """The micro curves of ``base`` × ``snow`` (computed once and cached on disk)."""
        from skisnow.multiscale import micro_curves

        return micro_curves(self.texture(), self.snow_definition())

    # ----------------------------------------------------------------------------------------
    def ski(self, label: str) -> Any:  # a skisnow.ski.Ski (imported lazily)
        """The :class:`~skisnow.ski.Ski` of ``label``: its definition carried by the spec, or
        the shipped ski of that name."""
        from skisnow.ski import get_ski

        for key, text in self.ski_files:
            if key == label:
                return _ski_from_text(text, key)
        return get_ski(label)

    @property
    def shape(self) -> tuple[int, int, int, int, int]:
        """Dataset shape (ski, mass, load position, snow modulus, zone)."""
        return (
            len(self.skis),
            len(self.masses),
            len(self.load_positions),
            len(self.snow_moduli),
            len(self.zones),
        )

    def chunks(self) -> list[tuple[int, int, int]]:
        """All chunk keys ``(ski_index, load_position_index, snow_modulus_index)``."""
        return [
            (i, j, k)
            for i in range(len(self.skis))
            for j in range(len(self.load_positions))
            for k in range(len(self.snow_moduli))
        ]

    @property
    def n_points_total(self) -> int:
        """Number of contact solves of the sweep."""
        n_s, n_m, n_p, n_e, _ = self.shape
        return n_s * n_m * n_p * n_e

    def to_json(self) -> str:
        """Canonical JSON (sorted keys): stored in the Zarr attributes and compared on resume."""
        return json.dumps(asdict(self), sort_keys=True)

    @classmethod
    def from_json(cls, text: str, *, where: str = "sweep spec") -> SweepSpec:
        """Inverse of :meth:`to_json`; a spec read from a store (``where``) is a door like any
        file: depth-limited JSON, every field validated, the grid checked for plausibility."""
        from skisnow._checks import check_option_values
        from skisnow._json import load_json

        d = load_json(text, where=where)
        try:
            for key in ("skis", "masses", "load_positions", "snow_moduli", "zones"):
                d[key] = tuple(d[key])
            d["ski_files"] = tuple(tuple(pair) for pair in d.get("ski_files", ()))
            d["friction"] = tuple(tuple(pair) for pair in d.get("friction", ()))
            spec = cls(**d)
        except (TypeError, KeyError, AttributeError) as exc:
            raise FileFormatError(f"{where}: not a sweep spec ({exc})") from None
        except InputError as exc:
            raise FileFormatError(f"{where}: {exc}") from None
        for name, values, quantity, to_field in (
            ("masses", spec.masses, "mass", 1.0),
            ("load_positions", spec.load_positions, "load_position", 1e3),
            ("snow_moduli", spec.snow_moduli, "snow_modulus", 1e-6),
        ):
            check_option_values(np.asarray(values) * to_field, quantity, f"{where}: {name}")
        return spec


@lru_cache(maxsize=8)
def _snow_from_text(text: str) -> Any:
    import json as _json

    from skisnow.snow import snow_from_record

    try:
        return snow_from_record(_json.loads(text), where="(sweep snow)")
    except ValueError as exc:
        raise InputError(f"snow: {exc}") from None


@lru_cache(maxsize=32)
def _ski_from_text(text: str, label: str) -> Any:
    from skisnow.ski import ski_from_json

    return ski_from_json(text, where=f"(sweep ski {label!r})")
