"""The trajectory contract shared by every planner (:mod:`gaitshift.trajectory.contract`) and its
file formats (:mod:`gaitshift.trajectory.formats`)."""

from gaitshift.trajectory.contract import Trajectory

__all__ = ["Trajectory"]
