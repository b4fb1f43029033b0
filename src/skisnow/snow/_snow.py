"""The snow as one object across scales (:class:`Snow`) and its published relations.

What each scale needs of the snow:

* macro/meso (Kalliorinne et al. 2023, eq. 2): the counter-surface modulus E_counter and its
  Poisson ratio — given, or estimated from the density (:func:`modulus_from_density`);
* micro (Scherge et al. 2021): the temperature, which sets the ice hardness H(T) (eq. 2 or 3,
  :func:`skisnow.micro.ice_hardness`), and the grain sizes — the distribution f(D) of eq. 12
  (:class:`skisnow.micro.GrainFit`) or measured diameters — over which the bearing model is
  averaged (eq. 13).

Density → modulus (dry snow), two published fits of E(ρ), ρ in kg/m³:

* ``'scapozza2004'`` (default): E = 0.1873·exp(0.0149·ρ) MPa, Scapozza (2004, PhD thesis ETH
  Zürich no. 15357, eq. 5-7): triaxial tests at strain rates 10⁻⁶–10⁻³ s⁻¹, −18.5 to −1.9 °C,
  ρ = 180–490 kg/m³ (r² = 0.93). Quasi-static, as the loaded ski. 450 kg/m³ → 153 MPa, in the
  50–350 MPa Lintzén & Edeskär (2015) measured on machine-made snow.
* ``'gerling2017'``: E = 6.0·10⁻¹⁰·ρ^4.6 MPa, Gerling et al. (2017, Geophys. Res. Lett. 44,
  eq. 6, acoustic), ρ ≈ 100–450 kg/m³: high-rate moduli, 3–10× the quasi-static ones.

Outside its density range a relation warns (:class:`~skisnow.DomainWarning`); wet snow has no
density relation here (both fits are for dry snow).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import special

from skisnow._errors import DomainWarning, InputError
from skisnow.materials import Material
from skisnow.micro import GrainFit, ice_hardness

__all__ = [
    "DENSITY_RELATIONS",
    "Snow",
    "gamma_grains",
    "modulus_from_density",
]

#: Density → modulus relations: name → (function of ρ [kg/m³] giving E [Pa], valid ρ range,
#: citation).
DENSITY_RELATIONS: dict[str, tuple[Any, tuple[float, float], str]] = {
    "scapozza2004": (
        lambda rho: 0.1873e6 * np.exp(0.0149 * rho),
        (180.0, 490.0),
        "Scapozza (2004), PhD thesis ETH Zürich, eq. 5-7: E = 0.1873·exp(0.0149·ρ) MPa",
    ),
    "gerling2017": (
        lambda rho: 6.0e-10 * rho**4.6 * 1e6,
        (100.0, 450.0),
        "Gerling et al. (2017), Geophys. Res. Lett. 44, eq. 6: E = 6.0e-10·ρ^4.6 MPa",
    ),
}

#: Density of ice [kg/m³] (the upper bound of a snow density).
ICE_DENSITY: float = 917.0


def modulus_from_density(density: float, *, relation: str = "scapozza2004") -> float:
    """Young's modulus E [Pa] of dry snow of density ρ [kg/m³] (see the module docstring).

    Raises :class:`~skisnow.InputError` for an impossible density (≤ 0 or above ice) or an
    unknown relation; warns (:class:`~skisnow.DomainWarning`) outside the relation's range.
    """
    if relation not in DENSITY_RELATIONS:
        raise InputError(
            f"density relation {relation!r} unknown; valid: {', '.join(DENSITY_RELATIONS)}"
        )
    rho = float(density)
    if not (math.isfinite(rho) and 0 < rho < ICE_DENSITY):
        raise InputError(
            f"snow density must lie between 0 and {ICE_DENSITY:g} kg/m³ (ice), got {density}"
        )
    fn, (lo, hi), cite = DENSITY_RELATIONS[relation]
    if not lo <= rho <= hi:
        warnings.warn(
            f"snow density {rho:g} kg/m³ lies outside the {lo:g}–{hi:g} kg/m³ of {cite}",
            DomainWarning,
            stacklevel=2,
        )
    return float(fn(rho))


def gamma_grains(mode: float, *, shape: float = 24.922) -> GrainFit:
    """The grain-size density f(D) = a·D^b·e^(−cD) of eq. 12 (Scherge et al. 2021) with mode
    b/c = ``mode`` [m] and exponent b = ``shape`` (default: the paper's fit, b = 24.9, whose
    relative spread is 1/√(b+1) = 20 %), normalised to unit area."""
    if not (math.isfinite(mode) and mode > 0 and shape > 0):
        raise InputError(f"grain mode [m] and shape must be positive, got {mode}, {shape}")
    c = shape / mode
    log_a = (shape + 1.0) * math.log(c) - float(special.gammaln(shape + 1.0))
    return GrainFit(log_a=log_a, b=float(shape), c=float(c))


@dataclass(frozen=True, kw_only=True, eq=False)
class Snow:
    """The snow under the ski, for every scale (SI units; temperature in °C as the papers).

    Parameters
    ----------
    name
        What to call it in tables ("fine-grained", a file name, ...).
    modulus
        E_counter [Pa] of the apparent contact (eq. 2 of Kalliorinne et al. 2023).
    poisson
        ν of the snow (the paper: 0.3).
    temperature_c
        Snow temperature [°C] (≤ 0): ice hardness H(T) (Scherge et al. 2021, eq. 2–3).
    hardness_model
        ``'poirier'`` (eq. 2, default) or ``'makkonen'`` (eq. 3).
    grains
        f(D) of eq. 12 (:class:`~skisnow.micro.GrainFit`), used when no diameters are given.
    grain_diameters
        Measured grain diameters [m] (then their empirical distribution replaces f(D)).
    density
        ρ [kg/m³] if known (informative; :meth:`from_density` derives the modulus from it).
    modulus_source
        Where the modulus comes from (a citation, "given", a preset's range).
    sources
        Citations of the values (presets).
    ranges
        What the preset stands for: quantity → (low, high) in the field units its key names
        (``modulus_mpa``, ``temperature_c``, ``grain_mode_um``, ``density_kg_m3``).
    description
        One line for tables.
    """

    name: str
    modulus: float
    poisson: float = 0.3
    temperature_c: float = -2.0
    hardness_model: str = "poirier"
    grains: GrainFit = field(default_factory=lambda: gamma_grains(625e-6))
    grain_diameters: tuple[float, ...] | None = None
    density: float | None = None
    modulus_source: str = "given"
    sources: tuple[str, ...] = ()
    ranges: dict[str, tuple[float, float]] = field(default_factory=dict)
    description: str = ""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.modulus) and self.modulus > 0):
            raise InputError(
                f"snow {self.name!r}: modulus must be positive [Pa], got {self.modulus}"
            )
        if not -1.0 < self.poisson < 0.5:
            raise InputError(f"snow {self.name!r}: Poisson ratio must lie in (-1, 0.5)")
        t = float(self.temperature_c)
        if not (math.isfinite(t) and -273.15 < t <= 0.0):
            raise InputError(
                f"snow {self.name!r}: temperature must lie between -273.15 and 0 °C, got {t}"
            )
        if self.hardness_model not in ("poirier", "makkonen"):
            raise InputError(
                f"snow {self.name!r}: hardness model {self.hardness_model!r} unknown; valid: "
                "poirier, makkonen"
            )
        if self.grain_diameters is not None:
            d = tuple(float(v) for v in self.grain_diameters)
            if len(d) < 1 or not all(math.isfinite(v) and v > 0 for v in d):
                raise InputError(f"snow {self.name!r}: grain diameters must be positive [m]")
            object.__setattr__(self, "grain_diameters", tuple(sorted(d)))
        if self.density is not None and not (0 < self.density < ICE_DENSITY):
            raise InputError(f"snow {self.name!r}: density must lie in (0, 917) kg/m³")

    @classmethod
    def from_density(
        cls, *, name: str, density: float, relation: str = "scapozza2004", **kwargs: Any
    ) -> Snow:
        """A snow whose modulus is estimated from its density (:func:`modulus_from_density`)."""
        e = modulus_from_density(density, relation=relation)
        cite = DENSITY_RELATIONS[relation][2]
        return cls(
            name=name,
            modulus=e,
            density=float(density),
            modulus_source=f"{cite} at {density:g} kg/m³",
            **kwargs,
        )

    def replace(self, **changes: Any) -> Snow:
        """A copy with ``changes`` (a given modulus is recorded as such)."""
        if "modulus" in changes and "modulus_source" not in changes:
            changes["modulus_source"] = "given"
        return dataclasses.replace(self, **changes)

    @property
    def material(self) -> Material:
        """The snow as the apparent contact sees it (E_counter, ν)."""
        return Material(name=f"snow ({self.name})", modulus=self.modulus, poisson=self.poisson)

    @property
    def hardness(self) -> float:
        """Ice hardness H(T) [Pa] (Scherge et al. 2021, eq. 2 or 3; warns out of range)."""
        return ice_hardness(self.temperature_c, model=self.hardness_model)

    @property
    def mean_grain_diameter(self) -> float:
        """Mean grain diameter [m] (measured, or (b+1)/c of f(D))."""
        if self.grain_diameters is not None:
            return float(np.mean(self.grain_diameters))
        return self.grains.mean

    def grain_nodes(self, n: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """Diameters [m] and weights (sum 1) that average a smooth function over the grains.

        For f(D) (a gamma density, shape b+1, rate c): the n-point generalised Gauss–Laguerre
        rule, exact for polynomials in D of degree < 2n. For measured diameters: n equal-count
        groups of the sorted diameters, each represented by its mean."""
        n = int(n)
        if n < 1:
            raise InputError(f"need at least one grain node, got {n}")
        if self.grain_diameters is not None:
            d = np.asarray(self.grain_diameters)
            groups = [g for g in np.array_split(d, min(n, d.size)) if g.size]
            return (
                np.array([g.mean() for g in groups]),
                np.array([g.size / d.size for g in groups]),
            )
        x, w = special.roots_genlaguerre(n, self.grains.b)
        return x / self.grains.c, w / w.sum()

    def micro_key(self) -> dict[str, Any]:
        """What the micro curves depend on (the cache key's snow part)."""
        d, w = self.grain_nodes()
        return {
            "temperature_c": float(self.temperature_c),
            "hardness_model": self.hardness_model,
            "grain_nodes_m": [float(v) for v in np.round(d, 12)],
            "grain_weights": [float(v) for v in np.round(w, 12)],
        }

    def describe(self) -> str:
        """One line: name, modulus, temperature and hardness, grains."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DomainWarning)
            h = self.hardness
        span = (self.ranges or {}).get("modulus_mpa")
        # what the modulus is worth: the published relations' spread for this snow, when known
        worth = (
            f"; this snow spans E {span[0]:.3g}-{span[1]:.3g} MPa: run both ends"
            if span is not None
            else ""
        )
        return (
            f"{self.name}: E {self.modulus / 1e6:.4g} MPa ({self.modulus_source}{worth}), "
            f"{self.temperature_c:g} °C (H_ice {h / 1e6:.3g} MPa, {self.hardness_model}), "
            f"mean grain {self.mean_grain_diameter * 1e6:.0f} µm"
        )
