"""The online VHIP running generator of paper 003 and its parts (generator, buffer, emission, events,
limits, steps, horizons, switching, foothold, swings, script, transitions)."""
