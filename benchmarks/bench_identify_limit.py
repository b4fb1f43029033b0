"""What the bench data can determine at all (issue 25, eighth pass: item 5's accuracy targets).

Run:  uv run python benchmarks/bench_identify_limit.py [--skis 1001 1002 1003 issue25]
      [--plans shop full] [--noise-um 5 10] [--n-stiffness 60 120] [--population 2000]

For each ski (``bench_identify_coverage.true_ski``: the held-out skis 1001-1003 and issue 25's
ski), plan (shop, full) and noise, the forward model of the fit (``skisnow.identify._model``:
the same mesh, bins, splines and σ-normalised residuals as ``identify_ski``'s defaults) is
linearised AT THE TRUTH p_t (the true log EI and z0 projected on the fit's splines by least
squares, ``bench_z0_linear_error.truth_parameters``): residuals r(p_t + δ) ≈ r₀ + J δ, white
unit noise in r. A penalised estimator with penalty rows P, t then errs by

    δ = -A⁻¹ (Jᵀ r₀ + Pᵀ (P p_t - t)),  A = JᵀJ + PᵀP,  Cov δ = A⁻¹ JᵀJ A⁻¹   (noise)

and its expected squared error of log EI over -450…+400 mm (5 mm grid) and of z0 modulo its
best line over the stations between the outermost contacts of the truth (5 mm grid) is the
squared bias (the splines' own error against the true curves, plus the penalty's pull, plus,
in the ``bench`` columns, the reference bench's model error r₀ at the truth) plus the trace of
the covariance. Printed (all figures rms; EI as 100 × log error, i.e. % for small errors):

* ``floor``: the splines' own error (the best any estimator in this basis can do, λ aside);
* ``oracle``: the penalised estimator of ``identify_ski`` (its penalty rows) with exact data of
  the projected truth (r₀ = noise only), minimised over λ ∈ ``--lambdas`` (log-EI smoothness)
  × λ_z ∈ ``--lambdas-z`` (z0 smoothness) KNOWING the truth, separately for EI and for z0,
  with the minimising λ; and at λ = 1 (what GCV picks on these benches), λ_z = 1;
* ``bench``: the same estimator on the reference bench (r₀ its noise-free residual at the
  projected truth: its 1 mm contact error and the splines' error in heights), at λ = 1 and
  at its best λ: the linear prediction of the actual fit;
* ``lmmse``: the linear minimum-mean-square-error estimator under a POPULATION PRIOR, the mean
  and covariance of (log EI, z0) coefficients on the fit's splines over ``--population`` skis of
  ``skisnow.bench.random_ski`` of the ski's kind (seeds ``--pop-seed`` onwards: not 1-24, not
  1001-1003), with a diagonal floor (``--jitter-ei`` in log EI, ``--jitter-z-um`` in z0) so the
  covariance is proper where the generator does not vary: given this ski (bias + noise, exact
  data of the projected truth), on the bench, and its Bayes risk (the posterior rms averaged
  over the population: what it is worth on a ski drawn from that population). Skis 1001-1003
  ARE draws of that generator and issue 25's ski is ``plausible_ski`` with parameters inside
  its classic ranges (three at a bound): the prior flatters all four; no out-of-family ski is
  in this table; ``shipped:classic`` / ``shipped:skate`` (``--skis``) are: the shipped spline
  skis, calibrated to the paper's captions (``skisnow.ski.get_ski``), benches made alike.

The Jacobian costs one evaluation per ski × plan × basis (0.05-0.2 s); the population 2 ms a
ski. Report the load average (printed) with the times.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import bench_of, true_ski

from skisnow.identify._cases import _bench_cases, load_cases
from skisnow.identify._identify import DEFAULT_ELEMENT_LENGTH, _camber_coefficients
from skisnow.identify._model import _design, _Problem
from skisnow.ski import DEFAULT_BOOT_LENGTH

CACHE = Path.home() / ".cache" / "skisnow-identify-bench"
EI_WINDOW = (-0.45, 0.40)
FINE = np.round(np.arange(-1.10, 1.1005, 0.001), 6)


def problem_of(name: str, plan: str, n_stiffness: int, cache: Path = CACHE, dx_mm: float = 1.0,
               sigma: float = 1e-6):  # fmt: skip
    """The fit's problem on the noise-free reference bench (identify_ski's defaults: 10 mm
    elements, 5 mm bins, z0 knots at the station spacing), σ = ``sigma`` for every case."""
    bench = bench_of(name, plan, 0.0, cache, dx_mm)
    md, raw = bench.metadata, _bench_cases(bench, bench.ski_name(None))
    x_tail, x_tip = float(md["x_tail_mm"]) * 1e-3, float(md["x_tip_mm"]) * 1e-3
    boot = float(md.get("boot_length_mm", DEFAULT_BOOT_LENGTH * 1e3)) * 1e-3
    nodes = np.linspace(x_tail, x_tip, max(8, round((x_tip - x_tail) / DEFAULT_ELEMENT_LENGTH)) + 1)
    cases = load_cases(raw, nodes, boot, 0.005)[0]
    return _Problem(cases, nodes, n_stiffness, _camber_coefficients(raw, x_tip - x_tail), sigma)


def projector(pr):
    """``(M_e, M_z)``: the least-squares maps from curves on :data:`FINE` (within the fit's
    outer nodes) to the fit's log-EI coefficients and z0 coefficients φ (modulo a line)."""
    x = FINE[(pr.nodes[0] <= FINE) & (pr.nodes[-1] >= FINE)]
    bz = _design(pr.t_z, x) @ pr.q_z
    lin = np.stack([np.ones_like(x), x], 1)
    m_e = np.linalg.pinv(_design(pr.t_e, x))
    m_z = np.linalg.pinv(np.hstack([bz, lin]))[: bz.shape[1]]
    return x, m_e, m_z


