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
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time
from pathlib import Path

from bench_network import TRAINING_MASSES, TRAINING_POSITIONS

from skisnow.bench import run_bench
from skisnow.ski import get_ski


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
        raise SystemExit(f"{args.ski}: the network was not trained on this dense bench")
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
        )
    }
    meta["continued_from"]["widen_seed"] = args.widen_seed
    meta["training_time_s"] = meta0["training_time_s"] + net.metadata["training_time_s"]
    net = dataclasses.replace(net, metadata=meta)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    save_network(net, Path(args.out) / args.ski)
    print(f"held-out before: {meta0['validation_errors']}")
    print(f"held-out after: {meta['validation_errors']}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
