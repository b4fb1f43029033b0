"""Widen a shipped camber network and continue its training (issue 30, fifth pass).

    nice -n 10 uv run python benchmarks/network_widen.py --ski skate \
        --widths 8,24,24,24,16,16 --lm-points 12000 --patience 50 --time-limit 2700 \
        --out DIR --log FILE [--models DIR0]

Starts from the network (shipped, or ``DIR0/SKI``), widens it without changing what it predicts
(:func:`skisnow.network.widen_network`: new neurons with zero outgoing weights), and continues
with the Levenberg–Marquardt phase only (``train_network(initial=..., adam_steps=0)``) on the
dense virtual bench it was trained on (checked by its sha256), with its own seed, split,
scaling, reference and loss weights, ``--lm-points`` points, early stopping after
``--patience`` steps without a better held-out error and a wall-clock budget. The best held-out
parameters are kept, the starting ones included: the result is never worse on its held-out
conditions than the network it started from. Writes ``DIR/SKI``; its metadata records the
network it continued (``continued_from``). Evaluate with ``bench_network.py --models DIR``.

``--rebench`` (issue 30, eighth pass): continue the same widths on the dense bench of a
*different* ski of the same name (a refitted reproduction ski): the sha check is skipped, the
network is moved into the new bench's frame (its output scaling and reference profile, computed
as :func:`~skisnow.network.train_network` computes them; the output layer re-expressed so that
the network still predicts the old ski's heights shifted by the change of the reference, the
load-independent part of the change of ski) and continued; the metadata records
``continued_from`` (with the old ``training_data_sha256``) and the new bench's sha256.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time
from pathlib import Path

import numpy as np
from bench_network import TRAINING_MASSES, TRAINING_POSITIONS

from skisnow.bench import run_bench
from skisnow.ski import get_ski


def reframed(net0, bench, meta0):  # type: ignore[no-untyped-def]
    """``net0`` in the frame (scaling, reference profile) ``train_network`` gives ``bench``
    with ``net0``'s seed and options: the frame from a zero-step training, the output layer
    re-expressed so that u_new = (s_old u_old + c_old - c_new) / s_new (u: the network's
    scaled output, s and c the height scale and centre); the input scaling must agree."""
    from skisnow.network import BlockNetwork, train_network

    opts = meta0["options"]
    frame = train_network(
        bench,
        architecture=net0.architecture,
        seed=meta0["seed"],
        validation_fraction=opts["validation_fraction"],
        adam_steps=0,
        lm_steps=0,
        reference_profile=opts["reference_profile"],
        ensemble=len(net0.members),
    )
    s0, s1 = net0.scaling, frame.scaling
    same = ("x_center", "x_scale", "mass_center", "mass_scale", "position_center",
            "position_scale")  # fmt: skip
    if any(getattr(s0, k) != getattr(s1, k) for k in same):
        raise SystemExit("--rebench: the new bench's inputs are not scaled as the old one's")
    a = s0.height_scale / s1.height_scale
    b = (s0.height_center - s1.height_center) / s1.height_scale
    members = []
    for member in net0.members:
        lay = {n: (np.asarray(la.weight), np.asarray(la.bias)) for n, la in member.layers()}
        w, c = lay["prediction"]
        lay["prediction"] = (a * w, a * c + b)
        members.append(BlockNetwork.from_layer_arrays(net0.architecture, lay))
    return dataclasses.replace(
        net0, scaling=s1, reference=frame.reference, domain=frame.domain, members=tuple(members)
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ski", required=True)
    ap.add_argument("--models", default=None, help="start from DIR/SKI (default: shipped)")
    ap.add_argument("--widths", required=True)
    ap.add_argument("--lm-points", type=int, default=12000)
    ap.add_argument("--lm-steps", type=int, default=2000)
    ap.add_argument("--patience", type=int, default=50)
    ap.add_argument("--time-limit", type=float, default=2700.0)
    ap.add_argument("--widen-seed", type=int, default=0)
    ap.add_argument("--out", required=True)
    ap.add_argument("--log", default=None)
    ap.add_argument(
        "--rebench",
        action="store_true",
        help="the ski changed: continue on its new dense bench (eighth pass)",
    )
    args = ap.parse_args()

    from skisnow.network import (
        bench_sha256,
        load_network,
        save_network,
        shipped_network,
        train_network,
        widen_network,
    )

    net0 = load_network(Path(args.models) / args.ski) if args.models else shipped_network(args.ski)
    meta0 = dict(net0.metadata)
    opts = meta0["options"]
    bench = run_bench(get_ski(args.ski), masses=TRAINING_MASSES, load_positions=TRAINING_POSITIONS)
    if bench_sha256(bench) != meta0["training_data_sha256"]:
        if not args.rebench:
            raise SystemExit(f"{args.ski}: the network was not trained on this dense bench")
        net0 = reframed(net0, bench, meta0)
    wide = widen_network(net0, args.widths, seed=args.widen_seed)
    log = open(args.log, "a") if args.log else None  # noqa: SIM115
    t0 = time.perf_counter()
    print(f"load before: {os.getloadavg()}", flush=True)

    def report(p) -> None:
        line = (
            f"{args.ski} widened {args.widths} lm {p.step}/{p.total}: train rms "
            f"{p.train_rms_um:.2f} µm, held-out mean {p.val_mean_um:.2f} µm"
            f" ({time.perf_counter() - t0:.0f} s, cpu {time.process_time():.0f} s,"
            f" load {os.getloadavg()[0]:.1f})"
        )
        print(line, flush=True)
        if log is not None:
            log.write(line + "\n")
            log.flush()

    net = train_network(
        bench,
        initial=wide,
        seed=meta0["seed"],
        validation_fraction=opts["validation_fraction"],
        adam_steps=0,
        lm_steps=args.lm_steps,
        lm_points=args.lm_points,
        patience=args.patience,
        contact_height=opts["contact_height_m"],
        contact_weight=opts["contact_weight"],
        reference_profile=opts["reference_profile"],
        ensemble=len(net0.members),
        time_limit=args.time_limit,
        progress=report,
    )
    if log is not None:
        log.close()
    meta = dict(net.metadata)
    meta["continued_from"] = {
        k: meta0.get(k)
        for k in (
            "options",
            "lm_steps_taken",
            "stopped_by",
            "status",
            "training_time_s",
            "validation_errors",
            "training_data_sha256",
        )
    }
    meta["continued_from"]["widen_seed"] = args.widen_seed
    meta["continued_from"]["rebench"] = args.rebench
    meta["training_time_s"] = meta0["training_time_s"] + net.metadata["training_time_s"]
    net = dataclasses.replace(net, metadata=meta)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    save_network(net, Path(args.out) / args.ski)
    print(f"held-out before: {meta0['validation_errors']}")
    print(f"held-out after: {meta['validation_errors']}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
