"""Every row of issue 29's table, one command: the contact solves and the workflows built on them.

    uv run python benchmarks/bench_speed.py                      # all rows (~5 min idle)
    uv run python benchmarks/bench_speed.py --rows strip,scaling # some rows
    uv run --group peers python benchmarks/bench_speed.py --rows hertz   # + tamaas (AGPL peer)

Rows (targets of issue 29 in brackets):

* ``strip``    — strip solve, classic, 60 kg at −120 mm, snow 100 MPa, 4096 stations, force +
  moment balance: median wall and CPU time of ``--repeat`` solves (operator cached, as in a
  sweep), iterations, operator products [≤ 2 ms; moment/load ≤ 1.2×];
* ``scaling``  — the same case from 1,024 to 65,536 stations: median CPU time, iterations,
  products and the peak memory of one solve (tracemalloc) — the growth law;
* ``hertz``    — non-periodic Hertz sphere 512² and 1024², one thread, cold (the kernel built in
  the timing): skisnow and, when importable, tamaas 2.9 (``PolonskyKeerRey``, non-periodic) in
  the same run, at tol 1e-10 and at equal accuracy against the analytic pressure (each code at
  the loosest tolerance of 1e-4, 1e-6, 1e-8, 1e-10 whose rel-L2 error is within 1 % of its own
  error at 1e-10) [≤ 0.3 s / ≤ 1.5 s, ≥ 25× tamaas];
* ``flexible`` — the flexible ski against the bare rigid solve, six cases [≤ 1.5×];
* ``sweep``    — the Figure 8/9 sweep (skate, 126 masses × 20 moduli, beam profiles) on a local
  Dask cluster of 1 and 2 worker processes, ``--sweep-runs`` runs each (default 3, 1 and 2
  alternately, a fresh cluster each, its start-up timed apart): the compute time (median) and
  each worker's and the client's CPU during the run (what each core must give on an idle
  machine) [< 2 s on 2; ≥ 1.8× over 1]; ``benchmarks/sweep_phases.py`` splits that CPU by
  phase;
* ``explore``  — the explorer's default page (3,120 solves) [< 8 s];
* ``cycle``    — 100-frame load cycles, every ski × template, rigid route, and two flexible
  [< 0.3 s];
* ``bearing``  — the bearing model, 1 mm², 1 µm pixels, 31 grain sizes, stride 1, 2 threads
  [< 8 s wall; CPU halved from 27.6 s].

The test suite's time is measured by ``uv run pytest -q -p no:randomly --durations=25``.

The machine may be shared: every row prints the load average before and after it, and CPU time
beside wall time (CPU is what carries over to an idle machine). The script runs unchanged on
the code before issue 29 (same public API), so the lead can run it on both checkouts.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import time
import tracemalloc

import numpy as np

# the Hertz problem and its tamaas run are bench_contact's (same folder: on sys.path when run)
from bench_contact import HERTZ_RADIUS, hertz_problem, tamaas_hertz
from bench_flexible import FLEX_CASES

ROWS = ("strip", "scaling", "hertz", "flexible", "sweep", "explore", "cycle", "bearing")
RESULTS: list[tuple[str, str, str, str]] = []  # (row, measured, target, load)


def load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def record(row: str, measured: str, target: str, before: str) -> None:
    RESULTS.append((row, measured, target, f"{before} -> {load()}"))
    print(f"  {row}: {measured}   [{target}]   load {before} -> {load()}", flush=True)


def medians(fn, repeat: int) -> tuple[float, float, object]:
    """Median wall and CPU seconds of ``repeat`` calls (after one warm-up call)."""
    out = fn()
    walls, cpus = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return statistics.median(walls), statistics.median(cpus), out


def ski_case(n: int, name: str = "classic", mass: float = 60.0, xm: float = -0.12):
    from skisnow.ski import camber_profile, get_ski

    ski = get_ski(name)
    edges = np.linspace(ski.x_tail, ski.x_tip, n + 1)
    return camber_profile(
        name, mass=mass, load_position=xm, x=0.5 * (edges[1:] + edges[:-1]), source="beam"
    )


def strip_kw(mass: float = 60.0, xm: float = -0.12, e: float = 100e6) -> dict:
    from skisnow.constants import STANDARD_GRAVITY
    from skisnow.contact import effective_modulus, snow

    return dict(load=mass * STANDARD_GRAVITY, load_position=xm, modulus=effective_modulus(snow(e)))


def row_strip(repeat: int) -> None:
    from skisnow.contact import solve_contact

    before = load()
    x, h = ski_case(4096)
    t = {}
    for control in ("moment", "load"):
        wall, cpu, sol = medians(
            lambda c=control: solve_contact(x, h, control=c, **strip_kw()), repeat
        )
        t[control] = (wall, cpu)
        print(
            f"    strip 4096 {control}: wall {wall * 1e3:.2f} ms, CPU {cpu * 1e3:.2f} ms, "
            f"{sol.iterations} iterations, {sol.convolutions} products, "
            f"{int(sol.contact.sum())} cells in contact"
        )
    (wm, cm), (wl, cl) = t["moment"], t["load"]
    record(
        "strip solve 4096, moment",
        f"{wm * 1e3:.2f} ms wall, {cm * 1e3:.2f} ms CPU (median of {repeat})",
        "<= 2 ms",
        before,
    )
    record("moment / load", f"{wm / wl:.2f} wall, {cm / cl:.2f} CPU", "<= 1.2", before)


def row_scaling(repeat: int) -> None:
    from skisnow.contact import solve_contact

    before = load()
    print(
        f"    {'stations':>8} {'CPU ms':>8} {'wall ms':>8} {'iter':>5} {'products':>8} "
        f"{'contact':>7} {'peak MB':>8}"
    )
    prev = None
    for n in (1024, 2048, 4096, 8192, 16384, 32768, 65536):
        x, h = ski_case(n)
        r = max(3, repeat * 1024 // n)
        wall, cpu, sol = medians(lambda x=x, h=h: solve_contact(x, h, **strip_kw()), r)
        tracemalloc.start()
        solve_contact(x, h, **strip_kw())
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        growth = f"  x{cpu / prev:.2f}" if prev else ""
        prev = cpu
        print(
            f"    {n:8d} {cpu * 1e3:8.2f} {wall * 1e3:8.2f} {sol.iterations:5d} "
            f"{sol.convolutions:8d} {int(sol.contact.sum()):7d} {peak:8.2f}{growth}"
        )
    record("scaling 1,024 -> 65,536 stations", "table above", "growth law", before)


def _hertz(n: int):
    """``bench_contact``'s Hertz problem with the exact pressure on its cells."""
    from skisnow.contact import reference

    x, h, w, e_prime, length = hertz_problem(n)
    ref = reference.hertz_sphere(w, HERTZ_RADIUS, modulus=e_prime)
    xx, yy = np.meshgrid(x, x, indexing="ij")
    rr = np.hypot(xx, yy)
    exact = ref.max_pressure * np.sqrt(np.clip(1 - (rr / ref.contact_radius) ** 2, 0, None))
    return x, h, w, e_prime, length, exact


