"""The ski base as a texture: the polyethylene's properties and its surface (:class:`Base`).

A base is what the ski brings to both scales: the base material for the apparent contact
(Kalliorinne et al. 2023, eq. 2: :data:`skisnow.materials.BASE`, 900 MPa, ν = 0.3) and for the
micro contact with ice (Scherge et al. 2021, Table 2: :data:`skisnow.materials.UHMWPE`,
840 MPa, ν = 0.46 — each scale keeps its paper's constants), and the texture of its surface:

* a measured topography file (any reader skisnow has: :func:`skisnow.micro.read_topography`);
* a synthetic grind: the presets S1–S5 (:func:`skisnow.micro.grind_preset`, stand-ins built to
  Scherge et al.'s Tables 1 and 4) or any :class:`skisnow.micro.GrindSpec`;
* none: a smooth base.

The texture is prepared once, by the one preparation of the roughness code
(:func:`skisnow.micro.prepare`: form removal, then the 33 µm Fourier low-pass), and both micro
models see that prepared map.
"""

from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._errors import InputError
from skisnow.materials import BASE, UHMWPE, Material
from skisnow.micro import (
    DEFAULT_CUTOFF,
    PRESETS,
    GrindSpec,
    Topography,
    grind,
    grind_preset,
    prepare,
    read_topography,
)

__all__ = ["SMOOTH_NAMES", "Base", "make_base"]

#: Names that mean "no texture".
SMOOTH_NAMES: tuple[str, ...] = ("smooth", "none", "flat")


@dataclass(frozen=True, kw_only=True, eq=False)
class Base:
    """A ski base: materials for both scales and the texture of its surface.

    Parameters
    ----------
    name
        What to call it in tables ("S3", a file name, "smooth").
    texture
        The raw topography [m] (heights toward the snow), or ``None`` for a smooth base.
    material
        The base as the apparent contact sees it (eq. 2 of Kalliorinne et al. 2023).
    micro_material
        The base as the micro contact with ice sees it (Scherge et al. 2021, Table 2).
    cutoff, form
        The preparation (:func:`skisnow.micro.prepare`): low-pass cut-off [m] (``None``: no
        filter) and form removal.
    source
        Where the texture came from (file, preset and its synthesis settings).
    """

    name: str
    texture: Topography | None = field(default=None, repr=False)
    material: Material = BASE
    micro_material: Material = UHMWPE
    cutoff: float | None = DEFAULT_CUTOFF
    form: str = "plane"
    source: str = ""

    @property
    def smooth(self) -> bool:
        """True for a base without texture."""
        return self.texture is None

    @functools.cached_property
    def prepared(self) -> Topography | None:
        """The texture after the one preparation (form removal + low-pass); ``None`` if smooth."""
        if self.texture is None:
            return None
        return prepare(self.texture, cutoff=self.cutoff, form=self.form)

    @functools.cached_property
    def key(self) -> str:
        """SHA-256 of what the micro curves see of the base: the prepared heights, the pixel
        sizes, the preparation and the micro material."""
        digest = hashlib.sha256()
        meta: dict[str, Any] = {
            "cutoff": self.cutoff,
            "form": self.form,
            "micro_material": [self.micro_material.modulus, self.micro_material.poisson],
        }
        t = self.prepared
        if t is None:
            meta["texture"] = "smooth"
        else:
            meta |= {"dx": t.dx, "dy": t.dy, "shape": list(t.shape)}
            digest.update(np.ascontiguousarray(np.round(t.heights, 15)).tobytes())
        digest.update(json.dumps(meta, sort_keys=True).encode())
        return digest.hexdigest()

    def describe(self) -> str:
        """One line: name and texture."""
        if self.texture is None:
            return f"{self.name}: smooth (no texture)"
        t = self.texture
        return (
            f"{self.name}: {t.size[0] * 1e3:.3g} × {t.size[1] * 1e3:.3g} mm map at "
            f"{t.dx * 1e6:.3g} µm ({self.source or t.source})"
        )


@functools.lru_cache(maxsize=32)
def _preset_base(
    name: str, size: float, dx: float, seed: int, material: Material, micro_material: Material
) -> Base:
    """A preset grind as a Base, made once per process (its preparation and key are cached on
    the instance, so sweeps and repeated cases do not grind and filter again)."""
    t = grind_preset(name, size=size, dx=dx, seed=seed)
    src = (
        f"preset {name} ({PRESETS[name].description}), {size * 1e3:g} mm at {dx * 1e6:g} µm, "
        f"seed {seed}"
    )
    return Base(name=name, texture=t, source=src, material=material, micro_material=micro_material)


def make_base(
    spec: Base | str | Path | GrindSpec | Topography | None,
    *,
    size: float = 1e-3,
    dx: float = 1e-6,
    seed: int = 0,
    pixel_size: float | tuple[float, float] | None = None,
    height_unit: str = "m",
    material: Material = BASE,
    micro_material: Material = UHMWPE,
) -> Base:
    """A :class:`Base` from a preset name (S1–S5), ``smooth``/``none``, a topography file, a
    :class:`~skisnow.micro.GrindSpec`, a :class:`~skisnow.micro.Topography` or a Base.

    Synthetic grinds are drawn on a square map of side ``size`` [m] at pixel ``dx`` [m] with
    ``seed``; ``pixel_size`` and ``height_unit`` are passed to
    :func:`~skisnow.micro.read_topography` for ``.npy`` and text matrices.
    """
    common = {"material": material, "micro_material": micro_material}
    if isinstance(spec, Base):
        return spec
    if spec is None:
        return Base(name="smooth", source="no texture", **common)
    if isinstance(spec, Topography):
        return Base(name=spec.source, texture=spec, source=spec.source, **common)
    if isinstance(spec, GrindSpec):
        t = grind(spec, shape=(round(size / dx), round(size / dx)), dx=dx, seed=seed)
        return Base(name=spec.name, texture=t, source=f"grind {spec.name}, seed {seed}", **common)
    text = str(spec).strip()
    path = Path(text)
    if path.is_file():
        t = read_topography(path, pixel_size=pixel_size, height_unit=height_unit)
        return Base(name=path.name, texture=t, source=str(path), **common)
    if text.lower() in SMOOTH_NAMES:
        return Base(name="smooth", source="no texture", **common)
    if text.upper() in PRESETS:
        return _preset_base(
            text.upper(), float(size), float(dx), int(seed), material, micro_material
        )
    raise InputError(
        f"base {text!r}: not a topography file, and not one of the grinds "
        f"{', '.join(PRESETS)} or {', '.join(SMOOTH_NAMES)}"
    )
