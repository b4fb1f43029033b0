"""skisnow: how a cross-country ski meets the snow.

Three scales, one pipeline:

* :mod:`skisnow.ski` — the ski at the macro scale: Euler–Bernoulli beam with unilateral
  contact (the *virtual ski* and *virtual bench*), practitioner metrics and the camber network.
* :mod:`skisnow.contact` — the apparent (meso-scale) contact: half-space BEM with force and
  moment balance (Kalliorinne et al. 2023, eq. 2–3), zones and their metrics.
* :mod:`skisnow.micro` — the real (micro-scale) contact: grinding topographies, roughness,
  the bearing model of ice grains (Scherge et al. 2021, eq. 1–13).

Inside the library every quantity is in SI units (m, N, Pa, kg, K or °C where the papers use
°C). Field units (mm, kg, MPa, kPa) appear only at the edges: the CLI and file formats.
"""

from importlib.metadata import PackageNotFoundError, version

from skisnow._checks import allow_implausible
from skisnow._errors import (
    ConvergenceError,
    DomainWarning,
    FileFormatError,
    ImplausibleValueError,
    InputError,
    SkisnowError,
    SolverStatus,
    UnsupportedLoadError,
)

try:
    __version__ = version("skisnow")
except PackageNotFoundError:  # pragma: no cover - running from a source tree without install
    __version__ = "0+unknown"

__all__ = [
    "ConvergenceError",
    "DomainWarning",
    "FileFormatError",
    "ImplausibleValueError",
    "InputError",
    "SkisnowError",
    "SolverStatus",
    "UnsupportedLoadError",
    "__version__",
    "allow_implausible",
]
