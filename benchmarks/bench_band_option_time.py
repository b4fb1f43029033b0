"""The cost of the model-discrepancy bands in an identification (issue 25, seventh pass).

Run:  nice -n 10 uv run python benchmarks/bench_band_option_time.py

``identify_ski`` on issue 25's ski's shop bench (the independent 1 mm reference bench, 5 µm
seeded noise, ``bench_identify_coverage.bench_of``) without and with ``discrepancy_bands``,
two interleaved runs each: CPU (``time.process_time``) and wall seconds, the exit, the band
coverage of EI and z0 at the determined stations and the ``bands`` detail of the ski file.
Report the load average printed with the times.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import bench_of, errors, true_ski

from skisnow.identify import identify_ski


def main() -> None:
    cache = Path.home() / ".cache" / "skisnow-identify-bench"
    bench = bench_of("issue25", "shop", 5.0, cache)
    true = true_ski("issue25")
    print("load", os.getloadavg())
    for _ in range(2):
        for disc in (False, True):
            t, w = time.process_time(), time.perf_counter()
            res = identify_ski(bench, discrepancy_bands=disc)
            cpu, wall = time.process_time() - t, time.perf_counter() - w
            e = errors(res, true)
            bands = dict(res.ski.provenance.details)["bands"]
            print(f"discrepancy_bands={disc}: CPU {cpu:.2f} s, wall {wall:.1f} s, exit "
                  f"{0 if res.converged else 3}, EI in {e['ei_in']}/{e['ei_n']}, z0 in "
                  f"{e['z0_in']}/{e['z0_n']}, z0 half-width {e['z0_hw']:.1f} µm | {bands}",
                  flush=True)  # fmt: skip
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
