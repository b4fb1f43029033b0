"""Topography maps of a ski base: the container, file input/output, missing pixels, form removal.

Conventions (used by the whole micro package):

* ``heights[i, j]`` is the height [m] at ``x = i·dx``, ``y = j·dy``; axis 0 (x) runs ACROSS the
  ski, axis 1 (y) ALONG the ski (the sliding direction). Linear grinds have grooves along y, so
  their line roughness is measured along x.
* Heights point OUT of the base, toward the snow: ridges of the grind are maxima.
* Missing (undefined) pixels are ``NaN``. Roughness is computed on the defined pixels only
  (SurfaceTopography's masked-array handling); the bearing model needs a complete map and fills
  them by harmonic interpolation (:func:`fill_missing`, SurfaceTopography's
  ``interpolate_undefined_data('harmonic')``: each missing pixel is the mean of its neighbours,
  i.e. a discrete Laplace equation with the defined pixels as boundary values).

Instrument files are read by SurfaceTopography (``read_topography``; it detects ~40 formats,
among them Wyko/Bruker ``.opd``, Digital Surf ``.sur``, ``.x3p``, Zygo ``.datx``, Sensofar
``.plu``, Alicona ``.al3d``) and converted to metres. ``.npy`` files and plain text matrices carry
no pixel size, so the caller must give one (``pixel_size``); they are read with NumPy so that the
matrix orientation is the file's (row = axis 0), which SurfaceTopography's text reader transposes.
"""

from __future__ import annotations

import struct
import warnings
import xml.etree.ElementTree
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from skisnow._errors import FileFormatError, InputError

#: what corrupt or truncated files raise deep inside SurfaceTopography's vendor readers (binary
#: layouts read with struct/numpy, XML and zip containers, text headers)
_VENDOR_READ_ERRORS = (
    ValueError,  # numpy reshapes of short buffers, bad numbers, UnicodeDecodeError
    OSError,
    EOFError,
    KeyError,
    IndexError,
    TypeError,
    AttributeError,
    RuntimeError,
    ArithmeticError,
    struct.error,
    zipfile.BadZipFile,
    xml.etree.ElementTree.ParseError,
)

__all__ = [
    "Topography",
    "fill_missing",
    "make_topography",
    "read_topography",
    "remove_form",
    "to_surface_topography",
    "write_topography",
]

_TEXT_SUFFIXES = {".txt", ".csv", ".asc", ".dat"}
_UNIT_TO_M = {"m": 1.0, "mm": 1e-3, "µm": 1e-6, "um": 1e-6, "nm": 1e-9, "pm": 1e-12, "Å": 1e-10}


@dataclass(frozen=True, eq=False)
class Topography:
    """A height map on a uniform grid (SI units).

    Attributes
    ----------
    heights
        ``(nx, ny)`` float array [m]; ``NaN`` marks missing pixels.
    dx, dy
        Pixel sizes [m] along axis 0 (across the ski) and axis 1 (along the ski).
    source
        Where the map came from (file name, preset name, ``"<array>"``), used in messages.
    """

    heights: np.ndarray
    dx: float
    dy: float
    source: str = "<array>"

    @property
    def shape(self) -> tuple[int, int]:
        """Grid points ``(nx, ny)``."""
        return self.heights.shape  # type: ignore[return-value]

    @property
    def size(self) -> tuple[float, float]:
        """Physical size ``(nx·dx, ny·dy)`` [m]."""
        return (self.shape[0] * self.dx, self.shape[1] * self.dy)

    @property
    def missing(self) -> np.ndarray:
        """Boolean mask of the missing pixels."""
        return ~np.isfinite(self.heights)

    @property
    def n_missing(self) -> int:
        """Number of missing pixels."""
        return int(self.missing.sum())