def _skisnow_hertz(n: int, tol: float):
    from skisnow.contact import _problem, solve_contact

    x, h, w, e, _, exact = _hertz(n)
    _problem._operator.cache_clear()  # cold: the kernel and its spectrum in the timing
    t0, c0 = time.perf_counter(), time.process_time()
    sol = solve_contact(
        x, h, y=x, load=w, modulus=e, model="surface", control="load", tol=tol, workers=1
    )
    t, c = time.perf_counter() - t0, time.process_time() - c0
    return t, c, np.linalg.norm(sol.pressure - exact) / np.linalg.norm(exact), sol.pressure


def _tamaas_hertz(n: int, tol: float):
    """tamaas on the same problem (``bench_contact.tamaas_hertz``), with its error."""
    t, c, p = tamaas_hertz(n, tol)
    exact = _hertz(n)[-1]
    return t, c, np.linalg.norm(p - exact) / np.linalg.norm(exact), p


def _equal_accuracy(run, n: int) -> tuple[float, float, float, float]:
    """(tol, wall, CPU, error) at the loosest tolerance within 1 % of the error at 1e-10."""
    ladder = {tol: run(n, tol) for tol in (1e-10, 1e-8, 1e-6, 1e-4)}
    best = ladder[1e-10][2]
    for tol in (1e-4, 1e-6, 1e-8, 1e-10):
        t, c, err, _ = ladder[tol]
        if err <= 1.01 * best:
            return tol, t, c, err
    raise AssertionError("unreachable")


