"""Published numbers of Scherge, Stoll & Moseler (2021), Front. Mech. Eng. 7:659995 (CC BY 4.0).

Transcribed from Tables 1–4 of Scherge et al. (2021) as printed (lengths in µm as in the paper;
this module is data, so it keeps the paper's units and says so in every name). Known oddities,
kept as printed:

* Table 4 "Sq 213" for S2 is read as 2.13 µm (a lost decimal point; Sq ≥ Sa must hold and
  Sa = 1.63 µm).
* Table 4 "Sku" values 0.33–2.83 are below 1, impossible for the fourth standardised moment
  (always ≥ 1; 3 for a Gaussian); the paper's Sku is presumably an excess kurtosis or another
  definition. skisnow's own Sku is the ISO 25178 one (no −3).
* The S1 average in Table 3 is 7.64 s, but the mean of its three runs is 7.64 s; S4's runs
  average 7.35 s, S5's 7.45 s — consistent; S2's 7.373 and S3's 7.333 round as printed.
"""

from __future__ import annotations

STRUCTURES: tuple[str, ...] = ("S1", "S2", "S3", "S4", "S5")
DESCRIPTIONS: dict[str, str] = {
    "S1": "linear/fine",
    "S2": "linear/medium",
    "S3": "linear/coarse",
    "S4": "linear/multiple",
    "S5": "cross-hatched",
}

#: Table 1: line roughness after grinding [µm].
TABLE1_RA_UM: dict[str, float] = {"S1": 1.51, "S2": 1.78, "S3": 2.88, "S4": 1.61, "S5": 1.37}
TABLE1_RZ_UM: dict[str, float] = {"S1": 8.97, "S2": 10.6, "S3": 12.7, "S4": 10.5, "S5": 10.1}

#: Table 2: properties at −2 °C (modulus and hardness in MPa).
TABLE2 = {
    "ice": {"youngs_modulus_mpa": 9500.0, "poisson": 0.31, "hardness_mpa": 15.9},
    "UHMWPE": {"youngs_modulus_mpa": 840.0, "poisson": 0.46, "hardness_mpa": 42.3},
}

#: Table 3: sliding times over 40 m [s], three runs, published average, STD and ranking.
TABLE3_RUNS_S: dict[str, tuple[float, float, float]] = {
    "S1": (7.52, 7.67, 7.73),
    "S2": (7.32, 7.39, 7.41),
    "S3": (7.23, 7.34, 7.43),
    "S4": (7.28, 7.34, 7.43),
    "S5": (7.35, 7.49, 7.51),
}
TABLE3_AVERAGE_S: dict[str, float] = {"S1": 7.64, "S2": 7.37, "S3": 7.33, "S4": 7.35, "S5": 7.45}
TABLE3_STD_S: dict[str, float] = {"S1": 0.11, "S2": 0.05, "S3": 0.10, "S4": 0.08, "S5": 0.09}
TABLE3_RANK: dict[str, int] = {"S1": 5, "S2": 3, "S3": 1, "S4": 2, "S5": 4}

#: Table 4: areal roughness (Sa, Sq in µm; Sdq, Ssk, Sku dimensionless) and the published
#: Pearson r of each with the dimensionless sliding time (eq. 11).
TABLE4: dict[str, dict[str, float]] = {
    "Sa": {"S1": 1.86, "S2": 1.63, "S3": 2.84, "S4": 2.45, "S5": 1.81},
    "Sq": {"S1": 2.79, "S2": 2.13, "S3": 6.49, "S4": 4.62, "S5": 3.00},
    "Sdq": {"S1": 0.135, "S2": 0.107, "S3": 0.137, "S4": 0.175, "S5": 0.126},
    "Ssk": {"S1": 0.41, "S2": 0.54, "S3": 0.18, "S4": 0.29, "S5": 0.67},
    "Sku": {"S1": 1.68, "S2": 2.83, "S3": 0.33, "S4": 0.70, "S5": 2.22},
}
TABLE4_R_PUBLISHED: dict[str, float] = {
    "Sa": -0.62,
    "Sq": -0.65,
    "Sdq": -0.20,
    "Ssk": 0.38,
    "Sku": 0.41,
}

#: §4.4 / Fig. 8: Pearson r of the grain-averaged fractional contact area with sliding time.
R_GRAIN_AVERAGED_AREA: float = 0.93
