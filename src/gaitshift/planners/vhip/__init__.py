"""The online VHIP running generator of paper 003 and its parts (generator, emission,
limits, steps, horizons, switching, foothold, swings, transitions; the clock, buffer, events and script
they share with the locomotion generator are in :mod:`gaitshift.planners.streaming`)."""
