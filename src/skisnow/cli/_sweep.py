"""Commands for maps over load and snow: sweep, plot, report."""
