"""The apparent (meso-scale) contact of a rigid loaded ski profile with elastic snow."""
