"""The apparent (meso-scale) contact of a rigid loaded ski profile with elastic snow.

Kalliorinne et al. (2023) §3.2: the loaded camber profile, a rigid body free to translate and to
rotate about the load point, is pressed into an elastic half-space of equivalent modulus E'
(eq. 2) with force and moment balance (eq. 3).

Equation map (paper → function):

===============================================  ==================================================
Kalliorinne et al. (2023) eq. 2, E'              :func:`effective_modulus`, :class:`Material`,
                                                 :data:`BASE`, :data:`STONE`, :func:`snow`
Boussinesq / Love (1929) influence coefficients  :func:`surface_kernel`, :func:`strip_kernel`,
(the half-space u = K p)                         :func:`line_kernel`, :class:`Convolution`
Kalliorinne et al. (2023) eq. 3, force and       :func:`solve_contact` → :class:`ContactSolution`
moment balance of the loaded profile             (models 'strip', 'surface', 'line'; control
                                                 'moment', 'load', 'displacement')
Polonsky & Keer (1999) constrained CG, with      :func:`polonsky_keer` →
the moment constraint, a hardness cap            :class:`PolonskyKeerResult` on any
(Sainsot & Lubrecht 2011) and a circulant        :class:`ComplianceOperator` (:class:`CellOperator`
preconditioner (Vollebregt 2014)                 for a grid)
the free Euler–Bernoulli ski bending on the      :func:`solve_flexible`, :func:`solve_flexible_ski`
half-space, compliance K_snow + K_beam (MPRGP,   → :class:`FlexibleSolution`;
Dostál & Schöberl 2005; active-set steps,        :func:`cantilever_compliance`
Hintermüller, Ito & Kunisch 2002)
contact zones and lengths; Breitschädel (2012)   :func:`contact_zones` → :class:`ZoneMetrics`,
50 µm criterion                                  :func:`patches`
Hertz (line, sphere), flat punch (Johnson 1985)  :mod:`skisnow.contact.reference`
===============================================  ==================================================

Files: :func:`read_profile` (CSV ``x_mm,height_mm``), :func:`write_fields`, :func:`read_fields`,
:func:`fields_table`.

Where the code is: ``_problem`` (validation, grid, operator), ``_starts`` (warm, multilevel and
rigid starts), ``_polonsky_keer`` (the iteration), ``_operators`` (what it needs of K),
``_candidates`` (the 1D candidate-cell restriction), ``_solver`` (:func:`solve_contact`, a short
pipeline over them), ``_kernels`` (kernels and FFT convolution), ``_zones``, ``_materials``,
``_io``; the flexible ski: ``_flexible`` (:func:`solve_flexible`), ``_flexible_pdas`` (active-set
steps), ``_flexible_candidates``, ``_mprgp``, ``_beam_operator`` / ``_beam_kernel`` (the
cantilever compliance), ``_coupled_operator``.

May import: ski
"""

from skisnow.contact import reference
from skisnow.contact._beam_operator import CantileverCompliance, cantilever_compliance
from skisnow.contact._flexible import (
    EQUIVALENT_MODULUS_RANGE,
    FlexibleSolution,
    solve_flexible,
    solve_flexible_ski,
)
from skisnow.contact._io import fields_table, read_fields, read_profile, write_fields
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
from skisnow.contact._regions import (
    CLASSIC_REGIONS,
    SPLIT_REGIONS,
    Footprint,
    Patch,
    Region,
    footprint,
    region_index,
    region_marks,
)
from skisnow.contact._solver import ContactSolution, solve_contact
from skisnow.contact._zones import (
    BREITSCHAEDEL_THRESHOLD,
    REGION_NAMES,
    Zone,
    ZoneMetrics,
    contact_zones,
    paper_zones,
    patches,
)

__all__ = [
    "BASE",
    "BREITSCHAEDEL_THRESHOLD",
    "CLASSIC_REGIONS",
    "EQUIVALENT_MODULUS_RANGE",
    "REGION_NAMES",
    "SNOW_MODULUS_RANGE",
    "SPLIT_REGIONS",
    "STONE",
    "CantileverCompliance",
    "CellOperator",
    "ComplianceOperator",
    "ContactSolution",
    "Convolution",
    "FlexibleSolution",
    "Footprint",
    "Material",
    "Patch",
    "PolonskyKeerResult",
    "Region",
    "Zone",
    "ZoneMetrics",
    "cantilever_compliance",
    "contact_modulus",
    "contact_zones",
    "effective_modulus",
    "fields_table",
    "footprint",
    "line_convolution",
    "line_kernel",
    "paper_zones",
    "patches",
    "polonsky_keer",
    "read_fields",
    "read_profile",
    "reference",
    "region_index",
    "region_marks",
    "snow",
    "solve_contact",
    "solve_flexible",
    "solve_flexible_ski",
    "strip_convolution",
    "strip_kernel",
    "surface_convolution",
    "surface_kernel",
    "write_fields",
]
