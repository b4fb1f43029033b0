"""Compact binary packing of explorer data: what the page decodes in the browser.

Curves along the ski (pressure, ski base, snow surface) are quantised per grid point to at most
±16000 steps of a per-point scale (so that successive differences fit in int16), stored as int16
deltas along the stations with their low and high bytes in separate planes, and the whole blob is
gzip-compressed: away from the contact the pressure is zero and the curves are smooth, so the
deltas are mostly 0 or ±1 and compress to a few bits a station. Metrics are float32. Everything is
pure NumPy; :func:`unpack` is the exact Python mirror of the page's decoder (used by the tests).
"""

from __future__ import annotations

import gzip
from collections.abc import Mapping
from typing import Any

import numpy as np

#: Largest quantised magnitude: differences of two such values fit in int16.
QMAX = 16000


def quantise_curves(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-row scale and integer levels of curves ``values`` (..., n_station).

    Returns ``(levels, scale)`` with ``levels`` int32 in [−QMAX, QMAX] and ``scale`` float32 of
    shape ``values.shape[:-1]`` such that ``levels * scale`` ≈ ``values`` to within half a step.
    Non-finite values (points not solved) become 0 with scale 0.
    """
    v = np.asarray(values, dtype=np.float64)
    finite = np.isfinite(v)
    v = np.where(finite, v, 0.0)
    peak = np.abs(v).max(axis=-1)
    scale = np.where(peak > 0, peak / QMAX, 0.0).astype(np.float32)
    # levels against the float32 scale that is stored, so that levels × scale is what is decoded
    # (rows below float32's range, |v| < 1e-41, have scale 0 and decode to 0)
    safe = np.where(scale > 0, scale, np.inf).astype(np.float64)
    levels = np.rint(v / safe[..., None]).astype(np.int32)
    np.clip(levels, -QMAX, QMAX, out=levels)
    return levels, scale


def delta_planes(levels: np.ndarray) -> bytes:
    """int16 deltas of ``levels`` along the last axis (first element absolute), as two byte
    planes: all low bytes, then all high bytes (C order)."""
    lv = np.asarray(levels, dtype=np.int32)
    d = np.diff(lv, axis=-1, prepend=0).astype(np.int16).ravel()
    u = d.view(np.uint16)
    return (u & 0xFF).astype(np.uint8).tobytes() + (u >> 8).astype(np.uint8).tobytes()


def pack(
    curves: Mapping[str, np.ndarray], arrays: Mapping[str, np.ndarray]
) -> tuple[dict[str, Any], bytes]:
    """Pack ``curves`` (float, quantised, delta-coded; each adds ``<name>_scale``) and plain
    ``arrays`` (float32 / uint8 / int32 as given) into one gzip blob and its manifest.

    Returns ``(manifest, blob)``: ``manifest[name] = {offset, nbytes, shape, dtype, codec}``
    with offsets into the *decompressed* buffer, 8-byte aligned.
    """
    parts: list[bytes] = []
    manifest: dict[str, Any] = {}
    offset = 0

    def add(name: str, raw: bytes, shape: tuple[int, ...], dtype: str, codec: str) -> None:
        nonlocal offset
        manifest[name] = {
            "offset": offset,
            "nbytes": len(raw),
            "shape": [int(s) for s in shape],
            "dtype": dtype,
            "codec": codec,
        }
        pad = (-len(raw)) % 8
        parts.append(raw + b"\0" * pad)
        offset += len(raw) + pad

    for name, values in curves.items():
        levels, scale = quantise_curves(values)
        add(name, delta_planes(levels), levels.shape, "int16", "delta16")
        add(f"{name}_scale", scale.tobytes(), scale.shape, "float32", "raw")
    for name, values in arrays.items():
        a = np.ascontiguousarray(values)
        if a.dtype == np.bool_ or (a.dtype.kind in "iu" and a.dtype.itemsize == 1):
            a = a.astype(np.uint8)  # flags and small codes (0..255) as bytes
        elif a.dtype.kind == "f":
            a = a.astype(np.float32)
        elif a.dtype.kind in "iu" and a.dtype != np.uint8:
            a = a.astype(np.int32)
        add(name, a.tobytes(), a.shape, a.dtype.name, "raw")
    # level 6 (zlib's default): 2 % larger than level 9 on the default page, 3.5x faster
    return manifest, gzip.compress(b"".join(parts), compresslevel=6, mtime=0)


def unpack(manifest: Mapping[str, Any], blob: bytes) -> dict[str, np.ndarray]:
    """Decode a :func:`pack` blob exactly as the explorer page does (curves scaled back)."""
    raw = gzip.decompress(blob)
    out: dict[str, np.ndarray] = {}
    for name, a in manifest.items():
        buf = raw[a["offset"] : a["offset"] + a["nbytes"]]
        shape = tuple(a["shape"])
        if a["codec"] == "delta16":
            n = int(np.prod(shape))
            lo = np.frombuffer(buf[:n], dtype=np.uint8).astype(np.uint16)
            hi = np.frombuffer(buf[n : 2 * n], dtype=np.uint8).astype(np.uint16)
            d = (lo | (hi << 8)).view(np.int16).astype(np.int64).reshape(shape)
            out[name] = np.cumsum(d, axis=-1)
        else:
            out[name] = np.frombuffer(buf, dtype=a["dtype"]).reshape(shape)
    for name, a in manifest.items():
        if a["codec"] == "delta16":
            out[name] = out[name] * out[f"{name}_scale"][..., None].astype(np.float64)
    return out
