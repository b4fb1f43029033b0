"""Figures (Matplotlib, imported only here). Numerics never import this package."""