def curves(ski, x):
    xc = np.clip(x, ski.x_tail, ski.x_tip)
    return np.log(ski.stiffness(xc)), ski.free_camber(xc)


def truth_parameters(pr, true) -> np.ndarray:
    x, m_e, m_z = projector(pr)
    le, z = curves(true, x)
    return np.concatenate([m_e @ le, m_z @ z])


def population(pr, kind: str, n: int, seed0: int, jitter_ei: float, jitter_z: float):
    """Mean and covariance of the fit's coefficients over ``n`` skis of ``random_ski(seed,
    kind)``, seeds ``seed0``…, plus the diagonal floor."""
    from skisnow.bench import random_ski

    x, m_e, m_z = projector(pr)
    ps = []
    for s in range(seed0, seed0 + n):
        le, z = curves(random_ski(s, kind=kind), x)
        ps.append(np.concatenate([m_e @ le, m_z @ z]))
    ps = np.array(ps)
    mu, cov = ps.mean(0), np.cov(ps, rowvar=False)
    cov[np.diag_indices(pr.n_e)] += jitter_ei**2
    iz = np.arange(pr.n_e, pr.n_params)
    cov[iz, iz] += jitter_z**2
    return mu, cov


def metrics(pr, true, contacts):
    """``(B_e, e_e, B_z, e_z)``: log EI over :data:`EI_WINDOW` and z0 (minus its best line)
    between the outermost contacts, both on 5 mm grids, as linear maps of δp, and the splines'
    own errors there at the projected truth."""
    p_t = truth_parameters(pr, true)
    xe = np.arange(EI_WINDOW[0], EI_WINDOW[1] + 1e-9, 0.005)
    b_e = np.hstack([_design(pr.t_e, xe), np.zeros((xe.size, pr.n_z - 2))])
    e_e = b_e @ p_t - np.log(true.stiffness(xe))
    xz = np.arange(contacts[0], contacts[1] + 1e-9, 0.005)
    lin = np.stack([np.ones_like(xz), xz], 1)
    proj = np.eye(xz.size) - lin @ np.linalg.pinv(lin)
    b_z = proj @ np.hstack([np.zeros((xz.size, pr.n_e)), _design(pr.t_z, xz) @ pr.q_z])
    e_z = b_z @ p_t - proj @ true.free_camber(xz)
    return p_t, b_e, e_e, b_z, e_z, xe