def row_hertz(sizes: list[int], peers: bool = True) -> None:
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    try:
        import tamaas  # noqa: F401

        peer = peers
    except ImportError:
        peer = False
        print("    tamaas not importable: run with `uv run --group peers`; skisnow only")
    targets = {512: 0.3, 1024: 1.5}
    for n in sizes:
        before = load()
        t, c, err, p = _skisnow_hertz(n, 1e-10)
        msg = f"skisnow {t:.2f} s wall, {c:.2f} s CPU, rel-L2 vs Hertz {err:.2e} (tol 1e-10)"
        if peer:
            tt, tc, terr, tp = _tamaas_hertz(n, 1e-10)
            rel = np.linalg.norm(p - tp) / np.linalg.norm(tp)
            msg += (
                f"; tamaas {tt:.2f} s wall, {tc:.2f} s CPU, rel-L2 vs Hertz {terr:.2e}; "
                f"skisnow vs tamaas {rel:.1e}; speed-up {tt / t:.1f}x wall, {tc / c:.1f}x CPU"
            )
        record(
            f"Hertz {n}² non-periodic, tol 1e-10",
            msg,
            f"<= {targets.get(n, float('nan'))} s, >= 25x tamaas",
            before,
        )
        if peer:
            before = load()
            st, sw, sc, se = _equal_accuracy(_skisnow_hertz, n)
            tt, tw, tc, te = _equal_accuracy(_tamaas_hertz, n)
            record(
                f"Hertz {n}² at equal accuracy",
                f"skisnow tol {st:g}: {sw:.2f} s (err {se:.3e}); tamaas tol {tt:g}: {tw:.2f} s "
                f"(err {te:.3e}); speed-up {tw / sw:.1f}x wall, {tc / sc:.1f}x CPU",
                ">= 25x tamaas",
                before,
            )


def row_flexible(repeat: int) -> None:
    from skisnow.constants import STANDARD_GRAVITY
    from skisnow.contact import STONE, effective_modulus, snow, solve_contact, solve_flexible
    from skisnow.pipeline import stations
    from skisnow.ski import camber_profile, get_ski

    before = load()
    worst = 0.0
    for name, m, xm_mm, e_mpa in FLEX_CASES:
        ski = get_ski(name)
        x = stations(ski, 4096)
        xm = xm_mm * 1e-3
        e = effective_modulus(snow(e_mpa * 1e6)) if e_mpa else effective_modulus(STONE)
        _, h = camber_profile(ski, mass=m, load_position=xm, x=x, source="beam")
        kw = dict(load=m * STANDARD_GRAVITY, load_position=xm, modulus=e, width=ski.width)
        z0, ei = ski.free_camber(x), ski.stiffness(x)
        wr, cr, _ = medians(lambda x=x, h=h, kw=kw: solve_contact(x, h, **kw), repeat)
        wf, cf, _ = medians(
            lambda x=x, z0=z0, ei=ei, kw=kw: solve_flexible(x, z0, ei, **kw), repeat
        )
        worst = max(worst, cf / cr)
        print(
            f"    {name} {m} kg {xm_mm} mm {e_mpa or 'stone'}: rigid {cr * 1e3:.2f} ms CPU, "
            f"flexible {cf * 1e3:.2f} ms CPU, ratio {cf / cr:.2f} (wall {wf / wr:.2f})"
        )
    record("flexible / bare rigid (CPU, worst of 6)", f"{worst:.2f}", "<= 1.5", before)


def figure89_spec():
    """The Figure 8/9 sweep of the benchmark (skate, 126 masses × 20 moduli, beam profiles);
    also used by ``sweep_phases.py``."""
    from skisnow.sweep import SweepSpec

    return SweepSpec(
        skis=("skate",),
        masses=np.arange(5.0, 131.0, 1.0),
        load_positions=(-0.120,),
        snow_moduli=np.arange(20.0, 401.0, 20.0) * 1e6,
        model="strip",
        profile_source="beam",
        n_points=4096,
    )


# the bearing row's sweep (31 grain sizes at stride 1, 2 threads) on the S3 grind, 1 mm², 1 µm
# pixels at -2 °C; also used by ``bearing_same_answers.py``
BEARING_CASE = {
    "diameters": np.arange(450, 751, 10) * 1e-6,
    "pressure": 20e3,
    "stride": 1,
    "workers": 2,
}


