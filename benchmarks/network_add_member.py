"""Add a member to a trained camber network: an ensemble of two (issue 30, fifth pass).

    nice -n 10 uv run python benchmarks/network_add_member.py --ski classic --out DIR \
        --log FILE [--time-limit 2400] [--models DIR0]

Trains member ``n`` (n = the network's member count) of the network's own recipe
(``metadata["options"]``, its seed: the same held-out conditions, scaling and reference
profile; ``train_network(first_member=n)``) on the dense virtual bench the network was trained
on (checked by the bench's sha256), with an LM wall-clock budget ``--time-limit``, and writes
the ensemble (the old members + the new one; the prediction is their mean) to ``DIR/SKI``.
The held-out errors in its metadata are re-measured for the ensemble; the new member's own
record is kept under ``metadata["added_members"]``. Evaluate with ``bench_network.py --models
DIR``.
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


def held_out_errors(net, table) -> dict[str, float]:
    """Mean, p95, max and near-contact mean |error| [µm] on the held-out conditions (as
    ``train_network`` records them)."""
    err, near = [], []
    for c in net.metadata["validation_conditions"]:
        rows = (table["mass_kg"] == c["mass_kg"]) & (
            table["load_position_mm"] == c["load_position_mm"]
        )
        x = table.loc[rows, "x_mm"].to_numpy(float) * 1e-3
        h = table.loc[rows, "height_mm"].to_numpy(float) * 1e-3
        pred = net.predict(x, c["mass_kg"], c["load_position_mm"] * 1e-3, on_domain_error="ignore")
        err.append(np.abs(pred - h))
        near.append(h < 0.2e-3)
    e, n = np.concatenate(err), np.concatenate(near)
    return {
        "mean_um": float(1e6 * e.mean()),
        "p95_um": float(1e6 * np.percentile(e, 95)),
        "max_um": float(1e6 * e.max()),
        "near_contact_mean_um": float(1e6 * e[n].mean()),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ski", default="classic")
    ap.add_argument("--models", default=None, help="start from DIR/SKI (default: shipped)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--log", default=None)
    ap.add_argument("--time-limit", type=float, default=2400.0)
    args = ap.parse_args()

    from skisnow.network import (
        CamberNetwork,
        bench_sha256,
        load_network,
        save_network,
        shipped_network,
        train_network,
    )

    net0 = load_network(Path(args.models) / args.ski) if args.models else shipped_network(args.ski)
    meta0 = dict(net0.metadata)
    opts = meta0["options"]
    bench = run_bench(get_ski(args.ski), masses=TRAINING_MASSES, load_positions=TRAINING_POSITIONS)
    if bench_sha256(bench) != meta0["training_data_sha256"]:
        raise SystemExit(f"{args.ski}: the network was not trained on this dense bench")
    log = open(args.log, "a") if args.log else None  # noqa: SIM115
    t0 = time.perf_counter()

    def report(p) -> None:
        if p.phase == "lm" or p.step % 200 == 0:
            line = (
                f"{args.ski} member {len(net0.members)} {p.phase} {p.step}/{p.total}: train rms "
                f"{p.train_rms_um:.2f} µm, held-out mean {p.val_mean_um:.2f} µm"
                f" ({time.perf_counter() - t0:.0f} s, cpu {time.process_time():.0f} s,"
                f" load {os.getloadavg()[0]:.1f})"
            )
            print(line, flush=True)
            if log is not None:
                log.write(line + "\n")
                log.flush()

    new = train_network(
        bench,
        seed=meta0["seed"],
        architecture=opts["architecture"],
        validation_fraction=opts["validation_fraction"],
        adam_steps=opts["adam_steps"],
        adam_learning_rate=opts["adam_learning_rate"],
        lm_steps=opts["lm_steps"],
        lm_points=opts["lm_points"],
        adam_points=opts["adam_points"],
        patience=opts["patience"],
        contact_height=opts["contact_height_m"],
        contact_weight=opts["contact_weight"],
        reference_profile=opts["reference_profile"],
        ensemble=1,
        first_member=len(net0.members),
        time_limit=args.time_limit,
        progress=report,
    )
    if log is not None:
        log.close()
    same = (
        new.scaling == net0.scaling
        and new.architecture == net0.architecture
        and np.array_equal(new.reference.height, net0.reference.height)
        and new.metadata["validation_conditions"] == meta0["validation_conditions"]
    )
    if not same:
        raise SystemExit("the new member's split, scaling or reference differs: not merged")
    ens = CamberNetwork(
        architecture=net0.architecture,
        scaling=net0.scaling,
        domain=net0.domain,
        members=(*net0.members, *new.members),
        reference=net0.reference,
        metadata=meta0,
    )
    member_record = {
        k: new.metadata[k]
        for k in ("options", "lm_steps_taken", "stopped_by", "status", "training_time_s")
    }
    member_record["validation_errors"] = new.metadata["validation_errors"]
    meta = {
        **meta0,
        "validation_errors": held_out_errors(ens, bench.table),
        "lm_steps_taken": [*meta0["lm_steps_taken"], *new.metadata["lm_steps_taken"]],
        "stopped_by": [*meta0["stopped_by"], *new.metadata["stopped_by"]],
        "member_status": [*meta0["member_status"], *new.metadata["member_status"]],
        "training_time_s": meta0["training_time_s"] + new.metadata["training_time_s"],
        "added_members": [*meta0.get("added_members", []), member_record],
    }
    ens = dataclasses.replace(ens, metadata=meta)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    save_network(ens, Path(args.out) / args.ski)
    single = held_out_errors(
        dataclasses.replace(ens, members=new.members, metadata=meta0), bench.table
    )
    print(f"held-out: first member {meta0['validation_errors']}")
    print(f"held-out: new member {single}")
    print(f"held-out: ensemble {meta['validation_errors']}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
