"""The snow as one object across scales: modulus (macro), temperature → ice hardness and grain
sizes (micro), density → modulus; presets for the snow types a technician names; snow files.

* :class:`Snow` — E_counter and ν (Kalliorinne et al. 2023, eq. 2), temperature → H_ice
  (Scherge et al. 2021, eq. 2–3), grain-size distribution (eq. 12) or measured diameters;
* :func:`modulus_from_density` — Scapozza (2004) or Gerling et al. (2017);
* :func:`gamma_grains` — f(D) of eq. 12 about a mode;
* :data:`SNOW_PRESETS` — ``new``, ``fine-grained``, ``coarse``, ``machine-made``, ``wet``, with
  sources and ranges (:func:`snow_preset`);
* :func:`get_snow` (a preset name or a file), :func:`read_snow`, :func:`write_snow`,
  :func:`snow_record`.

May import: micro
"""

from skisnow.snow._file import (
    SNOW_FILE_KEYS,
    get_snow,
    read_snow,
    snow_from_record,
    snow_record,
    write_snow,
)
from skisnow.snow._presets import SNOW_ALIASES, SNOW_PRESETS, snow_preset
from skisnow.snow._snow import DENSITY_RELATIONS, Snow, gamma_grains, modulus_from_density

__all__ = [
    "DENSITY_RELATIONS",
    "SNOW_ALIASES",
    "SNOW_FILE_KEYS",
    "SNOW_PRESETS",
    "Snow",
    "gamma_grains",
    "get_snow",
    "modulus_from_density",
    "read_snow",
    "snow_from_record",
    "snow_preset",
    "snow_record",
    "write_snow",
]
