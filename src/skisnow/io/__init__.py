"""File formats: bench data tables, profiles, model files. Field units in column headers."""
