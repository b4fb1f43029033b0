"""Elastic materials of every scale: one :class:`Material` and the presets of both papers.

The apparent contact (:mod:`skisnow.contact`, Kalliorinne et al. 2023, eq. 2) and the micro
contact (:mod:`skisnow.micro`, Scherge et al. 2021, Table 2) describe their bodies with the
same dataclass. Presets:

* :data:`BASE` — the default ski base: UHMWPE as in Kalliorinne et al. (2023, §3.2),
  E = 900 MPa, ν = 0.3. Every default base modulus in skisnow (contact, sweeps, CLI) is this one.
* :data:`STONE` — the granite stone of the SkiSelector bench, E = 70 GPa, ν = 0.3
  (Kalliorinne et al. 2023, Figure 4).
* :data:`ICE` — an ice grain, E = 9.5 GPa, ν = 0.31 (Scherge et al. 2021, Table 2, after
  Böttcher et al. 2017).
* :data:`UHMWPE` — the ski base of the micro contact, E = 840 MPa, ν = 0.46 (Scherge et al.
  2021, §3.4 and Table 2). It differs from :data:`BASE` because the two papers take the base's
  constants from different sources; each scale keeps its paper's value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from skisnow._errors import InputError

__all__ = ["BASE", "ICE", "STONE", "UHMWPE", "Material"]


@dataclass(frozen=True, kw_only=True)
class Material:
    """An isotropic linear-elastic body.

    Parameters
    ----------
    name : str
        Shown in messages and tables.
    modulus : float
        Young's modulus E [Pa], finite and > 0.
    poisson : float
        Poisson's ratio ν [-] in (-1, 0.5); default 0.3.
    """

    name: str
    modulus: float
    poisson: float = 0.3

    def __post_init__(self) -> None:
        if not (math.isfinite(self.modulus) and self.modulus > 0):
            raise InputError(
                f"{self.name}: modulus must be positive and finite [Pa], got {self.modulus}"
            )
        if not -1.0 < self.poisson < 0.5:
            raise InputError(
                f"{self.name}: Poisson ratio must lie in (-1, 0.5), got {self.poisson}"
            )

    @property
    def plane_strain_compliance(self) -> float:
        """(1 − ν²)/E [1/Pa], the body's term in the equivalent modulus (Johnson 1985, eq. 4.22;
        Kalliorinne et al. 2023, eq. 2)."""
        return (1.0 - self.poisson**2) / self.modulus


#: The default ski base (UHMWPE) of Kalliorinne et al. (2023, §3.2): E = 900 MPa, ν = 0.3.
BASE = Material(name="ski base (UHMWPE)", modulus=900e6, poisson=0.3)
#: The granite stone of the SkiSelector bench: E = 70 GPa, ν = 0.3 (Kalliorinne et al. 2023).
STONE = Material(name="stone", modulus=70e9, poisson=0.3)
#: An ice grain (Scherge et al. 2021, Table 2, after Böttcher et al. 2017): E = 9.5 GPa, ν = 0.31.
ICE = Material(name="ice", modulus=9.5e9, poisson=0.31)
#: The ski base of the micro contact (Scherge et al. 2021, §3.4): E = 840 MPa, ν = 0.46.
UHMWPE = Material(name="UHMWPE", modulus=840e6, poisson=0.46)
