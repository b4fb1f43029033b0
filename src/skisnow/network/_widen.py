"""Widening a trained camber network without changing what it predicts (issue 30, fifth pass).

The paper fixes the blocks and their wiring (Kalliorinne et al. 2023, §3.1, Figure 3), not their
widths. A network trained at some widths can be continued at larger widths: every new neuron
gets small random incoming weights and **zero outgoing weights**, so the widened network
computes exactly the function of the trained one (the function-preserving growth of Chen,
Goodfellow & Shlens 2016, "Net2Net", in its zero-output variant), and a continued
Levenberg–Marquardt phase (:func:`skisnow.network.train_network` with ``initial=``) starts from
the trained network's error with more capacity to lower it.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from skisnow._errors import InputError
from skisnow.network._network import Architecture, BlockNetwork, CamberNetwork

__all__ = ["widen_network"]


def _grow(
    weight: np.ndarray,
    bias: np.ndarray,
    rows: int,
    col_blocks: list[tuple[int, int]],
    rng: np.random.Generator,
    init_scale: float | None,
) -> tuple[np.ndarray, np.ndarray]:
    """A layer (weight ``(out, in)``, bias) grown to ``rows`` outputs; its inputs come in blocks
    ``(old width, new width)``: old columns copied into the first columns of each block, the new
    columns of each block zero (the new neurons feeding this layer do not change it); new rows
    (new neurons) random: uniform in ±1/√fan-in (Equinox's initialisation of a linear layer)
    when ``init_scale`` is None, else ``N(0, init_scale²)``; their biases likewise."""
    n_in = sum(new for _, new in col_blocks)
    n_new = rows - weight.shape[0]
    w = np.zeros((rows, n_in))
    b = np.zeros(rows)
    if init_scale is None:
        lim = 1.0 / np.sqrt(n_in)
        w[weight.shape[0] :, :] = rng.uniform(-lim, lim, (n_new, n_in))
        b[weight.shape[0] :] = rng.uniform(-lim, lim, n_new)
    else:
        w[weight.shape[0] :, :] = init_scale * rng.standard_normal((n_new, n_in))
    src = dst = 0
    for old, new in col_blocks:
        w[: weight.shape[0], dst : dst + old] = weight[:, src : src + old]
        w[: weight.shape[0], dst + old : dst + new] = 0.0
        src, dst = src + old, dst + new
    b[: bias.shape[0]] = bias
    return w, b


def widen_network(
    net: CamberNetwork,
    architecture: Architecture | str,
    *,
    seed: int = 0,
    init_scale: float | None = None,
) -> CamberNetwork:
    """The trained ``net`` at the larger widths ``architecture``, predicting exactly the same.

    Every layer keeps its trained weights; each new neuron has random incoming weights and bias
    (seeded by ``seed``; uniform in ±1/√fan-in as a fresh layer, or ``N(0, init_scale²)``
    weights and zero bias) and zero outgoing weights (Chen et al. 2016, Net2Net, zero-output
    growth). Scaling, reference profile, domain and metadata are kept (the metadata gains
    ``widened_from``: the old widths).

    Raises
    ------
    InputError
        A width of ``architecture`` smaller than the network's.
    """
    new = (
        architecture
        if isinstance(architecture, Architecture)
        else Architecture.from_widths(architecture)
    )
    old = net.architecture
    if any(n < o for n, o in zip(new.widths, old.widths, strict=True)):
        raise InputError(f"widening needs widths >= {old.widths}, got {new.widths}")
    rng = np.random.default_rng(seed)
    members = []
    for member in net.members:
        lay = {name: (np.asarray(la.weight), np.asarray(la.bias)) for name, la in member.layers()}
        c, k = new.collapse, new.camber
        oc, ok = old.collapse, old.camber
        grown = {
            "load": _grow(*lay["load"], new.load, [(2, 2)], rng, init_scale),
            "collapse0": _grow(
                *lay["collapse0"], c[0], [(1, 1), (old.load, new.load)], rng, init_scale
            ),
            "collapse1": _grow(*lay["collapse1"], c[1], [(oc[0], c[0])], rng, init_scale),
            "collapse2": _grow(*lay["collapse2"], c[2], [(oc[1], c[1])], rng, init_scale),
            "camber0": _grow(*lay["camber0"], k[0], [(1, 1)], rng, init_scale),
            "camber1": _grow(*lay["camber1"], k[1], [(ok[0], k[0])], rng, init_scale),
            "prediction": _grow(
                lay["prediction"][0],
                lay["prediction"][1],
                1,
                [(oc[2], c[2]), (ok[1], k[1])],
                rng,
                init_scale,
            ),
        }
        members.append(BlockNetwork.from_layer_arrays(new, grown))
    return dataclasses.replace(
        net,
        architecture=new,
        members=tuple(members),
        metadata={**net.metadata, "widened_from": list(old.widths)},
    )
