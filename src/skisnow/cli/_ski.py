"""Commands for the ski: skis, bench, metrics."""
