"""Analysis of trajectories: physics report, support margins, capture point, the 3D-SLIP comparison."""
