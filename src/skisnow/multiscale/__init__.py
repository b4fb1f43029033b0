"""The real contact along the ski: from camber to grind in one pipeline.

Kalliorinne et al. (2023, Lubricants 11(10) 427) couple the apparent pressure p(x) of a ski
(macro/meso: :mod:`skisnow.contact`) with the real contact of the base texture (micro:
:mod:`skisnow.micro`, Scherge et al. 2021). Here:

* :class:`Base`, :func:`make_base` — the base: materials of both scales and its texture (a
  measured file, a synthetic grind S1–S5, or smooth), prepared once (form removal + 33 µm);
* :class:`MicroCurves`, :func:`micro_curves` — the micro contact once per base × snow over a log
  grid of nominal pressures: the bearing model (eq. 5–9, 13) and the elastic–plastic flat-ice
  contact (real area, mean separation, reciprocal separation), cached on disk
  (:func:`cache_dir`);
* :class:`RealContact`, :func:`real_contact` — the curves at p(x): real area, separation,
  ∫1/u dA per station, summarised over any station masks (:meth:`RealContact.summarize`);
* :class:`FrictionParameters` — τ, η, v, film cut-off with their cited defaults; the dry
  (τ·A_r) and viscous (η·v·∫1/u dA) proxies and µ = F/W with its assumptions.

May import: contact, micro, snow
"""

from skisnow.multiscale._along import RealContact, RealSummary, real_contact
from skisnow.multiscale._base import SMOOTH_NAMES, Base, make_base
from skisnow.multiscale._cache import cache_dir
from skisnow.multiscale._curves import (
    CURVES_FORMAT,
    DEFAULT_PIXEL,
    DEFAULT_PRESSURES,
    MicroCurves,
    micro_curves,
)
from skisnow.multiscale._friction import (
    DEFAULT_DRY_FRICTION,
    DEFAULT_FILM_CUTOFF,
    DEFAULT_SLIDING_SPEED,
    FrictionParameters,
    ResolvedFriction,
    water_viscosity,
)

__all__ = [
    "CURVES_FORMAT",
    "DEFAULT_DRY_FRICTION",
    "DEFAULT_FILM_CUTOFF",
    "DEFAULT_PIXEL",
    "DEFAULT_PRESSURES",
    "DEFAULT_SLIDING_SPEED",
    "SMOOTH_NAMES",
    "Base",
    "FrictionParameters",
    "MicroCurves",
    "RealContact",
    "RealSummary",
    "ResolvedFriction",
    "cache_dir",
    "make_base",
    "micro_curves",
    "real_contact",
    "water_viscosity",
]
