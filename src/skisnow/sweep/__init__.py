"""Sweeps of the contact over ski, load and snow, on Dask, resumable, as xarray datasets."""
