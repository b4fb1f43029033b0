"""The apparent (meso-scale) contact of a rigid loaded ski profile with elastic snow.

Kalliorinne et al. (2023) §3.2: the loaded camber profile, a rigid body free to translate and to
rotate about the load point, is pressed into an elastic half-space of equivalent modulus E'
(eq. 2) with force and moment balance (eq. 3). Public API:

* :func:`effective_modulus`, :class:`Material`, presets :data:`BASE`, :data:`STONE`, :func:`snow`;
* :func:`solve_contact` → :class:`ContactSolution` (models 'strip', 'surface', 'line'; control
  'moment', 'load', 'displacement');
* :func:`contact_zones` → :class:`ZoneMetrics` (rear / middle / front / total, Breitschädel);
* :mod:`skisnow.contact.reference` — Hertz line and sphere, flat punch;
* files: :func:`read_profile` (CSV ``x_mm,height_mm``), :func:`write_fields`, :func:`fields_table`;
* the half-space kernels and FFT convolution in :mod:`skisnow.contact._kernels`.
"""

from skisnow.contact import reference
from skisnow.contact._io import fields_table, read_profile, write_fields
from skisnow.contact._kernels import (
    Convolution,
    line_convolution,
    line_kernel,
    strip_convolution,
    strip_kernel,
    surface_convolution,
    surface_kernel,
)
from skisnow.contact._materials import (
    BASE,
    SNOW_MODULUS_RANGE,
    STONE,
    Material,
    contact_modulus,
    effective_modulus,
    snow,
)
from skisnow.contact._solver import ContactSolution, solve_contact
from skisnow.contact._zones import (
    BREITSCHAEDEL_THRESHOLD,
    Zone,
    ZoneMetrics,
    contact_zones,
    patches,
)

__all__ = [
    "BASE",
    "BREITSCHAEDEL_THRESHOLD",
    "SNOW_MODULUS_RANGE",
    "STONE",
    "ContactSolution",
    "Convolution",
    "Material",
    "Zone",
    "ZoneMetrics",
    "contact_modulus",
    "contact_zones",
    "effective_modulus",
    "fields_table",
    "line_convolution",
    "line_kernel",
    "patches",
    "read_profile",
    "reference",
    "snow",
    "solve_contact",
    "strip_convolution",
    "strip_kernel",
    "surface_convolution",
    "surface_kernel",
    "write_fields",
]
