"""A new robot's gait keys: derived from its model (:mod:`.start`), then searched on a small campaign
(:mod:`.search`), reported (:mod:`.report`). ``gaitshift robot tune ROBOT.yaml``."""
