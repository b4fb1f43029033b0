"""The camber network's file format: weights as ``.npz`` (float arrays only, never pickle) plus
``.json`` metadata.

A model ``PATH`` is the pair ``PATH.npz`` + ``PATH.json``. The JSON document records the sha256
of the ``.npz`` bytes, so a truncated or corrupted weights file is detected before it is parsed;
``np.load(..., allow_pickle=False)`` refuses object arrays.

Two layers: :func:`write_model_files` / :func:`read_model_files` / :func:`parse_model_bytes`
move arrays and a JSON document safely and know nothing of their meaning; :func:`save_network`,
:func:`load_network` and :func:`shipped_network` map a :class:`skisnow.network.CamberNetwork` (the
model, which knows nothing of files) to and from that layout. Array names:
``member{k}/{layer}/weight|bias`` (layers as :meth:`skisnow.network.BlockNetwork.layers` names them)
and ``reference/height``.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
from collections.abc import Mapping
from dataclasses import asdict
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from skisnow._checks import check_value
from skisnow._errors import FileFormatError, InputError, SolverStatus
from skisnow._json import load_json
from skisnow._resources import load_npz

if TYPE_CHECKING:
    from skisnow.network._network import BlockNetwork, CamberNetwork

__all__ = [
    "MODEL_FORMAT",
    "MODEL_FORMAT_VERSION",
    "load_network",
    "metadata_checksum",
    "model_paths",
    "network_arrays",
    "network_from_files",
    "parse_model_bytes",
    "read_model_files",
    "save_network",
    "shipped_network",
    "write_model_files",
]

#: Name of the model file layout written by :func:`save_network`.
MODEL_FORMAT = "skisnow-camber-network"
#: Version of that layout (bump on incompatible change).
MODEL_FORMAT_VERSION = 1
#: Package whose ``models/`` directory holds the pretrained networks of the shipped skis.
MODELS_PACKAGE = "skisnow.network"


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
    doc = {k: v for k, v in metadata.items() if k not in _CHECKSUMS}
    doc["weights_sha256"] = hashlib.sha256(data).hexdigest()
    doc["metadata_sha256"] = metadata_checksum(doc)
    from skisnow._atomic import atomic_write

    # each file whole or not at all; the JSON last, so a pair is complete once the JSON exists
    atomic_write(npz_path, data)
    atomic_write(json_path, json.dumps(doc, indent=2, allow_nan=False) + "\n")
    return npz_path, json_path


#: The checksum keys of a model's JSON document (not covered by the metadata checksum).
_CHECKSUMS = ("metadata_sha256",)


def metadata_checksum(doc: Mapping[str, Any]) -> str:
    """sha256 of everything in the JSON document that defines the model (architecture,
    scaling, trained domain, reference window, training record and the weights' own sha256):
    its canonical JSON (sorted keys, no whitespace, strict floats). Editing any of it, e.g.
    widening the trained domain, fails the check."""
    body = {k: v for k, v in doc.items() if k not in _CHECKSUMS}
    try:
        text = json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False)
    except ValueError:  # NaN/inf somewhere: never a document skisnow wrote
        text = json.dumps(body, sort_keys=True, separators=(",", ":"))
        return "nonfinite:" + hashlib.sha256(text.encode("utf-8")).hexdigest()
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def parse_model_bytes(
    npz: bytes, text: str, where: str
) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Check and parse the two files' contents; ``where`` names them in error messages."""
    doc = load_json(text, where=f"{where}.json")
    if not isinstance(doc, dict):
        raise FileFormatError(f"{where}.json: expected a JSON object, got {type(doc).__name__}")
    declared = doc.get("metadata_sha256")
    # (a file of another format version is refused by its version, with its own message)
    same_version = (
        doc.get("format") == MODEL_FORMAT and doc.get("format_version") == MODEL_FORMAT_VERSION
    )
    if same_version and declared != metadata_checksum(doc):
        raise FileFormatError(
            f"{where}.json: the model's metadata fails its checksum (metadata_sha256 "
            f"{'missing' if declared is None else 'differs'}): the file was edited or damaged "
            "after it was written (architecture, scaling, trained domain and training record "
            "are all covered). Retrain with `skisnow train`, or restore the file."
        )
    expected = doc.get("weights_sha256")
    actual = hashlib.sha256(npz).hexdigest()
    if expected != actual:
        raise FileFormatError(
            f"{where}.npz: weights file is corrupt or truncated, or does not belong to "
            f"{where}.json (sha256 {actual[:12]}…, metadata says {str(expected)[:12]}…)"
        )
    # headers and sizes first (a re-signed archive bomb), never pickle
    arrays = load_npz(npz, where=f"{where}.npz")
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
        text = json_path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise FileFormatError(f"{json_path}: not UTF-8 text ({exc})") from None
    arrays, doc = parse_model_bytes(npz_path.read_bytes(), text, where)
    return arrays, doc, where


# --------------------------------------------------------------------------------------------
# The camber network <-> arrays + JSON document


def network_arrays(net: CamberNetwork) -> dict[str, np.ndarray]:
    """The weights as a flat ``{name: float64 array}`` dict (the .npz content)."""
    arrays = {}
    for k, member in enumerate(net.members):
        for name, layer in member.layers():
            arrays[f"member{k}/{name}/weight"] = np.asarray(layer.weight, dtype=np.float64)
            arrays[f"member{k}/{name}/bias"] = np.asarray(layer.bias, dtype=np.float64)
    if net.reference is not None:
        arrays["reference/height"] = np.asarray(net.reference.height, dtype=np.float64)
    return arrays


def _metadata_document(net: CamberNetwork) -> dict[str, Any]:
    from skisnow import __version__

    return {
        "format": MODEL_FORMAT,
        "format_version": MODEL_FORMAT_VERSION,
        "skisnow_version": __version__,
        "architecture": {
            "load": net.architecture.load,
            "collapse": list(net.architecture.collapse),
            "camber": list(net.architecture.camber),
        },
        "n_members": len(net.members),
        "scaling": asdict(net.scaling),
        "domain": asdict(net.domain),
        "reference": None
        if net.reference is None
        else {
            "x_min": net.reference.x_min,
            "x_max": net.reference.x_max,
            "n": int(net.reference.height.size),
            # h = h_0(x) + m · network (issue 30, fifth pass); absent in older files: False
            **({"mass_scaled": True} if net.reference.mass_scaled else {}),
        },
        "metadata": dict(net.metadata),
    }


def _require(doc: Mapping[str, Any], key: str, where: str) -> Any:
    if key not in doc:
        raise FileFormatError(f"{where}: metadata key {key!r} is missing")
    return doc[key]


def _members_from_arrays(
    arrays: Mapping[str, np.ndarray], architecture: Any, n_members: int, where: str
) -> tuple[BlockNetwork, ...]:
    from skisnow.network._network import BlockNetwork

    shapes = BlockNetwork.layer_shapes(architecture)
    members = []
    for k in range(n_members):
        layers = {}
        for name, expected in shapes.items():
            parts = []
            for part, shape in zip(("weight", "bias"), expected, strict=True):
                key = f"member{k}/{name}/{part}"
                if key not in arrays:
                    raise FileFormatError(f"{where}: weight array {key!r} is missing")
                a = arrays[key]
                if a.shape != shape or a.dtype != np.float64:
                    raise FileFormatError(
                        f"{where}: array {key!r} has shape {a.shape} {a.dtype}, the "
                        f"architecture {architecture.widths} needs {shape} float64"
                    )
                if not np.all(np.isfinite(a)):
                    raise FileFormatError(f"{where}: array {key!r} holds NaN/inf")
                parts.append(a)
            layers[name] = tuple(parts)
        members.append(BlockNetwork.from_layer_arrays(architecture, layers))
    return tuple(members)


def _check_numbers(scaling: Any, domain: Any, where: str) -> None:
    """Every loaded number finite and in range: scales > 0, a trained domain with min < max
    inside what a ski and a bench can be (masses, positions, x in skisnow._checks' ranges)."""
    from skisnow._checks import QUANTITIES

    for key, value in asdict(scaling).items():
        if not np.isfinite(value) or (key.endswith("_scale") and value <= 0):
            raise FileFormatError(
                f"{where}.json: scaling.{key} = {value!r}; every scaling value must be finite "
                "and every *_scale > 0"
            )
    d = asdict(domain)
    limits = {"mass": ("mass", 1.0), "position": ("load_position", 1e3), "x": ("x", 1e3)}
    for prefix, (quantity, to_field) in limits.items():
        lo, hi = d[f"{prefix}_min"], d[f"{prefix}_max"]
        q = QUANTITIES[quantity]
        p_lo, p_hi = q.plausible
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise FileFormatError(
                f"{where}.json: domain.{prefix}_min/max = {lo!r}/{hi!r}; need finite min < max"
            )
        if lo * to_field < p_lo or hi * to_field > p_hi or (quantity == "mass" and lo <= 0):
            raise FileFormatError(
                f"{where}.json: domain.{prefix}_min/max = {lo!r}/{hi!r} lies outside the "
                f"plausible range of the {q.name}; need both within {q.describe_plausible()}"
            )


def network_from_files(
    arrays: Mapping[str, np.ndarray], doc: Mapping[str, Any], where: str
) -> CamberNetwork:
    """Rebuild a :class:`~skisnow.network.CamberNetwork` from the .npz arrays and the .json
    document.

    Raises
    ------
    FileFormatError
        Foreign format, unsupported version, missing or invalid metadata, missing arrays or
        arrays of the wrong shape, dtype or with NaN/inf; ``where`` names the files.
    """
    from skisnow.network._network import (
        Architecture,
        CamberNetwork,
        Domain,
        ReferenceProfile,
        Scaling,
    )

    if doc.get("format") != MODEL_FORMAT:
        raise FileFormatError(
            f"{where}: not a skisnow camber-network model (format {doc.get('format')!r}, "
            f"expected {MODEL_FORMAT!r})"
        )
    version = doc.get("format_version")
    if version != MODEL_FORMAT_VERSION:
        raise FileFormatError(
            f"{where}: model file format version {version!r} (written by skisnow "
            f"{doc.get('skisnow_version', '?')}) is not supported; this skisnow reads version "
            f"{MODEL_FORMAT_VERSION}. Retrain with `skisnow train`."
        )
    try:
        arch_doc = _require(doc, "architecture", where)
        architecture = Architecture(
            load=int(arch_doc["load"]),
            collapse=tuple(int(w) for w in arch_doc["collapse"]),
            camber=tuple(int(w) for w in arch_doc["camber"]),
        )
        scaling = Scaling(**{k: float(v) for k, v in _require(doc, "scaling", where).items()})
        domain = Domain(**{k: float(v) for k, v in _require(doc, "domain", where).items()})
        n_members = int(_require(doc, "n_members", where))
    except (KeyError, TypeError, ValueError) as exc:
        if isinstance(exc, FileFormatError):
            raise
        raise FileFormatError(f"{where}: invalid metadata ({exc})") from None
    if n_members < 1:
        raise FileFormatError(f"{where}: n_members must be >= 1, got {n_members}")
    check_value(n_members, "ensemble_members", where=f"{where}.json: n_members")
    for i, w in enumerate(architecture.widths):
        check_value(w, "layer_width", where=f"{where}.json: architecture, layer {i + 1}")
    _check_numbers(scaling, domain, where)
    status = doc.get("metadata", {}).get("status")
    if status is not None and status not in {s.value for s in SolverStatus}:
        raise FileFormatError(
            f"{where}: metadata status {status!r} is not one of "
            f"{', '.join(s.value for s in SolverStatus)}"
        )
    members = _members_from_arrays(arrays, architecture, n_members, where)
    reference = None
    ref_doc = doc.get("reference")
    if ref_doc is not None:
        h_ref = arrays.get("reference/height")
        try:
            n_ref, x0, x1 = int(ref_doc["n"]), float(ref_doc["x_min"]), float(ref_doc["x_max"])
        except (KeyError, TypeError, ValueError) as exc:
            raise FileFormatError(f"{where}: invalid reference-profile metadata ({exc})") from None
        if h_ref is None or h_ref.shape != (n_ref,) or not np.all(np.isfinite(h_ref)):
            raise FileFormatError(
                f"{where}: reference profile array missing or not {n_ref} finite floats"
            )
        mass_scaled = ref_doc.get("mass_scaled", False)
        if not isinstance(mass_scaled, bool):
            raise FileFormatError(f"{where}: reference 'mass_scaled' must be true or false")
        reference = ReferenceProfile(x_min=x0, x_max=x1, height=h_ref, mass_scaled=mass_scaled)
    net = CamberNetwork(
        reference=reference,
        architecture=architecture,
        scaling=scaling,
        domain=domain,
        members=members,
        metadata=dict(doc.get("metadata", {})),
    )
    # a file re-signed after an edit passes both checksums: the physics must still hold. The
    # ski sits lower under the load at the heaviest trained mass than at the lightest, and its
    # profile moves with every step of the load across the trained range (a re-scaled input
    # saturates the network: one profile for 5, 30 and 55 kg). A model whose training record
    # says it converged is held to it (anything `skisnow train` finished), and so is one that
    # ran out of its budget after a full-size Levenberg–Marquardt phase (>= 100 steps: the
    # shipped networks, trained to a step or wall-clock budget)
    steps = net.metadata.get("lm_steps_taken") or [0]
    full_budget = (
        net.status is SolverStatus.MAX_STEPS_REACHED
        and isinstance(steps, list)
        and all(isinstance(k, int) and k >= 100 for k in steps)
    )
    if net.status is None or not (net.status.successful or full_budget):
        return net  # no record of a finished training (a toy, a stopped run): not held to it
    p = 0.5 * (domain.position_min + domain.position_max)
    masses = np.linspace(domain.mass_min, domain.mass_max, 6)
    xs = np.linspace(domain.x_min, domain.x_max, 64)
    h = net.predict(np.append(xs, p), masses, p, on_domain_error="ignore", clip=False)
    moves = np.abs(np.diff(h[:, :-1], axis=0)).max(axis=1)
    if not (np.all(np.isfinite(h)) and h[-1, -1] < h[0, -1] and moves.min() > 1e-6):
        raise FileFormatError(
            f"{where}: the model does not respond to the load as a ski does (at {p * 1e3:.0f} "
            f"mm the ski sits {h[0, -1] * 1e3:.3g} mm high at {masses[0]:g} kg and "
            f"{h[-1, -1] * 1e3:.3g} mm at {masses[-1]:g} kg; the least move of the profile "
            f"between {len(masses)} masses is {moves.min() * 1e6:.3g} µm): its scaling or "
            "weights were edited and re-signed, or damaged; retrain with `skisnow train`"
        )
    return net


def save_network(net: CamberNetwork, path: str | Path) -> tuple[Path, Path]:
    """Write ``PATH.npz`` (weights) and ``PATH.json`` (metadata); return both paths.

    Parameters
    ----------
    net : CamberNetwork
        The trained network.
    path : str or Path
        The model path; may end in ``.npz``, ``.json`` or nothing.

    Returns
    -------
    tuple of Path
        ``(PATH.npz, PATH.json)``. The JSON holds the file-format version, the skisnow version,
        the architecture, scaling, domain, the sha256 of the weights file and the training
        metadata (data hash, seed, measured errors). No pickle anywhere.
    """
    return write_model_files(path, network_arrays(net), _metadata_document(net))


def load_network(path: str | Path) -> CamberNetwork:
    """Read a model written by :func:`save_network` (``PATH.npz`` + ``PATH.json``).

    Raises
    ------
    FileFormatError
        A file is missing, corrupt or truncated (the weights' sha256 is checked against the
        metadata) or from an incompatible format version.
    """
    arrays, doc, where = read_model_files(path)
    return network_from_files(arrays, doc, where)


@functools.cache
def shipped_network(ski_name: str) -> CamberNetwork:
    """The pretrained network of a shipped ski (:data:`skisnow.ski.SHIPPED_SKIS`), loaded once.

    The files are ``skisnow/network/models/<name>.npz|.json``, trained on the virtual bench of that
    ski (``benchmarks/bench_network.py --retrain --save`` regenerates them; the training bench
    and settings are in its ``SHIPPED_SETTINGS`` and in each file's metadata).

    Raises
    ------
    InputError
        No shipped network of that name (the message lists those available).
    """
    base = resources.files(MODELS_PACKAGE) / "models"
    available = (
        sorted(p.name[:-4] for p in base.iterdir() if p.name.endswith(".npz"))
        if base.is_dir()
        else []
    )
    if ski_name not in available:
        raise InputError(
            f"no shipped camber network for ski {ski_name!r}; available: {', '.join(available)}"
        )
    where = f"shipped model skisnow/network/models/{ski_name}"
    arrays, doc = parse_model_bytes(
        (base / f"{ski_name}.npz").read_bytes(),
        (base / f"{ski_name}.json").read_text(encoding="utf-8"),
        where,
    )
    return network_from_files(arrays, doc, where)
