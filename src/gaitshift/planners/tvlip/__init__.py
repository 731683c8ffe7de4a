"""The TV-LIPM planner of paper 001 over given footsteps: ZMP boxes, boundary problem, planner,
closed-form sampling and re-planning."""
