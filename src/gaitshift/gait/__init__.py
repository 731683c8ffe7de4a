"""Gait: footholds, contact phases with their stiffness, and swing-foot paths."""
