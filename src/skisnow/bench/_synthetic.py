"""Plausible synthetic skis for validation studies (identification coverage, benchmarks).

A ski whose truth is known, built like the shipped skis (:mod:`skisnow.ski._shipped`: a camber
arch between two support points, glide zones rising outside them, a tail rise and a shovel) with
the features that make a real ski hard to identify: sharp stiffness steps (a stiff plateau behind
the balance point, a soft front), almost flat glide zones (a power law of high exponent), a wax
pocket and µm waviness of the base. :func:`plausible_ski` builds one from its parameters,
:func:`random_ski` draws the parameters from the ranges of :data:`RANGES` (seeded), and
:func:`issue25_ski` is the ski of issue 25's account (207 cm classic, stiff plateau behind the
balance point, long soft front, almost flat glide zones, 15 µm waviness) as reconstructed here.

The ranges are chosen around the shipped skis and the practitioners' numbers their descriptions
cite (camber at half body weight 0.3-1.5 mm for classic skis, never closing for skate skis at
130 kg, EI between 100 and 10000 N m²); they are assumptions, not measurements.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from skisnow.ski import Provenance, Ski, rest_on_plane

__all__ = ["RANGES", "issue25_ski", "plausible_ski", "random_ski"]

#: Parameter ranges of :func:`random_ski` (uniform; lengths in m, EI in N m²).
RANGES: dict[str, dict[str, tuple[float, float]]] = {
    "classic": {
        "length": (1.90, 2.07), "rear_support": (-0.66, -0.54), "front_support": (0.48, 0.62),
        "camber": (2.2e-3, 3.5e-3), "camber_power": (2.0, 3.0), "pocket": (0.0, 0.4e-3),
        "glide_radius": (25.0, 70.0), "glide_power": (2.0, 4.0), "ei_mid": (1200.0, 3000.0),
        "ei_end": (100.0, 300.0), "plateau_factor": (1.0, 3.0), "front_factor": (0.6, 1.0),
        "step_width": (0.010, 0.040), "waviness": (0.0, 15e-6), "wavelength": (0.04, 0.12),
    },
    "skate": {
        "length": (1.80, 1.95), "rear_support": (-0.82, -0.70), "front_support": (0.66, 0.78),
        "camber": (5.0e-3, 6.5e-3), "camber_power": (1.8, 2.6), "pocket": (0.0, 0.0),
        "glide_radius": (20.0, 50.0), "glide_power": (2.0, 3.5), "ei_mid": (6000.0, 10000.0),
        "ei_end": (200.0, 400.0), "plateau_factor": (1.0, 2.0), "front_factor": (0.8, 1.0),
        "step_width": (0.010, 0.040), "waviness": (0.0, 15e-6), "wavelength": (0.04, 0.12),
    },
}  # fmt: skip


def _bump(x: NDArray[np.float64], start: float, end: float, power: float) -> NDArray[np.float64]:
    c, w = 0.5 * (start + end), 0.5 * (end - start)
    u = (x - c) / w
    return np.where(np.abs(u) < 1.0, np.abs(1.0 - u**2) ** power, 0.0)


def _step(x: NDArray[np.float64], at: float, width: float) -> NDArray[np.float64]:
    """0 → 1 across ``at`` over about ``width`` (10-90 %)."""
    return 0.5 * (1.0 + np.tanh(2.2 * (x - at) / max(width, 1e-6)))


def plausible_ski(
    *,
    name: str = "synthetic",
    kind: Literal["classic", "skate"] = "classic",
    length: float = 2.0,
    rear_support: float = -0.60,
    front_support: float = 0.52,
    camber: float = 3.0e-3,
    camber_power: float = 2.6,
    pocket: float = 0.0,
    glide_radius: float = 40.0,
    glide_power: float = 2.0,
    ei_mid: float = 1500.0,
    ei_end: float = 150.0,
    plateau_factor: float = 1.0,
    plateau: tuple[float, float] = (-0.45, -0.12),
    front_factor: float = 1.0,
    front: tuple[float, float] = (0.10, 0.85),
    step_width: float = 0.03,
    waviness: float = 0.0,
    wavelength: float = 0.06,
    phase: float = 0.0,
    description: str = "",
) -> Ski:
    """A ski from its shape parameters (SI units; module docstring).

    z0: ``camber``·(1 - u²)^``camber_power`` between the supports, a ``pocket`` bump over the
    middle third (classic), outside the supports d_ref²/(2 R)·(d/d_ref)^``glide_power`` (d_ref
    = 100 mm, R = ``glide_radius``; a power of 4 makes the glide zones almost flat near the
    support), ``waviness``·sin(2π x / ``wavelength`` + ``phase``), the 4 mm tail rise (last 50
    mm) and the 30 mm shovel (last 200 mm), resting on the plane. EI: ``ei_end`` + (``ei_mid``
    - ``ei_end``)(1 - x²) (x in m), times ``plateau_factor`` over ``plateau`` and
    ``front_factor`` over ``front``, each with edges ``step_width`` wide (10-90 %).
    """
    x_tail = -0.49 * length
    x_tip = x_tail + length
    x = np.round(np.linspace(x_tail, x_tip, round(length / 0.002) + 1), 9)
    z = camber * _bump(x, rear_support, front_support, camber_power)
    if pocket > 0:
        span = front_support - rear_support
        z += pocket * _bump(x, rear_support + span / 3, front_support - span / 3, 2.0)
    d_ref = 0.1
    for d in (np.clip(rear_support - x, 0, None), np.clip(x - front_support, 0, None)):
        z += d_ref**2 / (2.0 * glide_radius) * (d / d_ref) ** glide_power
    z += waviness * np.sin(2 * np.pi * x / wavelength + phase)
    z += 30e-3 * np.clip((x - (x_tip - 0.2)) / 0.2, 0, 1) ** 2.5
    z += 4e-3 * np.clip(((x_tail + 0.05) - x) / 0.05, 0, 1) ** 2
    ex = np.round(np.linspace(x_tail, x_tip, round(length / 0.005) + 1), 9)
    ei = ei_end + (ei_mid - ei_end) * np.clip(1.0 - ex**2, 0.0, None)
    for factor, (a, b) in ((plateau_factor, plateau), (front_factor, front)):
        ei *= 1.0 + (factor - 1.0) * _step(ex, a, step_width) * (1.0 - _step(ex, b, step_width))
    span = front_support - rear_support
    kick = (rear_support + 0.3 * span, front_support - 0.3 * span) if kind == "classic" else None
    return Ski(
        name=name, kind=kind, x_tail=x_tail, x_tip=x_tip, width=0.044,
        stiffness_x=ex, stiffness_values=ei, camber_x=x, camber_values=rest_on_plane(x, z),
        kick_zone=kick, boot_plate=(-0.30, 0.0),
        description=description or "synthetic ski (skisnow.bench.plausible_ski)",
        provenance=Provenance(method="synthetic (skisnow.bench.plausible_ski)",
                              data="none: chosen parameters"),
    )  # fmt: skip


def random_ski(seed: int, kind: Literal["classic", "skate"] | None = None) -> Ski:
    """A ski with parameters drawn uniformly from :data:`RANGES` (seeded with ``seed``; the
    kind drawn too unless given)."""
    rng = np.random.default_rng(seed)
    kind_ = kind or ("classic" if rng.random() < 0.5 else "skate")
    params: dict[str, Any] = {k: float(rng.uniform(*r)) for k, r in RANGES[kind_].items()}
    params["phase"] = float(rng.uniform(0.0, 2 * np.pi))
    # the plateau behind the balance point and the soft front: drawn positions
    a = float(rng.uniform(-0.50, -0.35))
    params["plateau"] = (a, a + float(rng.uniform(0.2, 0.35)))
    params["front"] = (float(rng.uniform(0.05, 0.25)), float(rng.uniform(0.7, 0.9)))
    return plausible_ski(name=f"random-{seed}", kind=kind_, **params)


def issue25_ski() -> Ski:
    """The ski of issue 25 as reconstructed here: a 207 cm classic with a stiff plateau behind
    the balance point (EI × 2.5 from -450 to -120 mm, 15 mm edges), a long soft front (× 0.6
    from +100 to +850 mm), almost flat glide zones (power 4) and 15 µm waviness (60 mm)."""
    return plausible_ski(
        name="issue25", kind="classic", length=2.07, rear_support=-0.62, front_support=0.56,
        camber=3.0e-3, camber_power=2.6, pocket=0.2e-3, glide_radius=40.0, glide_power=4.0,
        ei_mid=2000.0, ei_end=150.0, plateau_factor=2.5, plateau=(-0.45, -0.12),
        front_factor=0.6, front=(0.10, 0.85), step_width=0.015, waviness=15e-6,
        wavelength=0.06, description="issue 25's ski, reconstructed (skisnow.bench.issue25_ski)",
    )  # fmt: skip
