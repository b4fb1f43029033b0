"""Roughness parameters (ISO 25178 areal, ISO 4287 line) and the Fourier low-pass of the paper.

Scherge, Stoll & Moseler (2021), §2.1 and Tables 1 and 4: topographies are Fourier filtered with
a cut-off wavelength of 33 µm, then Sa, Sq, Sdq, Ssk, Sku (areal) and Ra, Rz (line scans) are
quoted. Which library computes what:

* Sq — SurfaceTopography ``rms_height_from_area`` (after our form removal);
* Sdq — SurfaceTopography ``rms_gradient`` (root mean square of the two-component gradient from
  finite differences, undefined pixels skipped);
* Sa, Ssk, Sku, Ra, Rz — SurfaceTopography has no such parameters (its ``mad_height`` is a
  median-based deviation, not Sa), so they are computed here from the heights (about the mean of
  the defined pixels).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from skisnow._errors import InputError
from skisnow.micro._topography import (
    Topography,
    fill_missing,
    make_topography,
    remove_form,
    to_surface_topography,
)

__all__ = [
    "Roughness",
    "SdqSpread",
    "areal_parameters",
    "line_parameters",
    "lowpass",
    "prepare",
    "roughness",
    "sdq_spread",
]

#: Scherge et al.'s (2021) cut-off wavelength of the Fourier filter [m] (§2.1).
DEFAULT_CUTOFF: float = 33e-6


@dataclass(frozen=True)
class Roughness:
    """Roughness parameters of a topography (SI: lengths in m, slopes and moments dimensionless).

    ``Ra`` and ``Rz`` are means over all line profiles along axis 0 (across the ski); ``Rz`` is
    the ISO 4287 ten-point height: the mean over five equal sampling lengths of (highest peak +
    deepest valley) about the profile's least-squares mean line; ``Rt`` is the total
    peak-to-valley height of the whole profile (also averaged over lines).
    """

    Sa: float
    Sq: float
    Sdq: float
    Ssk: float
    Sku: float
    Ra: float
    Rz: float
    Rt: float
    cutoff: float | None
    form: str

    def as_dict(self) -> dict[str, float | str | None]:
        """Plain dictionary (for JSON/tables)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def lowpass(topo: Topography, *, cutoff: float = DEFAULT_CUTOFF) -> Topography:
    """Fourier low-pass: remove all components of wavelength shorter than ``cutoff`` [m].

    Ideal (sharp) radial filter |k| ≤ 2π/λc. To avoid the wrap-around of a periodic FFT on a
    non-periodic map, the transform is the type-II DCT, i.e. the FFT of the map mirrored at its
    edges (even extension): DCT index j ↔ wavenumber k_j = π j/(N·Δ). Missing pixels are filled
    first (:func:`~skisnow.micro.fill_missing`) and restored as missing afterwards.
    """
    if not (np.isfinite(cutoff) and cutoff > 0):
        raise InputError(f"cutoff wavelength must be positive [m], got {cutoff}")
    missing = topo.missing
    h = np.asarray(fill_missing(topo).heights)
    nx, ny = h.shape
    kx = np.pi * np.arange(nx) / (nx * topo.dx)
    ky = np.pi * np.arange(ny) / (ny * topo.dy)
    keep = kx[:, None] ** 2 + ky[None, :] ** 2 <= (2 * np.pi / cutoff) ** 2
    spec = sfft.dctn(h, type=2, norm="ortho")
    out = sfft.idctn(spec * keep, type=2, norm="ortho")
    out[missing] = np.nan
    return make_topography(out, dx=topo.dx, dy=topo.dy, source=topo.source)


