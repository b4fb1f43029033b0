"""What limits the camber network's accuracy: short diagnostic trainings (issue 30).

    nice -n 10 uv run python benchmarks/network_diagnosis.py --ski classic --label base \
        [--lm-steps 150] [--lm-points 3000] [--widths 6,16,16,16,12,12] [--contact-weight 4] \
        [--no-reference] [--mass-scaled] [--validation-fraction 0.15] \
        [--bench paper|dense|m1p40|m5p13]

Trains one network (seeded) with the given recipe on a virtual bench of ``--ski`` and prints
one JSON line: the 25 off-grid load cases of ``bench_network.py`` (network and interpolation of
the same bench), the error split by truth height (< 0.2 mm, 0.2-2 mm, > 2 mm), the held-out
curve of the Levenberg-Marquardt phase every 25 steps, the CPU time and the load average.
Appends the line to ``--log`` (default ``benchmarks/network_diagnosis.jsonl``).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np
from bench_network import (
    TRAINING_MASSES,
    TRAINING_POSITIONS,
    bench_cube,
    interpolate_cases,
    log_record,
    offgrid_cases,
)

from skisnow.bench import DEFAULT_LOAD_POSITIONS, DEFAULT_MASSES, run_bench
from skisnow.ski import get_ski

BENCHES = {
    "paper": (DEFAULT_MASSES, DEFAULT_LOAD_POSITIONS),
    "dense": (TRAINING_MASSES, TRAINING_POSITIONS),
    "m1p40": (tuple(float(m) for m in range(5, 131)), DEFAULT_LOAD_POSITIONS),
    "m5p13": (DEFAULT_MASSES, TRAINING_POSITIONS),
}


def split_errors(est: np.ndarray, truth: np.ndarray) -> dict[str, float]:
    e = 1e6 * np.abs(est - truth)
    out = {"mean": float(e.mean()), "max": float(e.max())}
    for name, sel in (
        ("near", truth < 0.2e-3),
        ("mid", (truth >= 0.2e-3) & (truth < 2e-3)),
        ("far", truth >= 2e-3),
    ):
        out[name] = float(e[sel].mean())
        out[name + "_share"] = float(sel.mean())
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--ski", default="classic")
    ap.add_argument("--label", required=True)
    ap.add_argument("--bench", default="paper", choices=sorted(BENCHES))
    ap.add_argument("--adam-steps", type=int, default=600)
    ap.add_argument("--lm-steps", type=int, default=150)
    ap.add_argument("--lm-points", type=int, default=3000)
    ap.add_argument("--patience", type=int, default=1000)
    ap.add_argument("--widths", default="6,16,16,16,12,12")
    ap.add_argument("--contact-weight", type=float, default=4.0)
    ap.add_argument("--validation-fraction", type=float, default=0.15)
    ap.add_argument("--no-reference", action="store_true")
    ap.add_argument(
        "--mass-scaled",
        action="store_true",
        help="learn (h - h_0(x)) / m (train_network's mass_scaled_output; fifth pass)",
    )
    ap.add_argument("--interp-only", action="store_true")
    ap.add_argument(
        "--shipped-fit",
        action="store_true",
        help="no training: the shipped network's error on its own training bench (the fit) "
        "and on the 25 off-grid cases",
    )
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--log", default=str(Path(__file__).with_name("network_diagnosis.jsonl")))
    args = ap.parse_args()
    load0 = os.getloadavg()
    ski = get_ski(args.ski)
    masses, positions = BENCHES[args.bench]
    bench = run_bench(ski, masses=masses, load_positions=positions)
    cube = bench_cube(bench)
    x = cube[2]
    mm, pp, truth = offgrid_cases(ski, x)
    interp = interpolate_cases(cube, mm, pp)
    record = {
        "label": args.label,
        "ski": args.ski,
        "bench": args.bench,
        "n_conditions": len(masses) * len(positions),
        "interpolation": split_errors(interp, truth),
    }
    if args.shipped_fit:
        from skisnow.network import bench_sha256, shipped_network

        net = shipped_network(args.ski)
        if net.metadata["n_conditions"] != len(masses) * len(positions):
            raise SystemExit(f"{args.ski}: the shipped network was not trained on --bench")
        record["same_hash"] = bench_sha256(bench) == net.metadata["training_data_sha256"]
        _, _, _, hb = cube
        ms, ps = np.meshgrid(cube[0], cube[1])  # (n_pos, n_mass) as the cube
        fit = net.predict(x, ms.ravel(), ps.ravel(), on_domain_error="ignore")
        hb = hb.reshape(-1, x.size)
        record["shipped_fit"] = split_errors(fit, hb)
        record["network"] = split_errors(net.predict(x, mm, pp), truth)
    elif not args.interp_only:
        from skisnow.network import train_network

        curve = []

        def progress(p) -> None:
            if (p.phase == "lm" and p.step % 25 == 0) or (p.phase == "adam" and p.step == p.total):
                curve.append((p.phase, p.step, round(p.train_rms_um, 3), round(p.val_mean_um, 3)))
                print(curve[-1], f"{time.process_time():.0f} s cpu", flush=True)

        c0 = time.process_time()
        net = train_network(
            bench,
            seed=args.seed,
            architecture=args.widths,
            adam_steps=args.adam_steps,
            lm_steps=args.lm_steps,
            lm_points=args.lm_points,
            patience=args.patience,
            contact_weight=args.contact_weight,
            validation_fraction=args.validation_fraction,
            reference_profile=not args.no_reference,
            mass_scaled_output=args.mass_scaled,
            progress=progress,
            report_every=50,
        )
        cpu = time.process_time() - c0
        pred = net.predict(x, mm, pp)
        # the network on its own training profiles (fit), all conditions not held out
        record.update(
            {
                "recipe": {k: v for k, v in vars(args).items() if k not in ("log", "label")},
                "network": split_errors(pred, truth),
                "held_out": net.metadata["validation_errors"],
                "lm_steps_taken": net.metadata["lm_steps_taken"],
                "status": net.metadata["status"],
                "curve": curve,
                "cpu_s": round(cpu, 1),
                "wall_s": round(net.metadata["training_time_s"], 1),
            }
        )
    record["load"] = [round(v, 2) for v in (*load0, *os.getloadavg())]
    log_record(record, args.log)


if __name__ == "__main__":
    main()