def risk(b, e, bias, cov, parts: bool = False):
    """rms over the grid of the expected squared error: (e + B bias)² + diag(B Cov Bᵀ); with
    ``parts`` the two pointwise (bias², variance) instead."""
    b2, var = (e + b @ bias) ** 2, np.sum((b @ cov) * b, axis=1)
    return (b2, var) if parts else float(np.sqrt(np.mean(b2 + var)))


def along(x, b2, var, step: float = 0.1) -> str:
    """rms error (bias/sd, ×100: % of log EI) in windows of ``step`` from -450 mm."""
    out = []
    for a in np.arange(x[0], x[-1], step):
        m = (x >= a - 1e-9) & (x < a + step - 1e-9)
        out.append(f"{a * 1e3:.0f}:{100 * np.sqrt(b2[m].mean()):.1f}/"
                   f"{100 * np.sqrt(var[m].mean()):.1f}")  # fmt: skip
    return " ".join(out)


def estimator(jtj, jtr0, p_t, p_mat, target):
    """Bias without and with the bench's model error, and the noise covariance, of the
    penalised (or prior) estimator linearised at the truth (module docstring)."""
    a_inv = np.linalg.inv(jtj + p_mat.T @ p_mat)
    b_pen = -a_inv @ (p_mat.T @ (p_mat @ p_t - target))
    return b_pen, b_pen - a_inv @ jtr0, a_inv @ jtj @ a_inv, a_inv