def areal_parameters(topo: Topography) -> dict[str, float]:
    """Sa, Sq, Sdq, Ssk, Sku of a topography as it is (no form removal, no filter).

    Moments are about the mean of the defined pixels: Sa = ⟨|z|⟩, Sq = √⟨z²⟩, Ssk = ⟨z³⟩/Sq³,
    Sku = ⟨z⁴⟩/Sq⁴ with z = h − ⟨h⟩; Sdq = √⟨|∇h|²⟩.
    """
    h = np.asarray(topo.heights)
    z = h[np.isfinite(h)]
    z = z - z.mean()
    st = to_surface_topography(make_topography(h - np.nanmean(h), dx=topo.dx, dy=topo.dy))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sq = float(st.rms_height_from_area())
        sdq = float(st.rms_gradient())
    m2 = float(np.mean(z**2))
    return {
        "Sa": float(np.mean(np.abs(z))),
        "Sq": sq,
        "Sdq": sdq,
        "Ssk": float(np.mean(z**3) / m2**1.5) if m2 > 0 else 0.0,
        "Sku": float(np.mean(z**4) / m2**2) if m2 > 0 else 0.0,
    }


#: The definitions of Sdq on a map with missing pixels compared by :func:`sdq_spread`.
SDQ_DEFINITIONS: dict[str, str] = {
    "skipped": "finite differences, undefined pairs skipped (SurfaceTopography rms_gradient; "
    "the Sdq skisnow prints)",
    "joint": "finite differences at pixels whose x and y differences are both defined",
    "components": "mean square x and y differences averaged separately over their defined pairs",
    "filled": "holes filled by harmonic interpolation first (the smoothest surface meeting the "
    "holes' rims), then every pair",
}


@dataclass(frozen=True)
class SdqSpread:
    """Sdq of a map with missing pixels under each reasonable treatment of its holes.

    ``values`` maps each definition of :data:`SDQ_DEFINITIONS` to its Sdq; ``low``/``high``
    their range; ``sdq`` the value skisnow reports (``skipped``). ``digits`` is the number of
    significant digits the reported value is worth: its last digit at the order of the range.
    """

    missing: int
    sdq: float
    values: dict[str, float]
    low: float
    high: float

    @property
    def relative(self) -> float:
        """(high − low) / sdq."""
        return (self.high - self.low) / self.sdq if self.sdq > 0 else float("nan")

    @property
    def digits(self) -> int:
        """Significant digits of ``sdq`` worth printing (≥ 1): the last one at the range's order."""
        width = self.high - self.low
        if not (width > 0 and self.sdq > 0):
            return 4
        return max(1, int(np.floor(np.log10(self.sdq)) - np.floor(np.log10(width))) + 1)

    def as_dict(self) -> dict[str, object]:
        """Plain dictionary (JSON): the definitions with their values, the range, the digits."""
        return {
            "missing_pixels": self.missing,
            "reported": "skipped",
            "definitions": {
                k: {"Sdq": v, "treatment": SDQ_DEFINITIONS[k]} for k, v in self.values.items()
            },
            "low": self.low,
            "high": self.high,
            "relative_spread": self.relative,
            "significant_digits": self.digits,
        }


def sdq_spread(topo: Topography) -> SdqSpread | None:
    """How much Sdq = √⟨|∇h|²⟩ of a map with missing pixels depends on how its holes are treated.

    A slope needs two neighbouring pixels; a hole removes the pairs around it, and the
    reasonable definitions (:data:`SDQ_DEFINITIONS`: skip the undefined pairs as
    SurfaceTopography's ``rms_gradient`` does; only pixels where both components are defined;
    each component over its own defined pairs; the holes filled by harmonic interpolation,
    SurfaceTopography ``interpolate_undefined_data('harmonic')``) then differ. On a complete
    map they agree up to the edge pairs and there is nothing to report: ``None``.

    The harmonic fill minimises the sum of squared differences inside the holes for the given
    rims (Dirichlet's principle), so ``filled`` is at most the Sdq of any surface that meets
    the rims; the skipping definitions are averages over the defined pairs, unbiased only if
    the holes sit at pixels of typical slope (optical profilers lose the steepest ones).

    Parameters
    ----------
    topo
        the map as the roughness parameters see it (:func:`prepare`), holes as NaN.

    Returns
    -------
    SdqSpread or None
        ``None`` when no pixel is missing.
    """
    if topo.n_missing == 0:
        return None
    h = np.asarray(topo.heights, dtype=np.float64)
    h = h - np.nanmean(h)
    gx = np.diff(h, axis=0) / topo.dx
    gy = np.diff(h, axis=1) / topo.dy
    filled = fill_missing(make_topography(h, dx=topo.dx, dy=topo.dy))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        skipped = float(to_surface_topography(make_topography(h, dx=topo.dx, dy=topo.dy))
                        .rms_gradient())  # fmt: skip
        full = float(to_surface_topography(filled).rms_gradient())
        values = {
            "skipped": skipped,
            "joint": float(np.sqrt(np.nanmean(gx[:, :-1] ** 2 + gy[:-1, :] ** 2))),
            "components": float(np.sqrt(np.nanmean(gx**2) + np.nanmean(gy**2))),
            "filled": full,
        }
    v = np.array(list(values.values()))
    return SdqSpread(missing=int(topo.n_missing), sdq=skipped, values=values,
                     low=float(v.min()), high=float(v.max()))  # fmt: skip