def row_sweep(runs: int = 3) -> None:
    import tempfile
    from pathlib import Path

    from distributed import Client

    from skisnow.sweep import run_sweep
    from skisnow.sweep._run import local_cluster

    spec = figure89_spec()
    before = load()
    times: dict[int, list[float]] = {1: [], 2: []}
    cpus: dict[int, list[tuple[list[float], float]]] = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as tmp:
        # 1 and 2 workers alternately, each run on a freshly started cluster (its start-up
        # timed apart, before the run): a load that changes over the runs hits both alike
        for r in range(runs):
            for n in (1, 2):
                t0 = time.perf_counter()
                cluster = local_cluster(n)
                client = Client(cluster)
                start = time.perf_counter() - t0
                # the workers' CPU during the run (load-independent: what each core must give
                # on an idle machine) and the client's (its serial part: store, writes,
                # scheduler)
                w0, c0 = client.run(time.process_time), time.process_time()
                run = run_sweep(spec, Path(tmp) / f"r{r}w{n}.zarr", client=client)
                w1, c1 = client.run(time.process_time), time.process_time()
                client.close()
                cluster.close()
                times[n].append(run.compute_time)
                busy = sorted((w1[k] - w0[k] for k in w1), reverse=True)
                cpus[n].append((busy, c1 - c0))
                print(
                    f"    run {r + 1}, {n} worker(s): compute {run.compute_time:.2f} s, wall "
                    f"{run.wall_time:.2f} s (cluster start-up {start:.2f} s before); CPU of "
                    f"each worker {', '.join(f'{b:.2f}' for b in busy)} s, of the client "
                    f"{c1 - c0:.2f} s; load {load()}",
                    flush=True,
                )
        for n in (1, 2):
            w = [sum(b) for b, _ in cpus[n]]
            print(
                f"    {n} worker(s), median of {runs}: compute "
                f"{statistics.median(times[n]):.2f} s; workers' CPU summed "
                f"{statistics.median(w):.2f} s, client CPU "
                f"{statistics.median(c for _, c in cpus[n]):.2f} s"
            )
        # the same sweep in this process: its CPU time is what the workers need between them
        c0 = time.process_time()
        run = run_sweep(spec, Path(tmp) / "w0.zarr", workers=0)
        cpu = time.process_time() - c0
        print(
            f"    in process: compute {run.compute_time:.2f} s, CPU {cpu:.2f} s = "
            f"{1e3 * cpu / 2520:.2f} ms per solve; an idle 2-core machine needs ~{cpu / 2:.2f} s"
        )
        # the chunks alone (what the workers compute; the beam profiles cached after the first)
        from skisnow.sweep import contact_chunk

        contact_chunk(spec, "skate", -0.120, float(spec.snow_moduli[0]))
        c0 = time.process_time()
        for e in spec.snow_moduli:
            contact_chunk(spec, "skate", -0.120, float(e))
        chunks = time.process_time() - c0
        print(
            f"    the 20 chunks alone: CPU {chunks:.2f} s = {1e3 * chunks / 2520:.2f} ms per "
            f"point; on 2 idle cores ~{chunks / 2:.2f} s plus the client's profiles"
        )
    t1, t2 = statistics.median(times[1]), statistics.median(times[2])
    record(
        f"Figure 8/9 sweep, 2520 solves (median of {runs})",
        f"{t2:.2f} s on 2 workers, {t1:.2f} s on 1 ({t1 / t2:.2f}x)",
        "< 2 s on 2, >= 1.8x",
        before,
    )


def row_explore() -> None:
    from skisnow.explore import ExplorerGrid, explorer_dataset, render_explorer
    from skisnow.ski import camber_profile

    # JAX warm-up, where the optional 'network' extra is installed (the page's default profiles
    # come from the beam: JAX is not needed)
    with contextlib.suppress(ImportError):
        camber_profile("classic", mass=60.0, load_position=-0.12, source="network")
    # workers=0: in this process (the library's default); None: a local cluster of one worker
    # process per core (the default of `skisnow explore`), its start-up included
    for workers, label in ((0, "in-process"), (None, "1 worker per core, as `skisnow explore`")):
        before = load()
        t0, c0 = time.perf_counter(), time.process_time()
        ds = explorer_dataset(["classic", "skate"], ExplorerGrid(), workers=workers)
        t1 = time.perf_counter()
        render_explorer(ds)
        t2, c2 = time.perf_counter(), time.process_time()
        record(
            f"explorer default page (3,120 solves), {label}",
            f"{t2 - t0:.1f} s wall ({t1 - t0:.1f} s solves), {c2 - c0:.1f} s CPU of this process",
            "< 8 s",
            before,
        )


