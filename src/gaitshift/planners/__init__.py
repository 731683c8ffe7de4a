"""Planners: the TV-LIPM planner over given footsteps (paper 001) and the online generators."""
