"""Figures. One module per topic: ``tvlip`` (paper 001), ``vhip`` (paper 003), ``slip``, ``sim``.

Only the CLI and these modules import matplotlib (with the ``Agg`` backend).
"""
