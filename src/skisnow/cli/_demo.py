"""Commands for the end-to-end demo."""
