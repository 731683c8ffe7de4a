"""The online locomotion generator: stand, walk, run, turn and stop from a live (vx, vy, yaw rate)
command, with exact TV-LIPM dynamics (paper 001) across every gait switch (docs/locomotion.md)."""
