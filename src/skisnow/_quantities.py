"""Every quantity skisnow reads at its edge, stated once in its field unit (:data:`QUANTITIES`).

Each :class:`Quantity` names its field unit (the unit of the CLI option or file column), the
values that are physically impossible (always an error: a negative mass, a pixel of 0 µm, a
temperature below absolute zero) and the range that is plausible for a cross-country ski and its
snow (outside it: a unit slip, refused by :mod:`skisnow._checks` unless overridden). Options,
ski files, bench files, load histories, model files, side-cars and sweep specs all check their
values against this one table.

The ranges come from the skis and snows of Kalliorinne et al. (Lubricants 2023: skis of
1.8–2.1 m, camber heights up to ~40 mm at the tips, EI(x) of 50–25 000 N m², snow 20–400 MPa on
a 70 GPa stone bench) and Scherge et al. (Front. Mech. Eng. 2021: grinds of µm depth, pixels of
0.1–10 µm, grains of 100–2000 µm, snow from −30 °C to 0 °C); the loads of one ski from
force-measuring bindings (a skier's weight, up to about 3 body weights at the kick, sampled at
100–1000 Hz), widened generously: they catch unit slips, not unusual skis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["QUANTITIES", "Quantity"]


@dataclass(frozen=True, kw_only=True)
class Quantity:
    """One physical quantity at the edge of skisnow, in its field unit.

    Attributes
    ----------
    name
        What it is ("camber height").
    unit
        The field unit the value is given in ("mm").
    low, high
        Physically impossible beyond these bounds; ``low_open``/``high_open`` make the bound
        itself impossible too (a mass of 0 kg).
    plausible
        The range plausible for a ski; outside it the value is refused unless overridden.
    alternatives
        Units a user may have typed by mistake, as ``(unit, factor, offset)`` with
        ``value_in_field_unit = value_in_alternative · factor + offset``: used to say which unit
        was probably meant.
    min_span
        For a column of values: the smallest plausible spread (max − min); a smaller one means
        a unit slip (heights in metres in a millimetre column). ``0`` disables the check.
    typical
        A typical value (what a ski, a skier or a bench usually has): the scale against which
        a unit slip is measured (tests feed it ×1000 and ÷1000).
    infinite_ok
        ``+inf`` is a possible value ("no limit", e.g. a time budget).
    integer
        A count: a whole number.
    """

    name: str
    unit: str
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    plausible: tuple[float, float] = (-math.inf, math.inf)
    alternatives: tuple[tuple[str, float, float], ...] = ()
    min_span: float = 0.0
    typical: float = 1.0
    infinite_ok: bool = False
    integer: bool = False

    def possible(self, v: np.ndarray) -> np.ndarray:
        ok = np.isfinite(v) | ((v == math.inf) & self.infinite_ok)
        ok &= (v > self.low) if self.low_open else (v >= self.low)
        ok &= (v < self.high) if self.high_open else (v <= self.high)
        return ok

    def describe_possible(self) -> str:
        lo = "" if self.low == -math.inf else f"{'>' if self.low_open else '>='} {self.low:g}"
        hi = "" if self.high == math.inf else f"{'<' if self.high_open else '<='} {self.high:g}"
        bounds = " and ".join(b for b in (lo, hi) if b)
        what = "a whole number" if self.integer else "a finite number"
        unit = "" if self.unit in ("(count)", "(integer)") else self.unit  # "whole" says it
        return f"{what} {bounds} {unit}".replace("  ", " ").strip()

    def describe_plausible(self) -> str:
        lo, hi = self.plausible
        unit = "" if self.unit.startswith("(") else f" {self.unit}"  # a count: no "(count)"
        return f"{lo:g} to {hi:g}{unit}"

    def guess_unit(self, value: float, *, span: bool = False) -> str | None:
        """The alternative unit in which ``value`` would be plausible, if exactly one is."""
        lo, hi = self.plausible
        hits = []
        for unit, factor, offset in self.alternatives:
            if not span and value < lo <= 0.0 and offset == 0.0:
                continue  # a negative value of a (nearly) positive quantity: the sign is wrong

            if span:
                v = abs(value) * factor
                if v >= self.min_span and v <= hi - lo:
                    hits.append(unit)
            else:
                v = value * factor + offset
                if lo <= v <= hi:
                    hits.append(unit)
        return hits[0] if len(hits) >= 1 else None


_M = ("m", 1e3, 0.0)
_CM = ("cm", 10.0, 0.0)
_UM_IN_MM = ("µm", 1e-3, 0.0)

#: Every quantity skisnow reads at its edge, keyed by the name used in code.
QUANTITIES: dict[str, Quantity] = {
    "mass": Quantity(
        name="mass", unit="kg", low=0.0, low_open=True, plausible=(0.1, 300.0),
        alternatives=(("g", 1e-3, 0.0), ("lb", 0.45359237, 0.0)), typical=60.0,
    ),
    "load_position": Quantity(
        name="load position x_m from the balance point", unit="mm", plausible=(-700.0, 700.0),
        alternatives=(_M, _CM), typical=-120.0,
    ),
    "x": Quantity(
        name="position along the ski", unit="mm", plausible=(-1600.0, 1600.0),
        alternatives=(_M, _CM), min_span=100.0, typical=500.0,
    ),
    "ski_length": Quantity(
        name="ski length", unit="mm", low=0.0, low_open=True, plausible=(800.0, 2600.0),
        alternatives=(_M, _CM), typical=1900.0,
    ),
    "camber_height": Quantity(
        name="camber height above the bench", unit="mm", plausible=(-0.5, 250.0),
        alternatives=(_M, _UM_IN_MM), min_span=0.2, typical=10.0,
    ),
    "width": Quantity(
        name="ski width", unit="mm", low=0.0, low_open=True, plausible=(20.0, 150.0),
        alternatives=(_M, _CM), typical=44.0,
    ),
    "snow_modulus": Quantity(
        name="snow (counter-surface) modulus", unit="MPa", low=0.0, low_open=True,
        plausible=(0.01, 2.5e5), alternatives=(("Pa", 1e-6, 0.0), ("kPa", 1e-3, 0.0)),
        typical=100.0,
    ),
    "base_modulus": Quantity(
        name="ski base modulus", unit="MPa", low=0.0, low_open=True, plausible=(10.0, 2.0e4),
        alternatives=(("Pa", 1e-6, 0.0), ("GPa", 1e3, 0.0), ("kPa", 1e-3, 0.0)), typical=900.0,
    ),
    "temperature": Quantity(
        name="snow temperature", unit="°C", low=-273.15, low_open=False, plausible=(-60.0, 0.0),
        alternatives=(("K", 1.0, -273.15),), typical=-5.0,
    ),
    "pixel": Quantity(
        name="pixel size", unit="µm", low=0.0, low_open=True, plausible=(0.005, 2000.0),
        alternatives=(("m", 1e6, 0.0), ("mm", 1e3, 0.0), ("nm", 1e-3, 0.0)), typical=1.0,
    ),
    "map_size": Quantity(
        name="side of a topography map", unit="µm", low=0.0, low_open=True,
        plausible=(5.0, 2.0e5), alternatives=(("mm", 1e3, 0.0), ("m", 1e6, 0.0)), typical=1000.0,
    ),
    "topography_height": Quantity(
        name="peak-to-valley height of a ski-base topography", unit="m", low=0.0,
        plausible=(1e-10, 5e-3), alternatives=(("µm", 1e-6, 0.0), ("nm", 1e-9, 0.0),
                                             ("mm", 1e-3, 0.0)), typical=1e-5,
    ),
    "grain": Quantity(
        name="snow grain diameter", unit="µm", low=0.0, low_open=True, plausible=(5.0, 1.0e4),
        alternatives=(("mm", 1e3, 0.0), ("m", 1e6, 0.0)), typical=500.0,
    ),
    "pressure": Quantity(
        name="macroscopic pressure", unit="kPa", low=0.0, low_open=True,
        plausible=(0.01, 2.0e4), alternatives=(("Pa", 1e-3, 0.0), ("MPa", 1e3, 0.0)), typical=20.0,
    ),
    "cutoff": Quantity(
        name="low-pass cut-off wavelength (0 = none)", unit="µm", low=0.0,
        plausible=(0.0, 1.0e5), alternatives=(("m", 1e6, 0.0), ("mm", 1e3, 0.0)), typical=33.0,
    ),
    "step_along_ski": Quantity(
        name="sampling step along the ski", unit="mm", low=0.0, low_open=True,
        plausible=(0.005, 200.0), alternatives=(_M, _UM_IN_MM), typical=1.0,
    ),
    "noise": Quantity(
        name="standard deviation of the height noise", unit="mm", low=0.0, plausible=(0.0, 5.0),
        alternatives=(_UM_IN_MM,), typical=0.01,
    ),
    "alpha": Quantity(
        name="significance level", unit="(probability)", low=0.0, high=1.0, low_open=True,
        high_open=True, plausible=(1e-9, 0.2), typical=0.05,
    ),
    "glide_time": Quantity(
        name="glide time", unit="s", low=0.0, low_open=True, plausible=(0.01, 36000.0),
        typical=10.0,
    ),
    "grid_points": Quantity(
        name="number of grid points", unit="(count)", low=16.0, plausible=(16.0, 2.0**21),
        typical=4096.0, integer=True,
    ),
    "sliding_speed": Quantity(
        name="sliding speed", unit="m/s", low=0.0, low_open=True, plausible=(0.05, 40.0),
        alternatives=(("km/h", 1 / 3.6, 0.0),), typical=5.0,
    ),
    "film_cutoff": Quantity(
        name="film-thickness cut-off", unit="nm", low=0.0, low_open=True,
        plausible=(0.1, 1.0e5), alternatives=(("µm", 1e3, 0.0), ("m", 1e9, 0.0)), typical=10.0,
    ),
    "shear_strength": Quantity(
        name="shear strength of the real contact", unit="MPa", low=0.0, low_open=True,
        plausible=(1e-4, 100.0), alternatives=(("Pa", 1e-6, 0.0), ("kPa", 1e-3, 0.0)),
        typical=1.0,
    ),
    "viscosity": Quantity(
        name="meltwater viscosity", unit="mPa·s", low=0.0, low_open=True,
        plausible=(0.1, 100.0), alternatives=(("Pa·s", 1e3, 0.0),), typical=1.8,
    ),
    "cells_across": Quantity(
        name="number of cells across the width", unit="(count)", low=1.0, plausible=(1.0, 1024.0),
        typical=16.0,
        integer=True,
    ),
    # -- the ski file (skisnow.ski): zones, stiffness and uncertainties
    "zone_length": Quantity(
        name="length of a zone of the ski (kick zone, boot plate)", unit="mm", low=0.0,
        low_open=True, plausible=(20.0, 2600.0), alternatives=(_M, _CM), typical=500.0,
    ),
    "bending_stiffness": Quantity(
        name="bending stiffness EI", unit="N m²", low=0.0, low_open=True, plausible=(1.0, 2.0e5),
        alternatives=(("N mm²", 1e-6, 0.0), ("N cm²", 1e-4, 0.0), ("kN m²", 1e3, 0.0)),
        typical=2000.0,
    ),
    "log_ei_sd": Quantity(
        name="standard deviation of log EI", unit="(log units)", low=0.0, plausible=(0.0, 3.0),
        typical=0.05,
    ),
    "camber_sd": Quantity(
        name="standard deviation of the free camber", unit="mm", low=0.0, plausible=(0.0, 10.0),
        alternatives=(_UM_IN_MM,), typical=0.01,
    ),
    # -- load histories (skisnow.workflows)
    "force": Quantity(
        name="force on one ski", unit="N", low=0.0, plausible=(0.0, 1.0e4),
        alternatives=(("kN", 1e3, 0.0), ("mN", 1e-3, 0.0)), typical=700.0,
    ),
    "load_mass": Quantity(
        name="load on one ski (as a mass; 0 = unloaded)", unit="kg", low=0.0,
        plausible=(0.0, 1000.0), alternatives=(("g", 1e-3, 0.0), ("lb", 0.45359237, 0.0)),
        typical=70.0,
    ),
    "sample_step": Quantity(
        name="time step between samples", unit="s", low=0.0, low_open=True,
        plausible=(1e-5, 1.0), alternatives=(("ms", 1e-3, 0.0), ("µs", 1e-6, 0.0)),
        typical=0.01,
    ),
    "history_duration": Quantity(
        name="duration of a load history", unit="s", low=0.0, low_open=True,
        plausible=(0.01, 36000.0), alternatives=(("ms", 1e-3, 0.0),), typical=1.5,
    ),
    "mean_load": Quantity(
        name="mean load over a history (impulse / duration, as a mass)", unit="kg", low=0.0,
        plausible=(1.0, 300.0), alternatives=(("g", 1e-3, 0.0),), typical=50.0,
    ),
    "mean_force": Quantity(
        name="mean force over a history (impulse / duration)", unit="N", low=0.0,
        plausible=(10.0, 3000.0), alternatives=(("kN", 1e3, 0.0), ("mN", 1e-3, 0.0)),
        typical=500.0,
    ),
    "cycle_time": Quantity(
        name="cycle time of a stride", unit="s", low=0.0, low_open=True, plausible=(0.1, 20.0),
        alternatives=(("ms", 1e-3, 0.0),), typical=1.4,
    ),
    "animation_speed": Quantity(
        name="animation playback speed (1 = real time)", unit="(factor)", low=0.0,
        low_open=True, plausible=(1e-3, 1e3), typical=1.0,
    ),
    # -- derived quantities, checked where they are computed
    "apparent_pressure": Quantity(
        name="apparent contact pressure on snow", unit="kPa", low=0.0,
        plausible=(0.0, 1.0e4), alternatives=(("Pa", 1e-3, 0.0),), typical=60.0,
    ),
    # -- counts and settings of the commands
    "workers": Quantity(
        name="number of workers (0: in this process)", unit="(count)", low=0.0,
        plausible=(0.0, 1024.0), integer=True, typical=2.0,
    ),
    "display_stations": Quantity(
        name="number of display stations along the ski", unit="(count)", low=16.0,
        plausible=(16.0, 65536.0), integer=True, typical=512.0,
    ),
    "frames": Quantity(
        name="number of frames over a load cycle", unit="(count)", low=2.0, plausible=(2.0, 1.0e5),
        integer=True, typical=100.0,
    ),
    "seed": Quantity(
        name="random seed", unit="(integer)", low=0.0, high=2.0**63 - 1,
        plausible=(0.0, 2.0**63 - 1), integer=True, typical=0.0,
    ),
    "beam_element_length": Quantity(
        name="element length of a beam mesh", unit="mm", low=0.0, low_open=True, high=100.0,
        high_open=True, plausible=(0.5, 50.0), alternatives=(_M,), typical=10.0,
    ),
    "spline_coefficients": Quantity(
        name="number of spline coefficients", unit="(count)", low=2.0, plausible=(2.0, 4000.0),
        integer=True, typical=50.0,
    ),
    "evaluations": Quantity(
        name="evaluation limit", unit="(count)", low=1.0, plausible=(1.0, 1.0e6), integer=True,
        typical=60.0,
    ),
    "optimizer_steps": Quantity(
        name="number of optimiser steps", unit="(count)", low=0.0, plausible=(0.0, 1.0e6),
        integer=True, typical=200.0,
    ),
    "posterior_samples": Quantity(
        name="number of posterior samples (0: no intervals)", unit="(count)", low=0.0,
        plausible=(0.0, 1.0e4), integer=True, typical=200.0,
    ),
    "bootstrap_replicates": Quantity(
        name="number of bootstrap replicates (0: none; each one identification)",
        unit="(count)", low=0.0, plausible=(0.0, 200.0), integer=True, typical=0.0,
    ),
    "ensemble_members": Quantity(
        name="number of ensemble members", unit="(count)", low=1.0, plausible=(1.0, 100.0),
        integer=True, typical=1.0,
    ),
    "layer_width": Quantity(
        name="layer width of the camber network", unit="(count)", low=1.0,
        plausible=(1.0, 1024.0), integer=True, typical=16.0,
    ),
    "pixel_stride": Quantity(
        name="stride between evaluated pixels", unit="(count)", low=1.0, plausible=(1.0, 1.0e4),
        integer=True, typical=1.0,
    ),
    "population": Quantity(
        name="population size or number of generations of the optimiser", unit="(count)", low=1.0,
        plausible=(1.0, 1.0e5), integer=True, typical=20.0,
    ),
    "regularisation": Quantity(
        name="regularisation weight λ", unit="(weight)", low=0.0, plausible=(0.0, 1.0e12),
        typical=1.0,
    ),
    "weight": Quantity(
        name="weight of a term of the objective", unit="(weight)", low=0.0,
        plausible=(0.0, 1.0e6), typical=1.0,
    ),
    "noise_um": Quantity(
        name="standard deviation of the height noise", unit="µm", low=0.0, plausible=(0.0, 5000.0),
        alternatives=(("mm", 1e3, 0.0), ("m", 1e6, 0.0)), typical=10.0,
    ),
    "percent": Quantity(
        name="relative uncertainty", unit="%", low=0.0, low_open=True, plausible=(0.01, 1000.0),
        typical=5.0,
    ),
    "minutes": Quantity(
        name="time budget", unit="min", low=0.0, low_open=True, plausible=(0.01, math.inf),
        infinite_ok=True, typical=30.0,
    ),
    "fraction": Quantity(
        name="fraction", unit="(fraction)", low=0.0, plausible=(0.0, 100.0), typical=0.1,
    ),
    "ratio": Quantity(
        name="ratio", unit="(factor)", low=0.0, low_open=True, plausible=(1e-3, 1e3),
        typical=1.5,
    ),
    "ski_stiffness": Quantity(
        name="ski stiffness (load per mm of closing)", unit="N/mm", low=0.0, low_open=True,
        plausible=(5.0, 5000.0), alternatives=(("N/m", 1e-3, 0.0), ("kN/mm", 1e3, 0.0)),
        typical=230.0,
    ),
}  # fmt: skip
