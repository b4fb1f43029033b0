"""Elastic constants of the apparent contact: the equivalent modulus of eq. 2 and presets.

Kalliorinne et al. (2023), eq. 2:

    2/E' = (1 − ν²)/E_base + (1 − ν²)/E_counter.

E' is **twice** the contact modulus E* of Hertz/Johnson (1/E* = Σ (1 − ν²)/E). The half-space
kernels of :mod:`skisnow.contact._kernels` take E' and use the prefactor 2/(π E') = 1/(π E*), so
Hertz's formulas hold with E* = E'/2 (the Hertz tests in ``tests/contact`` prove it). For the
paper's stone bench (ski base 900 MPa, stone 70 GPa, ν = 0.3 on both), E' ≈ 1.95 GPa.

:class:`Material` and the presets :data:`BASE` (the default base) and :data:`STONE` are defined
once in :mod:`skisnow.materials` and re-exported here.
"""

from __future__ import annotations

from skisnow.materials import BASE, STONE, Material

__all__ = [
    "BASE",
    "SNOW_MODULUS_RANGE",
    "STONE",
    "Material",
    "contact_modulus",
    "effective_modulus",
    "snow",
]


#: The range of snow moduli the paper simulates (Lintzén & Edeskär 2015), Pa.
SNOW_MODULUS_RANGE: tuple[float, float] = (20e6, 400e6)


def snow(modulus: float, *, poisson: float = 0.3) -> Material:
    """Snow of elastic modulus ``modulus`` [Pa] (the paper uses 20–400 MPa and ν = 0.3)."""
    return Material(name="snow", modulus=modulus, poisson=poisson)


def effective_modulus(
    counter: Material | float,
    base: Material | float = BASE,
    *,
    poisson: float = 0.3,
) -> float:
    """Equivalent modulus E' [Pa] of eq. 2 (Kalliorinne et al. 2023).

    ``2/E' = (1 − ν_base²)/E_base + (1 − ν_counter²)/E_counter``. Moduli may be given as
    :class:`Material` or as plain numbers in Pa (then ν = ``poisson`` for that body). The
    default base is :data:`BASE` (900 MPa, ν = 0.3). ``E'`` is what every kernel and
    :func:`~skisnow.contact.solve_contact` take as ``modulus``; it equals 2·E*.

    >>> round(effective_modulus(STONE) / 1e9, 3)
    1.953
    """
    bodies = []
    for label, body in (("counter", counter), ("base", base)):
        if not isinstance(body, Material):
            body = Material(name=label, modulus=float(body), poisson=poisson)
        bodies.append(body)
    return 2.0 / sum(b.plane_strain_compliance for b in bodies)


def contact_modulus(modulus: float) -> float:
    """Hertz/Johnson contact modulus E* = E'/2 [Pa] from the paper's equivalent modulus E'."""
    return 0.5 * float(modulus)