def row_cycle(repeat: int) -> None:
    from skisnow.pipeline import _profiles
    from skisnow.workflows import TEMPLATES, run_cycle, template_history

    before = load()
    worst, worst_flex = 0.0, 0.0
    cases = [(s, t, "rigid") for s in ("classic", "skate") for t in TEMPLATES]
    cases += [("classic", "diagonal", "flexible"), ("skate", "skate_g3", "flexible")]
    for ski, name, model in cases:
        hist = template_history(name, body_mass=70.0, n_frames=100, duration=1.0)
        kw = dict(snow_modulus=100e6, n_points=4096, keep_fields=False, ski_model=model)

        def once(ski=ski, hist=hist, kw=kw):
            _profiles._beam_profile.cache_clear()
            return run_cycle(ski, hist, **kw)

        wall, cpu, ds = medians(once, repeat)
        if model == "rigid":
            worst = max(worst, wall)
        else:
            worst_flex = max(worst_flex, wall)
        print(f"    {ski} {name} {model} ({ds.attrs['route']}): {wall:.3f} s wall, {cpu:.3f} s CPU")
    record("100-frame cycle (slowest rigid)", f"{worst:.3f} s wall", "< 0.3 s", before)
    record(
        "100-frame cycle (slowest flexible)", f"{worst_flex:.3f} s wall", "(not a target)", before
    )


def row_bearing() -> None:
    from skisnow.micro import bearing_area, bearing_sweep, grind_preset, ice_hardness, lowpass

    topo = lowpass(grind_preset("S3", size=1e-3, dx=1e-6))
    hard = ice_hardness(-2.0)
    bearing_area(topo, diameter=600e-6, pressure=20e3, hardness=hard, stride=8)  # compile
    before = load()
    t0, c0 = time.perf_counter(), time.process_time()
    sweep = bearing_sweep(topo, hardness=hard, **BEARING_CASE)
    t, c = time.perf_counter() - t0, time.process_time() - c0
    record(
        "bearing model stride 1 (31 sizes, 2 threads)",
        f"{t:.1f} s wall, {c:.1f} s CPU, {int(sweep.n_positions.sum())} pairs",
        "< 8 s wall, CPU <= 13.8 s",
        before,
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", default=",".join(ROWS), help=f"comma list of {', '.join(ROWS)}")
    ap.add_argument("--repeat", type=int, default=30, help="repeats of the fast solves")
    ap.add_argument("--hertz-sizes", default="512,1024")
    ap.add_argument("--no-peers", action="store_true", help="skip tamaas even if importable")
    ap.add_argument("--sweep-runs", type=int, default=3, help="runs of the sweep row (median)")
    args = ap.parse_args()
    rows = [r.strip() for r in args.rows.split(",") if r.strip()]
    unknown = sorted(set(rows) - set(ROWS))
    if unknown:
        ap.error(f"unknown rows {unknown}; valid: {', '.join(ROWS)}")
    import skisnow

    print(
        f"skisnow {skisnow.__version__} at {os.path.dirname(skisnow.__file__)}; "
        f"{os.cpu_count()} CPUs; load average {load()}"
    )
    for row in rows:
        print(f"\n[{row}]", flush=True)
        if row == "strip":
            row_strip(args.repeat)
        elif row == "scaling":
            row_scaling(args.repeat)
        elif row == "hertz":
            row_hertz([int(s) for s in args.hertz_sizes.split(",")], not args.no_peers)
        elif row == "flexible":
            row_flexible(max(3, args.repeat // 3))
        elif row == "sweep":
            row_sweep(args.sweep_runs)
        elif row == "explore":
            row_explore()
        elif row == "cycle":
            row_cycle(3)
        elif row == "bearing":
            row_bearing()
    print("\n| row | measured | target | load average (1, 5, 15 min) before -> after |")
    print("|---|---|---|---|")
    for r in RESULTS:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":  # required: Dask workers re-import the main module
    main()
