"""An analytic chunk function for testing the sweep engine independently of the solvers.

Two rigid cylinders of radius R (a "rear" one at x_r and a "front" one at x_f) carry the load m·g
at x_m; statics (force and moment balance, the lever rule) splits it, and each pressed into the
elastic half-space gives the Hertz line contact (Johnson, Contact Mechanics, §4.2, per unit
width w, plane strain with the effective modulus E* = E'/2 of eq. 2):

    half-width a = sqrt(4 P' R / (π E*)),  p_max = 2 P' / (π a),  mean = P' / (2 a),

P' = load / w. Every variable is a closed-form function of the grid coordinates, so a test can
recompute the whole dataset independently and check that every chunk landed in its region.
``SKISNOW_TEST_CHUNK_DELAY`` (seconds) slows each chunk down, for the kill/resume test.
"""

from __future__ import annotations

import os
import time

import numpy as np

G = 9.80665
R = 20.0  # m: radius of the cylinders
W = 0.044  # m: width of the ski
X_REAR, X_FRONT = -0.5, 0.6  # m


def effective(e_snow: float, spec) -> float:
    nu = spec.poisson
    return 2.0 / ((1 - nu**2) / spec.base_modulus + (1 - nu**2) / e_snow)


def hertz(load: np.ndarray, e_prime: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    p_line = load / W
    e_star = e_prime / 2.0
    a = np.sqrt(4 * p_line * R / (np.pi * e_star))
    return 2 * a, p_line / (2 * a), 2 * p_line / (np.pi * a)


def hertz_chunk(spec, ski: str, load_position: float, snow_modulus: float) -> dict:
    delay = float(os.environ.get("SKISNOW_TEST_CHUNK_DELAY", "0"))
    if delay:
        time.sleep(delay)
    m = np.asarray(spec.masses, dtype=float)
    load = m * G
    share_front = (load_position - X_REAR) / (X_FRONT - X_REAR)
    shares = {"rear": 1 - share_front, "middle": 0.0, "front": share_front}
    # the regions: the cylinders lie in the rear and front glide (outside any kick zone)
    shares |= {"rear_glide": shares["rear"], "kick_zone": 0.0, "front_glide": shares["front"]}
    e_prime = effective(snow_modulus, spec)
    n_m, n_z = m.size, len(spec.zones)
    out = {
        k: np.zeros((n_m, n_z))
        for k in (
            "length_mm",
            "area_cm2",
            "mean_pressure_kpa",
            "max_pressure_kpa",
            "load_share",
            "breitschaedel_length_mm",
            "breitschaedel_area_cm2",
        )
    }
    out["patches"] = np.zeros((n_m, n_z), dtype=int)
    for q, zone in enumerate(spec.zones):
        if zone == "total":
            continue
        s = shares[zone]
        if s == 0:
            out["mean_pressure_kpa"][:, q] = np.nan
            continue
        length, mean, pmax = hertz(s * load, e_prime)
        out["length_mm"][:, q] = length * 1e3
        out["area_cm2"][:, q] = length * W * 1e4
        out["mean_pressure_kpa"][:, q] = mean / 1e3
        out["max_pressure_kpa"][:, q] = pmax / 1e3
        out["load_share"][:, q] = s
        out["patches"][:, q] = 1
        # "Breitschädel": where the undeformed cylinder lies within 50 µm of the plane
        out["breitschaedel_length_mm"][:, q] = 2 * np.sqrt(2 * R * 50e-6) * 1e3
    q = spec.zones.index("total")
    for name in ("length_mm", "area_cm2", "load_share", "patches", "breitschaedel_length_mm"):
        out[name][:, q] = out[name][:, :q].sum(axis=1)  # the paper's zones, before "total"
    out["mean_pressure_kpa"][:, q] = load / (out["area_cm2"][:, q] * 1e-4) / 1e3
    out["max_pressure_kpa"][:, q] = np.nanmax(out["max_pressure_kpa"][:, :q], axis=1)
    out["breitschaedel_area_cm2"] = out["breitschaedel_length_mm"] * W * 10
    out["iterations"] = np.full(n_m, 1 + spec.skis.index(ski))
    out["residual"] = np.zeros(n_m)
    out["converged"] = np.ones(n_m, dtype=bool)
    return out
