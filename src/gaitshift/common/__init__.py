"""Helpers without physics shared by every layer: atomic output files, strict JSON, rotations, runs."""
