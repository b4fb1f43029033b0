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

from skisnow._checks import check_value
from skisnow._errors import FileFormatError, InputError
from skisnow._json import read_json_file
from skisnow._resources import check_npy_header, load_npz

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
    if height_unit not in _UNIT_TO_M:
        raise InputError(
            f"{name}: height unit {height_unit!r} unknown (CLI: --height-unit); valid: "
            f"{', '.join(sorted(_UNIT_TO_M))}"
        )
    if suffix == ".npz":
        return _read_npz(path)
    if suffix == ".npy" or (suffix in _TEXT_SUFFIXES and pixel_size is not None):
        if _is_zip(path):
            raise FileFormatError(
                f"{name}: this is a .npz archive (zip), not a .npy array; rename it to .npz "
                "(skisnow reads the 'heights', 'dx_m', 'dy_m' of its own .npz files)"
            )
        sidecar = _read_sidecar(path)
        if pixel_size is not None and sidecar is not None:
            given = _pixel_pair(pixel_size)
            if not np.allclose(given, sidecar, rtol=1e-6) or height_unit != "m":
                raise InputError(
                    f"{name}: the pixel size {given[0] * 1e6:g} × {given[1] * 1e6:g} µm "
                    f"(--pixel-um) and height unit {height_unit!r} (--height-unit) contradict "
                    f"its side-car {_sidecar(path).name} ({sidecar[0] * 1e6:g} × "
                    f"{sidecar[1] * 1e6:g} µm, heights in m); drop the options or correct the "
                    "side-car"
                )
        if pixel_size is None and sidecar is None:
            raise InputError(
                f"{name}: a {suffix} matrix carries no pixel size and has no {_sidecar(path).name} "
                "beside it; give the pixel size (CLI: --pixel-um)"
            )
        if sidecar is not None:
            pixel_size, height_unit = (sidecar[0], sidecar[1]), "m"
        try:
            if suffix == ".npy":
                check_npy_header(path)  # the header's shape against memory, before reading
            arr = np.load(path, allow_pickle=False) if suffix == ".npy" else _load_text(path)
        except FileFormatError:
            raise
        except (ValueError, EOFError, OSError) as exc:  # what numpy raises for bad files
            why = (
                "holds Python objects (pickle), which skisnow never loads"
                if ("allow_pickle" in str(exc))
                else f"truncated or not a {suffix} matrix ({exc})"
            )
            raise FileFormatError(f"{name}: cannot read: {why}") from None
        if arr.ndim != 2 or not (
            np.issubdtype(arr.dtype, np.floating) or np.issubdtype(arr.dtype, np.integer)
        ):
            raise FileFormatError(
                f"{name}: expected a 2-D matrix of real heights, got shape {arr.shape} of "
                f"{arr.dtype}"
            )
        dx, dy = _pixel_pair(pixel_size)
        heights = arr.astype(np.float64) * _UNIT_TO_M[height_unit]
        _check_heights(heights, name, height_unit)
        return make_topography(heights, dx=dx, dy=dy, source=name)
    if suffix in _TEXT_SUFFIXES:
        header = _text_header_pixel(path)
        if header is not None:
            heights = _load_text(path)
            _check_heights(heights, name, "m")
            return make_topography(heights, dx=header[0], dy=header[1], source=name)
    return _read_with_surface_topography(path, channel=channel)


def _is_zip(path: Path) -> bool:
    with open(path, "rb") as fh:
        return fh.read(4) == b"PK\x03\x04"


def _sidecar(path: Path) -> Path:
    """The pixel-size sidecar of a ``.npy``/text matrix: ``NAME.npy.json``."""
    return path.with_name(path.name + ".json")


def _read_sidecar(path: Path) -> tuple[float, float] | None:
    side = _sidecar(path)
    if not side.is_file():
        return None
    doc = read_json_file(side, what="topography side-car", max_bytes=1 << 20)
    try:
        dx, dy = float(doc["dx_m"]), float(doc["dy_m"])
        if doc.get("height_unit", "m") != "m":
            raise ValueError("height_unit must be 'm'")
    except (ValueError, KeyError, TypeError) as exc:
        raise FileFormatError(
            f"{side}: not a skisnow topography sidecar (need a JSON object with dx_m, dy_m in "
            f"metres; {exc})"
        ) from None
    for key, v in (("dx_m", dx), ("dy_m", dy)):  # checked in µm, the unit of --pixel-um
        check_value(v * 1e6, "pixel", where=f"{side}: {key} = {v:g} m")
    return dx, dy


def _text_header_pixel(path: Path) -> tuple[float, float] | None:
    """The pixel size from the header line :func:`write_topography` puts in text matrices."""
    import re

    try:
        with open(path, encoding="utf-8-sig", errors="replace") as fh:
            first = fh.readline()
    except OSError:
        return None
    m = re.search(r"skisnow topography.*dx=([^ ]+) m, dy=([^ ]+) m", first)
    return (float(m.group(1)), float(m.group(2))) if m else None


