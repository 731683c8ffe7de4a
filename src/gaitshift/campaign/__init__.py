"""Campaigns: many independent runs (simulate, plan, reference) over a grid of parameters, on Dask.

``spec`` (the YAML spec and its axes, ``axes``), ``cases`` (the cartesian product, case hashes),
``execute`` (one case in a worker process), ``store`` (Parquet part files, resume), ``run`` (the Dask
client and cluster), ``report`` (heatmaps and tables). Command: ``gaitshift campaign``.
"""
