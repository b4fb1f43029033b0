"""The ski at the macro scale: beam model, shipped virtual skis, virtual bench, metrics, network."""
