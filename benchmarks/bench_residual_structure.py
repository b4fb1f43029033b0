"""The structure of a fit's residuals (issue 25, seventh pass: why residual-based bands miss z0).

Run:  nice -n 10 uv run python benchmarks/bench_band_variants.py --fit --skis 1-4
          --noise-um 5 10 --jobs 2 --store DIR
      uv run python benchmarks/bench_residual_structure.py --store DIR 1 2 3 4

On fits cached by ``bench_band_variants.py --fit`` (shop plan, independent 1 mm reference
bench): the pooled autocovariance of the σ-normalised residuals along each profile (lags 1, 2,
4, 8, 16, 32 bins; a white noise reads 0 ± ~0.02) and their mean product between two load cases
at the same station, for cases at the same load position and at the other. z0 is common to all
K load cases, so the fit absorbs what is common to them at every station: the residuals at a
station then sum to about zero over the cases and their cross-case covariance is about
-c₀ / (K - 1) (-0.09 for K = 12). The part of the bench's error common to all load cases,
which moves z0, is not in the residuals.
"""

from __future__ import annotations

import argparse
import pickle
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import STORE

LAGS = (1, 2, 4, 8, 16, 32)


def structure(g: dict) -> tuple[float, list[float], float, float, int]:
    sol, pr = g["sol"], g["problem"]
    r = sol.fun
    sizes = [c.x.size for c in pr.cases]
    parts = np.split(r, np.cumsum(sizes)[:-1])
    ac = []
    for lag in LAGS:
        num = sum(float(p[:-lag] @ p[lag:]) for p in parts if p.size > lag)
        den = sum(p.size - lag for p in parts if p.size > lag)
        ac.append(num / max(den, 1))
    same, other = [], []
    for i, ci in enumerate(pr.cases):
        for j in range(i + 1, len(pr.cases)):
            cj = pr.cases[j]
            xi, xj = np.round(ci.x * 1e4).astype(int), np.round(cj.x * 1e4).astype(int)
            com, ii, jj = np.intersect1d(xi, xj, return_indices=True)
            if com.size >= 20:
                v = float(np.mean(parts[i][ii] * parts[j][jj]))
                (same if abs(ci.position - cj.position) < 1e-6 else other).append(v)
    return float(np.mean(r**2)), ac, float(np.mean(same)), float(np.mean(other)), len(sizes)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("skis", nargs="+")
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--store", default=str(STORE))
    a = ap.parse_args()
    print("| ski | noise µm | c₀ | autocovariance at lags " + ", ".join(map(str, LAGS)) +
          " bins | cross-case, same position | other position | -c₀/(K-1) |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for s in a.skis:
        for n in a.noise_um:
            path = Path(a.store) / f"fit_{s}_shop_{n:g}.pkl"
            if not path.exists():
                continue
            with open(path, "rb") as fh:
                c0, ac, same, other, k = structure(pickle.load(fh))
            print(f"| {s} | {n:g} | {c0:.3f} | {' / '.join(f'{v:+.3f}' for v in ac)} | "
                  f"{same:+.3f} | {other:+.3f} | {-c0 / (k - 1):+.3f} |")  # fmt: skip


if __name__ == "__main__":
    main()
