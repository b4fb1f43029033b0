"""The intervals of a load cycle's summary for an identified ski (issue 25, item 4).

The whole cycle (:func:`~skisnow.workflows.run_cycle`: one case per frame, Kalliorinne et al.
2023, eq. 1–3) is run on posterior samples of the ski (:func:`skisnow.ski.sample_skis`), and the
summary over the stride — when and how long the grip wax touches
(:func:`~skisnow.workflows.kick_contact_summary`), and the contact over the loaded frames — gets
the 95 % intervals of :func:`skisnow.pipeline.sample_intervals`. A cycle costs one contact solve
per loaded frame, so a sample costs a whole cycle: the CLI's default sample count for a cycle is
smaller than for one case, and the Monte Carlo error of the ends is carried with the intervals.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from skisnow.workflows._skis import FleetSki

if TYPE_CHECKING:
    import xarray as xr

    from skisnow.pipeline import Intervals
    from skisnow.workflows._history import LoadHistory

__all__ = ["CYCLE_QUANTITIES", "cycle_intervals", "cycle_quantities"]

#: The summary answers of a cycle that carry intervals (SI): name -> description.
CYCLE_QUANTITIES: dict[str, str] = {
    "kick_contact_time": "time the grip wax touches the snow [s]",
    "kick_fraction_of_loaded": "that time over the loaded time",
    "max_kick_share": "largest load share of the kick zone",
    "max_kick_length": "largest contact length in the kick zone [m]",
    "mean_total_length": "contact length, mean over the loaded frames [m]",
    "peak_pressure": "peak contact pressure over the cycle [Pa]",
    "mean_rear_share": "load share of the rear zone, mean over the loaded frames",
}


def cycle_quantities(ds: xr.Dataset) -> dict[str, float]:
    """The summary answers of a cycle (:data:`CYCLE_QUANTITIES`, SI)."""
    from skisnow.workflows._cycle import kick_contact_summary

    s = kick_contact_summary(ds)
    loaded = np.asarray(ds["loaded"].values, dtype=bool)

    def mean_loaded(var: str, zone: str) -> float:
        v = np.asarray(ds[var].sel(zone=zone).values, dtype=float)[loaded]
        return float(np.mean(v)) if v.size else float("nan")

    return {
        "kick_contact_time": s["contact_time"],
        "kick_fraction_of_loaded": s["fraction_of_loaded"],
        "max_kick_share": s["max_kick_share"],
        "max_kick_length": s["max_kick_length"],
        "mean_total_length": mean_loaded("length", "total"),
        "peak_pressure": float(np.nanmax(ds["max_pressure"].values, initial=0.0)),
        "mean_rear_share": mean_loaded("load_share", "rear"),
    }


def cycle_intervals(
    fs: FleetSki,
    history: LoadHistory,
    ds: xr.Dataset,
    *,
    snow_modulus: float,
    samples: int,
    seed: int = 0,
    n_points: int = 4096,
    ski_model: str = "rigid",
) -> Intervals | None:
    """95 % intervals of :func:`cycle_quantities` of the cycle ``ds`` of ``fs`` (the same history
    and snow) over ``samples`` posterior samples; ``None`` when the ski carries no posterior or
    ``samples`` is 0. Each sample runs the cycle on the beam route (a sample is a new ski no
    network was trained on), without keeping the fields."""
    from skisnow.pipeline import sample_intervals
    from skisnow.workflows._cycle import run_cycle

    if samples <= 0 or not fs.ski.has_posterior:
        return None

    def answers(ski: Any) -> dict[str, float]:
        sample = FleetSki(label=fs.label, ski=ski, origin=fs.origin)
        run = run_cycle(sample, history, snow_modulus=snow_modulus, profile_source="beam",
                        n_points=n_points, keep_fields=False, ski_model=ski_model)  # fmt: skip
        return cycle_quantities(run)

    return sample_intervals(
        fs.ski, answers, estimate=cycle_quantities(ds), samples=samples, seed=seed
    )
