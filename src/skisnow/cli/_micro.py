"""Commands for the real contact: topo, grind, bearing, rank."""