def line_parameters(topo: Topography, *, axis: int = 0, n_sampling: int = 5) -> dict[str, float]:
    """Line roughness Ra, Rz (ISO 4287, ``n_sampling`` sampling lengths) and Rt, averaged over
    all complete profiles along ``axis`` (0: across the ski, i.e. across linear grooves).

    Each profile's least-squares mean line is removed first (vectorised over profiles)."""
    h = np.asarray(topo.heights)
    lines = np.moveaxis(h, axis, 0).T  # (n_lines, n_points)
    lines = lines[np.isfinite(lines).all(axis=1)]
    if lines.shape[0] == 0 or lines.shape[1] < 2 * n_sampling:
        raise InputError(f"{topo.source}: no complete profile along axis {axis}")
    x = np.arange(lines.shape[1], dtype=np.float64)
    xc = x - x.mean()
    slope = (lines @ xc) / (xc @ xc)
    r = lines - lines.mean(axis=1, keepdims=True) - slope[:, None] * xc[None, :]
    ra = np.mean(np.abs(r), axis=1)
    rt = r.max(axis=1) - r.min(axis=1)
    parts = np.array_split(np.arange(r.shape[1]), n_sampling)
    rz = np.mean([r[:, p].max(axis=1) - r[:, p].min(axis=1) for p in parts], axis=0)
    return {"Ra": float(ra.mean()), "Rz": float(rz.mean()), "Rt": float(rt.mean())}


def prepare(
    topo: Topography,
    *,
    cutoff: float | None = DEFAULT_CUTOFF,
    form: str = "plane",
    degree: int = 2,
) -> Topography:
    """A topography as the roughness parameters and both contact models see it (Scherge et al.
    2021, §2.2): form removal (``'mean'``, ``'plane'``, ``'polynomial'`` of ``degree``,
    :func:`~skisnow.micro.remove_form`), then the Fourier low-pass with ``cutoff`` [m]
    (:func:`lowpass`; ``None``: no filter). The one preparation of skisnow: :func:`roughness`,
    ``skisnow topo`` and ``skisnow bearing`` and the examples call it."""
    t = remove_form(topo, method=form, degree=degree)
    return t if cutoff is None else lowpass(t, cutoff=cutoff)


def roughness(
    topo: Topography,
    *,
    cutoff: float | None = DEFAULT_CUTOFF,
    form: str = "plane",
    degree: int = 2,
) -> Roughness:
    """All roughness parameters as Scherge et al. (2021) quote them: the map prepared by
    :func:`prepare` (form removal, then the Fourier low-pass with ``cutoff`` [m], ``None``: no
    filter), then Sa, Sq, Sdq, Ssk, Sku and the line values Ra, Rz, Rt across the ski."""
    t = prepare(topo, cutoff=cutoff, form=form, degree=degree)
    a = areal_parameters(t)
    line = line_parameters(t, axis=0)
    return Roughness(**a, **line, cutoff=cutoff, form=form)
