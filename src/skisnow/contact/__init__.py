"""The apparent (meso-scale) contact of a rigid loaded ski profile with elastic snow.

Kalliorinne et al. (2023) §3.2: the loaded camber profile, a rigid body free to translate and to
rotate about the load point, is pressed into an elastic half-space of equivalent modulus E'
(eq. 2) with force and moment balance (eq. 3).

Equation map (paper → function):

==============================================  =================================================
Kalliorinne et al. (2023) eq. 2, E'             :func:`effective_modulus`, :class:`Material`,
                                                :data:`BASE`, :data:`STONE`, :func:`snow`
Boussinesq / Love (1929) influence coefficients :func:`surface_kernel`, :func:`strip_kernel`,
(the half-space u = K p)                        :func:`line_kernel`, :class:`Convolution`
Kalliorinne et al. (2023) eq. 3, force and      :func:`solve_contact` → :class:`ContactSolution`
moment balance of the loaded profile            (models 'strip', 'surface', 'line'; control
                                                'moment', 'load', 'displacement')
Polonsky & Keer (1999) constrained CG, with     :func:`polonsky_keer` → :class:`PolonskyKeerResult`
the moment constraint, a hardness cap           on any :class:`ComplianceOperator`
(Sainsot & Lubrecht 2011) and a circulant       (:class:`CellOperator` for a grid)
preconditioner (Vollebregt 2014)
contact zones and lengths; Breitschädel (2012)  :func:`contact_zones` → :class:`ZoneMetrics`,
50 µm criterion                                 :func:`patches`
Hertz (line, sphere), flat punch (Johnson 1985) :mod:`skisnow.contact.reference`
==============================================  =================================================

Files: :func:`read_profile` (CSV ``x_mm,height_mm``), :func:`write_fields`,
:func:`fields_table`.

Where the code is: ``_problem`` (validation, grid, operator), ``_starts`` (warm, multilevel and
rigid starts), ``_polonsky_keer`` (the iteration), ``_operators`` (what it needs of K),
``_candidates`` (the 1D candidate-cell restriction), ``_solver`` (:func:`solve_contact`, a short
pipeline over them), ``_kernels`` (kernels and FFT convolution), ``_zones``, ``_materials``,
``_io``.
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
from skisnow.contact._operators import CellOperator, ComplianceOperator
from skisnow.contact._polonsky_keer import PolonskyKeerResult, polonsky_keer
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
    "CellOperator",
    "ComplianceOperator",
    "ContactSolution",
    "Convolution",
    "Material",
    "PolonskyKeerResult",
    "Zone",
    "ZoneMetrics",
    "contact_modulus",
    "contact_zones",
    "effective_modulus",
    "fields_table",
    "line_convolution",
    "line_kernel",
    "patches",
    "polonsky_keer",
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
