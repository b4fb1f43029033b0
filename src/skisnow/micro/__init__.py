"""The real (micro-scale) contact: grinding topographies, roughness, bearing model of ice grains."""
