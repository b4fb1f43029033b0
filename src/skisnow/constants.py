"""Physical constants and unit conversions used across skisnow (SI inside)."""

from __future__ import annotations

#: Standard acceleration of gravity, m/s² (CGPM 1901). The load of a mass m on the ski is m·g.
STANDARD_GRAVITY: float = 9.80665

#: Unit factors: multiply a value in the named unit by the factor to get SI.
MM: float = 1e-3
UM: float = 1e-6
KPA: float = 1e3
MPA: float = 1e6
GPA: float = 1e9
CM2: float = 1e-4
