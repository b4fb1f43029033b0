"""Synthetic stone-grinding structures of a ski base (seeded, reproducible).

A grinding stone cuts a periodic pattern of grooves; every pass removes material, so the base
after several passes is the pointwise MINIMUM of the surfaces each pass alone would leave (a
later pass never adds material). One pass is a family of parallel grooves of pitch ``pitch``,
depth ``depth`` and cross-section ``profile``, running at ``angle`` to the ski axis (axis 1);
groove depths vary from groove to groove by ``depth_jitter`` (relative, Gaussian) as a
conditioned stone does. Stone-grit noise is a Gaussian random field of rms ``grit_rms`` and
correlation length ``grit_length`` (white noise smoothed by a Gaussian kernel) added on top.

Profiles (u ∈ [−½, ½) is the position across one groove in units of the pitch, v = 2u/width):

* ``'parabolic'``: −depth·(1 − v²) for |v| ≤ 1, else 0 — round-bottomed grooves, cusped ridges
  (positive skewness, as in Scherge et al.'s (2021) Table 4);
* ``'v'``: −depth·(1 − |v|) for |v| ≤ 1, else 0 — V grooves;
* ``'sine'``: −depth·(1 + cos 2πu)/2 (``width`` ignored).

The presets S1–S5 mimic the five structures of Scherge et al. (2021, §2.1, Tables 1 and 4):
linear fine, medium, coarse, linear with several passes, cross-hatched. Their parameters were
chosen so that the line roughness across the ski after the paper's 33 µm low-pass lies in the
range of Table 1 (Ra 1.37–2.88 µm, Rz 9–13 µm) and the areal values are near Table 4; they are
plausible stand-ins, NOT the measured topographies (which are not published).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from skisnow._errors import InputError
from skisnow.micro._topography import Topography, make_topography

__all__ = [
    "PRESETS",
    "GrindSpec",
    "GroovePass",
    "grind",
    "grind_preset",
]


@dataclass(frozen=True)
class GroovePass:
    """One pass of the stone: parallel grooves (lengths in m, angle in degrees from the ski
    axis, positive counter-clockwise)."""

    pitch: float
    depth: float
    profile: str = "parabolic"
    width: float = 1.0
    angle_deg: float = 0.0
    offset: float = 0.0
    depth_jitter: float = 0.0


@dataclass(frozen=True)
class GrindSpec:
    """A grinding structure: passes plus stone-grit noise (lengths in m)."""

    name: str
    description: str
    passes: tuple[GroovePass, ...]
    grit_rms: float = 0.0
    grit_length: float = 5e-6


def _profile(u: np.ndarray, kind: str, width: float) -> np.ndarray:
    if kind == "sine":
        return -(1.0 + np.cos(2 * np.pi * u)) / 2.0
    v = 2.0 * u / width
    inside = np.abs(v) <= 1.0
    if kind == "parabolic":
        return np.where(inside, -(1.0 - v**2), 0.0)
    if kind == "v":
        return np.where(inside, -(1.0 - np.abs(v)), 0.0)
    raise InputError(f"groove profile {kind!r} unknown; valid: 'parabolic', 'v', 'sine'")


def _pass_surface(
    p: GroovePass, x: np.ndarray, y: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    if not (p.pitch > 0 and p.depth >= 0 and 0 < p.width <= 1):
        raise InputError(f"invalid groove pass {p}: need pitch > 0, depth >= 0, 0 < width <= 1")
    a = np.deg2rad(p.angle_deg)
    # coordinate across the grooves (grooves run along the direction (sin a, cos a))
    s = (x * np.cos(a) - y * np.sin(a) - p.offset) / p.pitch
    k = np.floor(s + 0.5)
    u = s - k
    h = p.depth * _profile(u, p.profile, p.width)
    if p.depth_jitter > 0:
        k = k.astype(np.int64)
        kmin = int(k.min())
        scale = 1.0 + p.depth_jitter * rng.standard_normal(int(k.max()) - kmin + 1)
        h = h * np.clip(scale, 0.0, None)[k - kmin]
    return h


def grind(
    spec: GrindSpec,
    *,
    shape: tuple[int, int] = (1000, 1000),
    dx: float = 1e-6,
    seed: int = 0,
) -> Topography:
    """Synthesise the structure ``spec`` on a grid of ``shape`` pixels of size ``dx`` [m]."""
    if len(shape) != 2 or min(shape) < 2:
        raise InputError(f"shape must be two sizes >= 2, got {shape}")
    if not dx > 0:
        raise InputError(f"pixel size dx must be positive [m], got {dx}")
    rng = np.random.default_rng(seed)
    x = (np.arange(shape[0]) * dx)[:, None]
    y = (np.arange(shape[1]) * dx)[None, :]
    h = np.zeros(shape)
    for i, p in enumerate(spec.passes):
        surf = _pass_surface(p, x, y, rng)
        h = surf if i == 0 else np.minimum(h, surf)
    if spec.grit_rms > 0:
        sigma = spec.grit_length / dx
        noise = ndimage.gaussian_filter(rng.standard_normal(shape), sigma, mode="wrap")
        noise *= spec.grit_rms / noise.std()
        h = h + noise
    return make_topography(h - h.mean(), dx=dx, source=f"preset {spec.name}")


_UM = 1e-6


def _preset(name: str, description: str, *passes: GroovePass) -> GrindSpec:
    """A preset: its groove passes over the stone grit all five share (0.6 µm rms, 6 µm)."""
    return GrindSpec(name, description, passes, grit_rms=0.6 * _UM, grit_length=6 * _UM)


#: The five structures of Scherge et al. (2021) (stand-ins; see the module docstring).
PRESETS: dict[str, GrindSpec] = {
    spec.name: spec
    for spec in (
        _preset("S1", "linear/fine", GroovePass(pitch=80 * _UM, depth=8.5 * _UM, depth_jitter=0.5)),
        _preset(
            "S2", "linear/medium", GroovePass(pitch=130 * _UM, depth=8.5 * _UM, depth_jitter=0.45)
        ),
        _preset(
            "S3", "linear/coarse", GroovePass(pitch=220 * _UM, depth=10.5 * _UM, depth_jitter=0.35)
        ),
        _preset(
            "S4",
            "linear/multiple",
            GroovePass(pitch=200 * _UM, depth=10.0 * _UM, depth_jitter=0.3),
            GroovePass(
                pitch=90 * _UM, depth=6.0 * _UM, width=0.8, offset=37 * _UM, depth_jitter=0.3
            ),
        ),
        _preset(
            "S5",
            "cross-hatched",
            GroovePass(pitch=120 * _UM, depth=11.5 * _UM, angle_deg=15.0, depth_jitter=0.35),
            GroovePass(pitch=120 * _UM, depth=11.5 * _UM, angle_deg=-15.0, depth_jitter=0.35),
        ),
    )
}


def grind_preset(name: str, *, size: float = 1e-3, dx: float = 1e-6, seed: int = 0) -> Topography:
    """The preset structure ``name`` (``'S1'``..``'S5'``) on a square map of side ``size`` [m]
    at pixel size ``dx`` [m]."""
    key = name.strip().upper()
    if key not in PRESETS:
        raise InputError(f"grinding preset {name!r} unknown; valid: {', '.join(PRESETS)}")
    n = round(size / dx)
    if n < 2:
        raise InputError(f"map of side {size} m at pixel {dx} m has fewer than 2 pixels")
    return grind(PRESETS[key], shape=(n, n), dx=dx, seed=seed)
