"""Model files: weights as ``.npz`` (float arrays only, never pickle) plus ``.json`` metadata.

A model ``PATH`` is the pair ``PATH.npz`` + ``PATH.json``. The JSON document records the sha256
of the ``.npz`` bytes, so a truncated or corrupted weights file is detected before it is parsed;
``np.load(..., allow_pickle=False)`` refuses object arrays. This module knows nothing about what
the arrays mean (see :mod:`skisnow.ski._network`); it only reads and writes them safely.
"""

from __future__ import annotations

import hashlib
import io
import json
import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._errors import FileFormatError

__all__ = ["model_paths", "parse_model_bytes", "read_model_files", "write_model_files"]


def model_paths(path: str | Path) -> tuple[Path, Path]:
    """``(PATH.npz, PATH.json)`` for a model path given with or without a suffix."""
    p = Path(path)
    if p.suffix in (".npz", ".json"):
        p = p.with_suffix("")
    return p.with_name(p.name + ".npz"), p.with_name(p.name + ".json")


def write_model_files(
    path: str | Path, arrays: Mapping[str, np.ndarray], metadata: Mapping[str, Any]
) -> tuple[Path, Path]:
    """Write the arrays (``.npz``, uncompressed) and the metadata plus the weights' sha256
    (``.json``). Returns the two paths."""
    npz_path, json_path = model_paths(path)
    buf = io.BytesIO()
    np.savez(buf, **{k: np.ascontiguousarray(v, dtype=np.float64) for k, v in arrays.items()})
    data = buf.getvalue()
    doc = dict(metadata)
    doc["weights_sha256"] = hashlib.sha256(data).hexdigest()
    npz_path.parent.mkdir(parents=True, exist_ok=True)
    npz_path.write_bytes(data)
    json_path.write_text(json.dumps(doc, indent=2, allow_nan=False) + "\n", encoding="utf-8")
    return npz_path, json_path


def parse_model_bytes(
    npz: bytes, text: str, where: str
) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Check and parse the two files' contents; ``where`` names them in error messages."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise FileFormatError(f"{where}.json: not valid JSON ({exc})") from None
    if not isinstance(doc, dict):
        raise FileFormatError(f"{where}.json: expected a JSON object, got {type(doc).__name__}")
    expected = doc.get("weights_sha256")
    actual = hashlib.sha256(npz).hexdigest()
    if expected != actual:
        raise FileFormatError(
            f"{where}.npz: weights file is corrupt or truncated, or does not belong to "
            f"{where}.json (sha256 {actual[:12]}…, metadata says {str(expected)[:12]}…)"
        )
    try:
        with np.load(io.BytesIO(npz), allow_pickle=False) as f:
            arrays = {k: f[k] for k in f.files}
    except (ValueError, OSError, zipfile.BadZipFile, EOFError) as exc:
        raise FileFormatError(f"{where}.npz: cannot read the weights ({exc})") from None
    return arrays, doc


def read_model_files(path: str | Path) -> tuple[dict[str, np.ndarray], dict[str, Any], str]:
    """Read ``PATH.npz`` + ``PATH.json``; return (arrays, metadata, display name)."""
    npz_path, json_path = model_paths(path)
    where = str(npz_path.with_suffix(""))
    for p in (npz_path, json_path):
        if not p.is_file():
            raise FileFormatError(
                f"model file {p} not found (a model is the pair PATH.npz + PATH.json)"
            )
    try:
        text = json_path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise FileFormatError(f"{json_path}: not UTF-8 text ({exc})") from None
    arrays, doc = parse_model_bytes(npz_path.read_bytes(), text, where)
    return arrays, doc, where
