"""Cheap ranking of optimisers that continue a trained camber network (issue 30, fifth pass).

    nice -n 10 uv run python benchmarks/network_polish.py --ski classic --method lbfgs \
        --points 100000 --budget 300 --label NAME [--models DIR] [--lr 1e-4]

Starts from a trained network (the shipped one, or ``--models DIR``), continues its training on
``--points`` points of the dense virtual bench (the held-out conditions of its training are
left out, evenly thinned, the training's near-contact weight), with ``--method``:

* ``lbfgs``: optax's L-BFGS with its zoom line search, full batch on the points;
* ``adam``: Adam at a constant learning rate ``--lr``, full batch;
* ``lm``: the training's Levenberg-Marquardt step on ``--points`` points (a fresh thinning).

for ``--budget`` CPU seconds, and prints / appends to ``--log`` (default
``benchmarks/network_polish.jsonl``) the off-grid error of ``bench_network.py`` (the 25 cases
off every bench grid, µm: mean and near contact) every ``--every`` steps, with the CPU seconds
(``time.process_time``) and the load average. A diagnostic of error per CPU second, not a
shipped recipe.
"""

from __future__ import annotations

import argparse
import json
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

from skisnow.bench import run_bench
from skisnow.ski import get_ski


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--ski", default="classic")
    ap.add_argument("--label", required=True)
    ap.add_argument("--models", default=None)
    ap.add_argument("--method", choices=("lbfgs", "adam", "lm"), default="lbfgs")
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--budget", type=float, default=300.0, help="CPU seconds")
    ap.add_argument("--lr", type=float, default=1e-4)
    ap.add_argument("--every", type=int, default=25)
    ap.add_argument("--save", default=None, help="write the continued network to this folder")
    ap.add_argument("--log", default=str(Path(__file__).with_name("network_polish.jsonl")))
    args = ap.parse_args()

    import dataclasses

    from skisnow.network import (
        load_network,
        save_network,
        shipped_network,
        split_conditions,
    )
    from skisnow.network._jax import jax, jnp, optax, ravel_pytree
    from skisnow.network._levenberg_marquardt import make_lm_step
    from skisnow.network._network import x64

    load0 = os.getloadavg()
    ski = get_ski(args.ski)
    net = load_network(Path(args.models) / args.ski) if args.models else shipped_network(args.ski)
    meta = net.metadata
    opts = meta["options"]
    bench = run_bench(ski, masses=TRAINING_MASSES, load_positions=TRAINING_POSITIONS)
    cube = bench_cube(bench)
    xg = cube[2]
    mm, pp, truth = offgrid_cases(ski, xg)
    interp = interpolate_cases(cube, mm, pp)
    near = truth < 0.2e-3

    def offgrid(n) -> tuple[float, float]:
        e = 1e6 * np.abs(n.predict(xg, mm, pp) - truth)
        return float(e.mean()), float(e[near].mean())

    t = bench.table
    x = t["x_mm"].to_numpy(float) * 1e-3
    m = t["mass_kg"].to_numpy(float)
    p = t["load_position_mm"].to_numpy(float) * 1e-3
    h = t["height_mm"].to_numpy(float) * 1e-3
    conds, ci = np.unique(np.stack([m, p], axis=1), axis=0, return_inverse=True)
    val = split_conditions(
        conds[:, 0], conds[:, 1], validation_fraction=opts["validation_fraction"], seed=meta["seed"]
    )
    tr = np.flatnonzero(~val[ci.ravel()])
    stride = max(1, len(tr) // args.points)
    rng = np.random.default_rng(1)
    sub = tr[int(rng.integers(stride)) :: stride]
    s = net.scaling
    target = h - net.reference(x) if net.reference is not None else h
    xs, ms, ps = s.scale_inputs(x[sub], m[sub], p[sub])
    hs = s.scale_height(target[sub])
    w = np.where(h[sub] < opts["contact_height_m"], opts["contact_weight"], 1.0)

    record = {
        "label": args.label,
        "ski": args.ski,
        "method": args.method,
        "points": len(sub),
        "lr": args.lr if args.method == "adam" else None,
        "start": dict(zip(("mean", "near"), offgrid(net), strict=True)),
        "interpolation_dense": {
            "mean": float(1e6 * np.abs(interp - truth).mean()),
            "near": float(1e6 * np.abs(interp - truth)[near].mean()),
        },
    }
    print(json.dumps(record), flush=True)
    curve = []
    with x64():
        member = net.members[0]
        theta, unravel = ravel_pytree(member)
        data = tuple(jnp.asarray(a) for a in (xs, ms, ps, hs, w))

        def residual(th, d=data):
            xs_, ms_, ps_, hs_, w_ = d
            return jnp.sqrt(w_) * (unravel(th).points(xs_, ms_, ps_) - hs_)

        def loss(th):
            r = residual(th)
            return jnp.mean(r * r)

        if args.method == "lbfgs":
            opt = optax.lbfgs()
            vg = optax.value_and_grad_from_state(loss)
            state = opt.init(theta)

            @jax.jit
            def step(th, st):
                value, g = vg(th, state=st)
                upd, st = opt.update(g, st, th, value=value, grad=g, value_fn=loss)
                return optax.apply_updates(th, upd), st, value

        elif args.method == "adam":
            opt = optax.adam(args.lr)
            state = opt.init(theta)

            @jax.jit
            def step(th, st):
                value, g = jax.value_and_grad(loss)(th)
                upd, st = opt.update(g, st, th)
                return optax.apply_updates(th, upd), st, value

        else:

            def point_residual(th, *pt):
                return residual(th, tuple(v[None] for v in pt))[0]

            lm = make_lm_step(residual, point_residual, data)
            state = jnp.asarray(1e-3)

            def step(th, mu):
                th, mu, rms, _ = lm(th, mu)
                return th, mu, rms**2

        c0 = time.process_time()
        k = 0
        while True:
            theta, state, value = step(theta, state)
            k += 1
            cpu = time.process_time() - c0
            if k % args.every == 0 or cpu > args.budget:
                cand = dataclasses.replace(net, members=(unravel(theta),))
                mean, nr = offgrid(cand)
                rms = float(s.height_scale * 1e6 * np.sqrt(float(value)))
                curve.append((k, round(cpu, 1), round(rms, 3), round(mean, 3), round(nr, 3)))
                print(curve[-1], f"load {os.getloadavg()[0]:.1f}", flush=True)
            if cpu > args.budget:
                break
    record.update({"curve": curve, "steps": k, "cpu_s": round(cpu, 1)})
    record["load"] = [round(v, 2) for v in (*load0, *os.getloadavg())]
    if args.save:
        out = dataclasses.replace(
            net,
            members=(unravel(theta),),
            metadata={**meta, "polish": {k: v for k, v in record.items() if k != "curve"}},
        )
        Path(args.save).mkdir(parents=True, exist_ok=True)
        save_network(out, Path(args.save) / args.ski)
    log_record(record, args.log)


if __name__ == "__main__":
    main()