def make_topography(
    heights: np.ndarray, *, dx: float, dy: float | None = None, source: str = "<array>"
) -> Topography:
    """Validate an array and pixel sizes [m] and wrap them in a :class:`Topography`."""
    h = np.array(heights, dtype=np.float64)
    if h.ndim != 2 or min(h.shape) < 2:
        raise InputError(f"{source}: heights must be a 2-D array of at least 2 × 2, got {h.shape}")
    dy = dx if dy is None else dy
    for name, v in (("dx", dx), ("dy", dy)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(f"{source}: pixel size {name} must be positive and finite, got {v}")
    if np.isinf(h).any():
        raise InputError(f"{source}: heights contain infinite values")
    if not np.isfinite(h).any():
        raise InputError(f"{source}: every pixel is missing")
    h.setflags(write=False)
    return Topography(heights=h, dx=float(dx), dy=float(dy), source=source)


def _import_surface_topography():  # -> module
    """Import SurfaceTopography quietly: its MPI layer (NuMPI) warns at import time that mpi4py
    is absent and falls back to a serial stub, which is what skisnow wants."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import SurfaceTopography
        from SurfaceTopography import open_topography  # noqa: F401  (loads the readers)
    return SurfaceTopography


def _pixel_pair(pixel_size: float | tuple[float, float]) -> tuple[float, float]:
    if np.isscalar(pixel_size):
        return float(pixel_size), float(pixel_size)  # type: ignore[arg-type]
    px, py = pixel_size  # type: ignore[misc]
    return float(px), float(py)


def read_topography(
    path: str | Path,
    *,
    pixel_size: float | tuple[float, float] | None = None,
    height_unit: str = "m",
    channel: int = 0,
) -> Topography:
    """Read a topography file into a :class:`Topography` in metres.

    Parameters
    ----------
    path
        An instrument file (any format SurfaceTopography detects), a ``.npy`` array or a text
        matrix (``.txt``, ``.csv``, ``.asc``, ``.dat``).
    pixel_size
        Pixel size [m] (one value or ``(dx, dy)``). Required for ``.npy``; for text matrices it
        selects the plain NumPy reader (row = axis 0). Ignored for instrument files, whose
        pixel size is in the file.
    height_unit
        Unit of the heights in ``.npy`` and text matrices (``m``, ``mm``, ``um``, ``nm``).
    channel
        Data channel of multi-channel instrument files.

    Raises
    ------
    FileFormatError
        The file is missing, of an unknown format, corrupt or truncated (the message names it).
    """
    path = Path(path)
    name = str(path)
    if not path.is_file():
        raise FileFormatError(f"{name}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".npy" or (suffix in _TEXT_SUFFIXES and pixel_size is not None):
        if pixel_size is None:
            raise InputError(
                f"{name}: a .npy array carries no pixel size; give pixel_size (CLI: --pixel-um)"
            )
        if height_unit not in _UNIT_TO_M:
            raise InputError(f"height_unit {height_unit!r} unknown; valid: {sorted(_UNIT_TO_M)}")
        try:
            arr = np.load(path, allow_pickle=False) if suffix == ".npy" else _load_text(path)
        except FileFormatError:
            raise
        except (ValueError, EOFError, OSError) as exc:  # what numpy raises for bad files
            raise FileFormatError(f"{name}: cannot read as {suffix} matrix ({exc})") from exc
        if arr.ndim != 2 or not np.issubdtype(arr.dtype, np.number):
            raise FileFormatError(f"{name}: expected a 2-D numeric matrix, got {arr.shape}")
        dx, dy = _pixel_pair(pixel_size)
        return make_topography(arr * _UNIT_TO_M[height_unit], dx=dx, dy=dy, source=name)
    return _read_with_surface_topography(path, channel=channel)


def _load_text(path: Path) -> np.ndarray:
    with open(path, encoding="utf-8", errors="strict") as fh:
        first = ""
        for line in fh:
            if line.strip() and not line.lstrip().startswith("#"):
                first = line
                break
    delimiter = "," if "," in first else None
    return np.loadtxt(path, delimiter=delimiter, comments="#", ndmin=2)


def _read_with_surface_topography(path: Path, *, channel: int) -> Topography:
    name = str(path)
    try:
        st = _import_surface_topography()
        from SurfaceTopography.Exceptions import ReadFileError

        open_topography = st.open_topography
    except ImportError as exc:  # pragma: no cover - it is a hard dependency
        raise FileFormatError(f"{name}: SurfaceTopography is needed to read it ({exc})") from exc
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # readers warn about vendor metadata quirks
            reader = open_topography(str(path))
            if not 0 <= channel < len(reader.channels):
                raise FileFormatError(
                    f"{name}: channel {channel} does not exist; the file has "
                    f"{len(reader.channels)} channel(s)"
                )
            topo = reader.topography(channel_index=channel)
            if topo.dim != 2:
                raise FileFormatError(f"{name}: holds a line scan, not an areal topography")
            if not topo.is_uniform:
                raise FileFormatError(f"{name}: non-uniform grids are not supported")
            topo = topo.to_unit("m")
            heights = topo.heights()
            dx, dy = (float(v) for v in topo.pixel_size)
    except FileFormatError:
        raise
    except ReadFileError as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise FileFormatError(f"{name}: unknown or unreadable topography format ({first})") from exc
    except _VENDOR_READ_ERRORS as exc:  # corrupt or truncated files fail deep in the readers
        raise FileFormatError(
            f"{name}: corrupt or truncated topography file ({type(exc).__name__}: {exc})"
        ) from exc
    h = np.ma.filled(np.ma.asarray(heights, dtype=np.float64), np.nan)
    return make_topography(h, dx=dx, dy=dy, source=name)


def write_topography(topo: Topography, path: str | Path) -> Path:
    """Write a topography: ``.x3p`` (ISO 25178-72, via SurfaceTopography; carries the pixel
    size), ``.npy`` or text (``.txt``/``.csv``; heights in metres, row = axis 0 — reading them
    back needs the pixel size). Returns the path."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".x3p":
        st = to_surface_topography(fill_missing(topo) if topo.n_missing else topo)
        st.to_x3p(str(path))
    elif suffix == ".npy":
        np.save(path, np.asarray(topo.heights))
    elif suffix in {".txt", ".csv"}:
        np.savetxt(
            path,
            topo.heights,
            delimiter="," if suffix == ".csv" else " ",
            header=f"skisnow topography, heights in m, dx={topo.dx!r} m, dy={topo.dy!r} m",
        )
    else:
        raise InputError(f"{path}: output format {suffix!r} unknown; valid: .x3p, .npy, .txt, .csv")
    return path


def to_surface_topography(topo: Topography):  # -> SurfaceTopography.Topography
    """The same map as a (non-periodic) SurfaceTopography ``Topography`` in metres; missing
    pixels become masked."""
    STTopography = _import_surface_topography().Topography

    h = np.ma.masked_invalid(np.asarray(topo.heights))
    if not np.ma.is_masked(h):
        h = np.asarray(topo.heights)
    return STTopography(h, topo.size, periodic=False, unit="m")


def fill_missing(topo: Topography) -> Topography:
    """Fill missing pixels by harmonic interpolation (SurfaceTopography
    ``interpolate_undefined_data('harmonic')``); a complete map is returned unchanged."""
    if topo.n_missing == 0:
        return topo
    st = to_surface_topography(topo)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        filled = st.interpolate_undefined_data("harmonic").heights()
    return make_topography(np.asarray(filled), dx=topo.dx, dy=topo.dy, source=topo.source)


def remove_form(topo: Topography, *, method: str = "plane", degree: int = 2) -> Topography:
    """Remove the form: ``'mean'``, ``'plane'`` (least-squares plane) or ``'polynomial'``
    (least-squares bivariate polynomial of total ``degree``), fitted to the defined pixels.

    The fit uses coordinates normalised to [0, 1] for conditioning (the same choice as
    SurfaceTopography's ``detrend``, whose 'center' and 'height' modes this reproduces).
    """
    valid = np.isfinite(topo.heights)
    h = np.asarray(topo.heights)
    if method == "mean":
        out = h - h[valid].mean()
    elif method in ("plane", "polynomial"):
        deg = 1 if method == "plane" else int(degree)
        if deg < 0:
            raise InputError(f"degree must be >= 0, got {degree}")
        nx, ny = h.shape
        x = (np.arange(nx) / max(nx - 1, 1))[:, None] * np.ones((1, ny))
        y = (np.arange(ny) / max(ny - 1, 1))[None, :] * np.ones((nx, 1))
        terms = [(i, k - i) for k in range(deg + 1) for i in range(k + 1)]
        basis = np.stack([x[valid] ** i * y[valid] ** j for i, j in terms], axis=1)
        coef, *_ = np.linalg.lstsq(basis, h[valid], rcond=None)
        form = sum(c * x**i * y**j for c, (i, j) in zip(coef, terms, strict=True))
        out = h - form
    else:
        raise InputError(f"form removal {method!r} unknown; valid: 'mean', 'plane', 'polynomial'")
    return make_topography(out, dx=topo.dx, dy=topo.dy, source=topo.source)
