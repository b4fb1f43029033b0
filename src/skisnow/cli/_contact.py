"""Commands for the apparent contact: contact."""
