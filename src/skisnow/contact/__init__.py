"""The apparent (meso-scale) contact of a rigid loaded ski profile with elastic snow.

Kalliorinne et al. (2023) §3.2: the loaded camber profile, a rigid body free to translate and to
rotate about the load point, is pressed into an elastic half-space of equivalent modulus E'
(eq. 2) with force and moment balance (eq. 3).

Equation map (paper → function):

==============================================  ==========================================

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
