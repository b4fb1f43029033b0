"""The real (micro-scale) contact: grinding topographies, roughness, bearing model of ice grains.

After Scherge, Stoll & Moseler, "On the Influence of Microtopography on the Sliding Performance
of Cross Country Skis", Front. Mech. Eng. 7:659995 (2021):

* topographies: :func:`read_topography` (SurfaceTopography readers, ``.npy``, text),
  :func:`remove_form`, :func:`fill_missing`, :func:`write_topography`;
* synthetic grinds: :func:`grind`, :func:`grind_preset` (S1–S5), :data:`PRESETS`;
* roughness: :func:`roughness`, :func:`prepare` (form removal + :func:`lowpass`, 33 µm
  cut-off: the one preparation of a map for roughness and contact), :func:`areal_parameters`,
  :func:`line_parameters`;
* materials (eq. 1–4): :func:`ice_hardness`, :func:`uhmwpe_hardness`,
  :func:`deformation_regime`, :func:`contact_time`;
* the bearing model (eq. 5–9): :func:`bearing_area`, :func:`bearing_sweep`,
  :func:`bearing_area_reference`;
* grains (eq. 12–13): :func:`fit_grain_distribution`, :func:`grain_average`,
  :data:`PAPER_GRAIN_FIT`;
* statistics (eq. 10): :func:`pearson`, :func:`critical_r`, :func:`rank_table`,
  :func:`read_rank_table`, :func:`table4_comparison`;
* elastic–perfectly-plastic flat-ice contact (Scherge et al. 2021, Fig. 3):
  :func:`elastoplastic_contact` (on the contact package's Polonsky–Keer core with a hardness
  cap), :func:`flat_plastic_area`;
* the same contact over a grid of nominal pressures, on the mirror-continued half-space
  (:class:`MirrorOperator`): :func:`elastoplastic_curve` — real area, mean separation and the
  gap distribution behind the reciprocal separation (Kalliorinne et al. 2023, Lubricants
  11(10) 427).

May import: contact
"""

from skisnow.micro import _scherge2021 as scherge2021
from skisnow.micro._bearing import (
    BearingMap,
    BearingSweep,
    bearing_area,
    bearing_area_reference,
    bearing_sweep,
    slope_factor,
)
from skisnow.micro._elastoplastic import (
    ElastoplasticResult,
    elastoplastic_contact,
    flat_plastic_area,
    ice_base_modulus,
)
from skisnow.micro._ep_curve import (
    GAP_EDGES,
    ElastoplasticCurve,
    elastoplastic_curve,
    reciprocal_from_bins,
)
from skisnow.micro._grains import (
    PAPER_GRAIN_FIT,
    GrainFit,
    fit_grain_distribution,
    grain_average,
    sample_grain_diameters,
)
from skisnow.micro._grinding import PRESETS, GrindSpec, GroovePass, grind, grind_preset
from skisnow.micro._ice import (
    ICE,
    UHMWPE,
    Material,
    Regime,
    contact_time,
    deformation_regime,
    ice_hardness,
    uhmwpe_hardness,
)
from skisnow.micro._mirror import MirrorOperator
from skisnow.micro._roughness import (
    DEFAULT_CUTOFF,
    SDQ_DEFINITIONS,
    Roughness,
    SdqSpread,
    areal_parameters,
    line_parameters,
    lowpass,
    prepare,
    roughness,
    sdq_spread,
)
from skisnow.micro._stats import (
    Correlation,
    RankTable,
    correlate,
    critical_r,
    pearson,
    rank,
    rank_table,
    read_rank_table,
    table4_comparison,
)
from skisnow.micro._topography import (
    Topography,
    fill_missing,
    make_topography,
    read_topography,
    remove_form,
    to_surface_topography,
    write_topography,
)

__all__ = [
    "DEFAULT_CUTOFF",
    "GAP_EDGES",
    "ICE",
    "PAPER_GRAIN_FIT",
    "PRESETS",
    "SDQ_DEFINITIONS",
    "UHMWPE",
    "BearingMap",
    "BearingSweep",
    "Correlation",
    "ElastoplasticCurve",
    "ElastoplasticResult",
    "GrainFit",
    "GrindSpec",
    "GroovePass",
    "Material",
    "MirrorOperator",
    "RankTable",
    "Regime",
    "Roughness",
    "SdqSpread",
    "Topography",
    "areal_parameters",
    "bearing_area",
    "bearing_area_reference",
    "bearing_sweep",
    "contact_time",
    "correlate",
    "critical_r",
    "deformation_regime",
    "elastoplastic_contact",
    "elastoplastic_curve",
    "fill_missing",
    "fit_grain_distribution",
    "flat_plastic_area",
    "grain_average",
    "grind",
    "grind_preset",
    "ice_base_modulus",
    "ice_hardness",
    "line_parameters",
    "lowpass",
    "make_topography",
    "pearson",
    "prepare",
    "rank",
    "rank_table",
    "read_rank_table",
    "read_topography",
    "reciprocal_from_bins",
    "remove_form",
    "roughness",
    "sample_grain_diameters",
    "scherge2021",
    "sdq_spread",
    "slope_factor",
    "table4_comparison",
    "to_surface_topography",
    "uhmwpe_hardness",
    "write_topography",
]
