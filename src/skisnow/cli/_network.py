"""Commands for the camber network: train, predict."""
