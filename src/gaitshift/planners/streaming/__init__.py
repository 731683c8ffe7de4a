"""What both streaming generators share (the VHIP generator of paper 003, :mod:`gaitshift.planners.vhip`,
and the locomotion generator, :mod:`gaitshift.planners.locomotion`): the sample clock and the
generator skeleton (:mod:`.generator`), the look-ahead buffer (:mod:`.buffer`), the emitted sample
blocks (:mod:`.samples`), events and planned steps (:mod:`.events`) and the command script
(:mod:`.script`)."""
