"""Unitree's low-level "hg" protocol over DDS (the G1): the messages (:mod:`gaitshift.dds.messages`),
their CRC (:mod:`gaitshift.dds.crc`), the G1's motor order (:mod:`gaitshift.dds.g1`) and the conversions
to and from gaitshift's frames (:mod:`gaitshift.dds.convert`). docs/deploy.md."""