def prior_rows(mu, cov):
    """Penalty rows of a Gaussian prior: PᵀP = Σ⁻¹, t = P μ."""
    p_mat = np.linalg.cholesky(np.linalg.inv(cov)).T
    return p_mat, p_mat @ mu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1001", "1002", "1003", "issue25"])
    ap.add_argument("--plans", nargs="+", default=["shop", "full"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--n-stiffness", nargs="+", type=int, default=[60, 120])
    ap.add_argument("--lambdas", nargs="+", type=float,
                    default=[10.0**k for k in range(-2, 7)])  # fmt: skip
    ap.add_argument("--lambdas-z", nargs="+", type=float,
                    default=[10.0**k for k in range(-2, 7)])  # fmt: skip
    ap.add_argument("--population", type=int, default=2000)
    ap.add_argument("--pop-seed", type=int, default=100_000)
    ap.add_argument("--jitter-ei", type=float, default=0.05, help="log-EI sd floor")
    ap.add_argument("--jitter-z-um", type=float, default=2.0, help="z0 sd floor [µm]")
    ap.add_argument("--cache", default=str(CACHE))
    ap.add_argument("--dx-mm", type=float, default=1.0,
                    help="grid of the reference bench [mm] (issue 25: 1 mm)")  # fmt: skip
    ap.add_argument(
        "--along",
        action="store_true",
        help="also the bias / sd of log EI in 100 mm windows (oracle, LMMSE)",
    )
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    print(
        "| ski | plan | noise µm | n_E | EI floor % | oracle EI % (λ, λ_z) | oracle EI at λ=1 | "
        "bench EI at λ=1 / best (λ) | LMMSE EI: this ski / bench / Bayes | z0 floor µm | "
        "oracle z0 µm (λ, λ_z) | oracle z0 at λ=1 | bench z0 at λ=1 / best | "
        "LMMSE z0: this ski / bench / Bayes | CPU s |"
    )
    print("| " + " | ".join(["---"] * 15) + " |")
    for name in a.skis:
        true = true_ski(name)
        for plan in a.plans:
            for n_e in a.n_stiffness:
                t0 = time.process_time()
                pr = problem_of(name, plan, n_e, Path(a.cache), a.dx_mm)
                p_t = truth_parameters(pr, true)
                r0, jac = pr.evaluate(p_t, jacobian=True)  # σ = 1 µm
                cont = np.concatenate([c for c in pr.contacts if c.size])
                p_t, b_e, e_e, b_z, e_z, xe = metrics(pr, true, (cont.min(), cont.max()))
                mu, cov = population(pr, true.kind, a.population, a.pop_seed, a.jitter_ei,
                                     a.jitter_z_um * 1e-6)  # fmt: skip
                pop_p, pop_t = prior_rows(mu, cov)
                for noise in a.noise_um:
                    j, r = jac / noise, r0 / noise
                    jtj, jtr0 = j.T @ j, j.T @ r
                    grid = {}
                    for lam in a.lambdas:
                        for lz in a.lambdas_z:
                            p_mat = pr.penalty_matrix(lam, lz)
                            tgt = pr.penalty_target(lam, lz)
                            b0, b1, c, _ = estimator(jtj, jtr0, p_t, p_mat, tgt)
                            grid[lam, lz] = (
                                *(risk(b_e, e_e, b, c) for b in (b0, b1)),
                                *(risk(b_z, e_z, b, c) for b in (b0, b1)),
                            )
                    ke = min(grid, key=lambda k: grid[k][0])
                    kz = min(grid, key=lambda k: grid[k][2])
                    kb = min(grid, key=lambda k: grid[k][1])
                    kbz = min(grid, key=lambda k: grid[k][3])
                    d1 = grid[1.0, 1.0]
                    b0, b1, c, post = estimator(jtj, jtr0, p_t, pop_p, pop_t)
                    zero = np.zeros_like(p_t)
                    le = [risk(b_e, e_e, b0, c), risk(b_e, e_e, b1, c),
                          risk(b_e, 0 * e_e, zero, post)]  # fmt: skip
                    lz_ = [risk(b_z, e_z, b0, c), risk(b_z, e_z, b1, c),
                           risk(b_z, 0 * e_z, zero, post)]  # fmt: skip
                    cpu = time.process_time() - t0
                    f = np.sqrt(np.mean(e_e**2)) * 100
                    fz = np.sqrt(np.mean(e_z**2)) * 1e6
                    print(
                        f"| {name} | {plan} | {noise:g} | {n_e} | {f:.2f} | "
                        f"{100 * grid[ke][0]:.2f} ({ke[0]:g}, {ke[1]:g}) | {100 * d1[0]:.2f} | "
                        f"{100 * d1[1]:.2f} / {100 * grid[kb][1]:.2f} ({kb[0]:g}, {kb[1]:g}) | "
                        f"{100 * le[0]:.2f} / {100 * le[1]:.2f} / {100 * le[2]:.2f} | {fz:.2f} | "
                        f"{1e6 * grid[kz][2]:.2f} ({kz[0]:g}, {kz[1]:g}) | {1e6 * d1[2]:.2f} | "
                        f"{1e6 * d1[3]:.2f} / {1e6 * grid[kbz][3]:.2f} | "
                        f"{1e6 * lz_[0]:.2f} / {1e6 * lz_[1]:.2f} / {1e6 * lz_[2]:.2f} | "
                        f"{cpu:.1f} |",
                        flush=True,
                    )
                    if a.along:
                        p_mat, tgt = pr.penalty_matrix(*ke), pr.penalty_target(*ke)
                        b0, _, c, _ = estimator(jtj, jtr0, p_t, p_mat, tgt)
                        ob2, ovar = risk(b_e, e_e, b0, c, parts=True)
                        b0, _, c, _ = estimator(jtj, jtr0, p_t, pop_p, pop_t)
                        lb2, lvar = risk(b_e, e_e, b0, c, parts=True)
                        print(f"    oracle EI bias/sd {100 * np.sqrt(ob2.mean()):.2f}/"
                              f"{100 * np.sqrt(ovar.mean()):.2f} %, along {along(xe, ob2, ovar)}\n"
                              f"    LMMSE EI bias/sd {100 * np.sqrt(lb2.mean()):.2f}/"
                              f"{100 * np.sqrt(lvar.mean()):.2f} %, along {along(xe, lb2, lvar)}",
                              flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
