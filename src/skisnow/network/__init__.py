"""The camber network: the loaded camber profile h = f(x, m, x_m) learnt from the bench.

Kalliorinne et al. (2023), eq. 1 and Figure 3: a block network (load condition, ski collapse,
ski camber, prediction; :class:`BlockNetwork`, :class:`Architecture`) trained on the bench of
one ski, an ensemble of them with MATLAB's ``mapminmax`` scaling (:class:`Scaling`), its trained
range (:class:`Domain`) and a reference profile (:class:`ReferenceProfile`):
:class:`CamberNetwork`, :meth:`CamberNetwork.predict`; training with held-out load conditions
and its own Levenberg–Marquardt (Marquardt 1963): :func:`train_network` →
:class:`TrainingProgress`; its file format (``PATH.npz`` weights + ``PATH.json`` metadata, never
pickle; :func:`save_network`, :func:`load_network`, :func:`read_model_files` and friends) and the
pretrained networks of the shipped skis in ``skisnow/network/models/``
(:func:`shipped_network`); and :func:`camber_profile`, the one function downstream code calls for
a loaded profile, from the beam or from the network. JAX is imported only when a network is
built or trained.

May import: ski, bench
"""

from __future__ import annotations

from skisnow._lazy import lazy_getattr
from skisnow.network._converged import training_converged
from skisnow.network._files import (
    MODEL_FORMAT,
    MODEL_FORMAT_VERSION,
    load_network,
    metadata_checksum,
    model_paths,
    network_arrays,
    network_from_files,
    parse_model_bytes,
    read_model_files,
    save_network,
    shipped_network,
    write_model_files,
)
from skisnow.network._profiles import camber_profile

# The network and its training need JAX: imported on first use, so that the contact sweep's
# workers and the CLI start without it. (The names repeat their modules' __all__, as every
# package door's imports do: one static list per door.)
_LAZY = {
    **dict.fromkeys(
        ("Architecture", "BlockNetwork", "CamberNetwork", "Domain", "ReferenceProfile", "Scaling"),
        "skisnow.network._network",
    ),
    **dict.fromkeys(
        ("TrainingProgress", "train_network"),
        "skisnow.network._training",
    ),
    **dict.fromkeys(("bench_sha256", "split_conditions"), "skisnow.network._bench_split"),
    "widen_network": "skisnow.network._widen",
}

__getattr__ = lazy_getattr(__name__, _LAZY)

__all__ = [
    "MODEL_FORMAT",
    "MODEL_FORMAT_VERSION",
    "Architecture",
    "BlockNetwork",
    "CamberNetwork",
    "Domain",
    "ReferenceProfile",
    "Scaling",
    "TrainingProgress",
    "bench_sha256",
    "camber_profile",
    "load_network",
    "metadata_checksum",
    "model_paths",
    "network_arrays",
    "network_from_files",
    "parse_model_bytes",
    "read_model_files",
    "save_network",
    "shipped_network",
    "split_conditions",
    "train_network",
    "training_converged",
    "widen_network",
    "write_model_files",
]
