"""Figures (Matplotlib, imported only here). Numerics never import this package."""

from skisnow.plot._profiles import plot_camber_profiles

__all__ = ["plot_camber_profiles"]
