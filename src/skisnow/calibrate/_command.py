"""The calibration program: the options of one run and the run itself (``skisnow calibrate``).

Fits each ski (:func:`~skisnow.calibrate.fit`), prints its report and writes the record
``OUT/calibration_<ski>[_caption_only]<tag>.json``; or prints the table of the shipped skis
(``shipped``); or writes the ski of a record as the shipped ski file (``write_shipped``, with
``ski_out`` to any file). Options in field units, as on the command line.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from skisnow.calibrate._fit import fit, report
from skisnow.calibrate._params import DENSE_KNOTS, KNOTS, record_vector, shipped_vector
from skisnow.calibrate._residuals import FitOptions
from skisnow.calibrate._shipped import write_shipped
from skisnow.paper import REPRODUCTION_TOLERANCES
from skisnow.ski import shipped_ski_path

__all__ = ["CalibrationRun", "run_calibration"]


@dataclass(frozen=True, kw_only=True)
class CalibrationRun:
    """The options of one run of the calibration (those of ``skisnow calibrate``, same names).

    Attributes
    ----------
    skis
        Which skis (``'classic'``, ``'skate'``); empty: both.
    seed, generations, popsize, sigma, max_minutes
        Of the differential evolution: seed, generations, population per parameter, spread of
        the population around the starts (unit box), stop after this time [min].
    caption_only
        No plausibility terms (what the captions alone want).
    shipped
        Only the table of the shipped skis (no fit).
    out, tag
        The folder of the records and a suffix of their names.
    start
        Starts: calibration records (JSON paths) or ``'shipped'``; empty: the built-in start.
    hinge_weight, topology_weight, ei_shape_weight
        Weights of the plausibility hinges, the topology and the EI-shape residuals.
    bench_topology, findings, front_pressure_growth_min
        The skate's topology also on the bench; the findings' thresholds (rear growth ≥ 1.4x,
        front mean pressure rise ≥ 1.5x or ``front_pressure_growth_min``, load share change
        ≤ 0.04).
    polish_starts
        Polish every start by least squares before the DE.
    knots
        ``'default'`` (the shipped skis' knots) or ``'dense'``.
    k_range
        The skate's stiffness k limits [N/mm]; None: the team means 225-251.
    kick_gap_max
        Classic: the largest gap left in the kick zone at twice the body weight [mm]; None: off.
    write_shipped, ski_out
        Write the ski of this record as the shipped ski file (or to ``ski_out``) instead.
    reproduction
        Fit a reproduction ski (issue 30): the captions alone (no plausibility terms), in
        units of :data:`skisnow.paper.REPRODUCTION_TOLERANCES` (10 %, 10 %, 3 points, the
        shares Figures 4 and 7 imply held too); records ``calibration_<ski>_k22<tag>.json``,
        written as the ski ``<ski>-k22``.
    """

    skis: tuple[str, ...] = ()
    seed: int = 0
    generations: int = 30
    popsize: int = 6
    caption_only: bool = False
    shipped: bool = False
    out: Path = Path("calibration")
    start: tuple[str, ...] = ()
    hinge_weight: float = 2.0
    topology_weight: float = 0.0
    max_minutes: float = math.inf
    ei_shape_weight: float = 0.0
    bench_topology: bool = False
    findings: bool = False
    front_pressure_growth_min: float | None = None
    polish_starts: bool = False
    tag: str = ""
    knots: str = "default"
    k_range: tuple[float, float] | None = None
    sigma: float = 0.08
    kick_gap_max: float | None = None
    write_shipped: Path | None = None
    ski_out: Path | None = None
    reproduction: bool = False


def run_calibration(run: CalibrationRun) -> list[Path]:
    """Run the calibration as ``run`` says (module docstring); return the records written."""
    if run.write_shipped is not None:
        doc = json.loads(run.write_shipped.read_text())
        name = doc["ski"] + ("-k22" if doc.get("reproduction") else "")
        print(write_shipped(doc, run.ski_out or shipped_ski_path(name)))
        return []
    run.out.mkdir(parents=True, exist_ok=True)
    opts = FitOptions(
        plausibility=not (run.caption_only or run.reproduction),
        hinge_weight=run.hinge_weight,
        topology_weight=run.topology_weight,
        ei_shape_weight=run.ei_shape_weight,
        bench_topology=run.bench_topology or run.findings,
        share_change=run.findings,
    )
    if run.findings:
        opts = replace(opts, rear_growth_min=1.4, front_pressure_growth_min=1.5)
        if run.front_pressure_growth_min is not None:
            opts = replace(opts, front_pressure_growth_min=run.front_pressure_growth_min)
    if run.k_range is not None:
        opts = replace(opts, k_range_n_per_mm=(run.k_range[0], run.k_range[1]))
    if run.kick_gap_max is not None:
        opts = replace(opts, kick_gap_max_mm=run.kick_gap_max)
    if run.reproduction:
        opts = replace(opts, tolerances=REPRODUCTION_TOLERANCES)
    written = []
    saved = dict(KNOTS)
    if run.knots == "dense":
        KNOTS.update(DENSE_KNOTS)
    try:
        for kind in run.skis or ["classic", "skate"]:
            if run.shipped:
                report(kind, shipped_vector(kind), opts)
                continue
            starts = []
            for src in run.start or []:
                if src == "shipped":
                    starts.append(shipped_vector(kind))
                    continue
                starts.append(record_vector(kind, json.loads(Path(src).read_text())))
            result = fit(
                kind, seed=run.seed, generations=run.generations, popsize=run.popsize,
                opts=opts, start=starts[0] if starts else None,
                sigma=run.sigma, more_starts=tuple(starts[1:]), max_seconds=60 * run.max_minutes,
                polish_starts=run.polish_starts,
            )  # fmt: skip
            doc = report(kind, np.array(result["vector"]), opts)
            doc |= {
                "seed": run.seed,
                "generations": run.generations,
                "popsize": run.popsize,
                "plausibility_terms": opts.plausibility,
                "reproduction": run.reproduction,
                "tolerances": {
                    "length": opts.tolerances.length,
                    "pressure": opts.tolerances.pressure,
                    "share": opts.tolerances.share,
                    "implied_shares": opts.tolerances.implied_shares,
                },
                "hinge_weight": run.hinge_weight,
                "topology_weight": run.topology_weight,
                "ei_shape_weight": run.ei_shape_weight,
                "bench_topology": run.bench_topology or run.findings,
                "findings": run.findings,
                "rear_growth_min": opts.rear_growth_min,
                "front_pressure_growth_min": opts.front_pressure_growth_min,
                "k_range_n_per_mm": list(opts.k_range_n_per_mm),
                "kick_gap_max_mm": opts.kick_gap_max_mm,
                "starts": list(run.start) or ["START"],
                "knots": run.knots,
                "polish_starts": run.polish_starts,
                "sigma": run.sigma,
                "evaluations": result["evaluations"],
                "generations_run": result["generations_run"],
                "seconds": round(result["seconds"], 1),
            }
            tag = (
                "_k22" if run.reproduction else "_caption_only" if run.caption_only else ""
            ) + run.tag
            path = run.out / f"calibration_{kind}{tag}.json"
            path.write_text(json.dumps(doc, indent=1))
            seconds, evaluations = result["seconds"], result["evaluations"]
            print(f"({kind}: {seconds:.0f} s, {evaluations} evaluations) → {path}")
            written.append(path)
    finally:  # the knots are the run's, not the process's
        KNOTS.clear()
        KNOTS.update(saved)
    return written