def _read_npz(path: Path) -> Topography:
    name = str(path)
    try:
        f = load_npz(path, where=name, keys=("heights", "dx_m", "dy_m"))  # headers checked first
        heights = np.asarray(f["heights"], dtype=np.float64)
        dx, dy = float(f["dx_m"]), float(f["dy_m"])
        for key, v in (("dx_m", dx), ("dy_m", dy)):
            check_value(v * 1e6, "pixel", where=f"{name}: {key} = {v:g} m")
    except KeyError as exc:
        raise FileFormatError(
            f"{name}: a skisnow .npz topography holds 'heights' [m], 'dx_m' and 'dy_m' "
            f"({exc} is missing)"
        ) from None
    except (ValueError, EOFError, OSError, TypeError) as exc:
        raise FileFormatError(f"{name}: not a readable .npz topography ({exc})") from None
    _check_heights(heights, name, "m")
    return make_topography(heights, dx=dx, dy=dy, source=name)


def _check_heights(heights: np.ndarray, name: str, unit: str) -> None:
    """A ski base's topography spans micrometres: a peak-to-valley beyond the plausible range
    means the heights were not in ``unit`` (e.g. integer counts or nanometres read as metres)."""

    finite = heights[np.isfinite(heights)]
    if finite.size:
        check_value(
            float(finite.max() - finite.min()),
            "topography_height",
            where=f"{name}: peak-to-valley height read with --height-unit {unit}",
        )


def _load_text(path: Path) -> np.ndarray:
    """A text matrix (``#`` comments; comma- or blank-separated), read line by line so that a bad
    cell is reported as the user counts: file line and column. (``np.loadtxt`` counts data rows
    only, and from 0.)"""
    try:
        lines = path.read_text(encoding="utf-8-sig").splitlines()
    except UnicodeDecodeError as exc:
        raise FileFormatError(f"{path}: not a text matrix (not UTF-8: {exc})") from None
    rows: list[list[float]] = []
    width_line = 0
    for no, line in enumerate(lines, start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        cells = text.split(",") if "," in text else text.split()
        row = []
        for col, cell in enumerate(cells, start=1):
            try:
                row.append(float(cell))
            except ValueError:
                raise FileFormatError(
                    f"{path}: line {no}, column {col}: {cell.strip()!r} is not a number (a "
                    "text matrix holds one row of heights per line)"
                ) from None
        if rows and len(row) != len(rows[0]):
            raise FileFormatError(
                f"{path}: line {no} has {len(row)} values, line {width_line} has "
                f"{len(rows[0])}; every row of a matrix needs the same number"
            )
        if not rows:
            width_line = no
        rows.append(row)
    if not rows:
        raise FileFormatError(f"{path}: no numbers (an empty text matrix)")
    return np.array(rows, dtype=np.float64)


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
        first = str(exc).strip().splitlines()[0].strip() if str(exc).strip() else ""
        detail = f" ({first})" if first and not first.endswith(":") else ""  # not "tried X: "
        raise FileFormatError(
            f"{name}: unknown, truncated or corrupt topography file: no reader accepts it"
            f"{detail}. Readable: instrument files SurfaceTopography knows (.x3p, .opd, .plu, "
            ".sur, .al3d, .datx, ...), skisnow's .npz, or a .npy/text matrix with --pixel-um"
        ) from None
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
    import json

    from skisnow._atomic import atomic_path, atomic_write

    if suffix not in {".x3p", ".npy", ".npz", ".txt", ".csv"}:
        raise InputError(
            f"{path}: output format {suffix!r} unknown; valid: .x3p, .npy, .npz, .txt, .csv"
        )
    with atomic_path(path) as tmp:
        if suffix == ".x3p":
            st = to_surface_topography(fill_missing(topo) if topo.n_missing else topo)
            st.to_x3p(str(tmp))
        elif suffix == ".npy":
            np.save(tmp, np.asarray(topo.heights))
        elif suffix == ".npz":
            np.savez(tmp, heights=np.asarray(topo.heights), dx_m=topo.dx, dy_m=topo.dy)
        else:
            np.savetxt(
                tmp,
                topo.heights,
                delimiter="," if suffix == ".csv" else " ",
                header=f"skisnow topography, heights in m, dx={topo.dx!r} m, dy={topo.dy!r} m",
            )
    if suffix == ".npy":  # a bare array: its pixel size goes beside it
        doc = {"format": "skisnow-topography", "dx_m": topo.dx, "dy_m": topo.dy,
               "height_unit": "m"}  # fmt: skip
        atomic_write(_sidecar(path), json.dumps(doc) + "\n")
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
