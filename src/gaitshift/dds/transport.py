"""The DDS side of the low-level protocol: one CycloneDDS participant on one network interface, the two
topics (``rt/lowcmd``: :class:`~gaitshift.dds.messages.LowCmd_`, ``rt/lowstate``:
:class:`~gaitshift.dds.messages.LowState_`), and the wait for new samples.

The participant talks on the interface it is given only (Unitree's SDK does the same with
``ChannelFactoryInitialize(domain, interface)``). On the loopback ``lo`` (Unitree's simulator bridge's
default, with domain 1) multicast is off and discovery goes to the unicast peer 127.0.0.1 only: nothing
leaves the machine. Domain 0 is the real robot's network.
"""

from dataclasses import dataclass
from typing import Any

from cyclonedds._clayer import ddspy_take, ddspy_write
from cyclonedds.core import DDSException, InstanceState, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from gaitshift.dds.messages import LowCmd_, LowState_
from gaitshift.errors import InputError

__all__ = [
    "DOMAIN_MAX",
    "LOWCMD_TOPIC",
    "LOWSTATE_TOPIC",
    "BytesReader",
    "BytesWriter",
    "Endpoint",
    "Participant",
    "check_domain",
    "cyclone_config",
    "open_endpoint",
    "open_participant",
    "topic_reader",
    "topic_writer",
]

LOWCMD_TOPIC = "rt/lowcmd"
LOWSTATE_TOPIC = "rt/lowstate"
#: the largest domain id CycloneDDS maps onto UDP ports
DOMAIN_MAX = 232
LOOPBACK = ("lo", "lo0", "127.0.0.1")
#: the reader keeps this many samples between two takes (the default keeps one: the newest), so that every
#: message received is seen and counted; the writer keeps a few for retransmission
READER_DEPTH, WRITER_DEPTH = 64, 8
#: the domains this process configured, kept alive with it
_DOMAINS: dict[int, Any] = {}


def cyclone_config(iface: str) -> str:
    """The CycloneDDS XML configuration: ``iface`` only; on a loopback interface no multicast and the
    unicast discovery peer 127.0.0.1."""
    discovery = ""
    multicast = ""
    if iface in LOOPBACK:
        multicast = "<AllowMulticast>false</AllowMulticast>"
        discovery = (
            "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>30</MaxAutoParticipantIndex>"
            '<Peers><Peer address="127.0.0.1"/></Peers></Discovery>'
        )
    return (
        '<CycloneDDS><Domain Id="any"><General><Interfaces>'
        f'<NetworkInterface name="{iface}" priority="default" multicast="default"/>'
        f"</Interfaces>{multicast}</General>{discovery}</Domain></CycloneDDS>"
    )


class BytesReader(DataReader[Any]):
    """cyclonedds's ``DataReader`` that also takes the samples' bytes, without its ``deserialize``."""

    def take_bytes(self, n: int = 64) -> list[bytes]:
        """Up to ``n`` serialized samples (data only: no dispose or unregister notices), oldest first."""
        got = ddspy_take(self._ref, SampleState.Any | ViewState.Any | InstanceState.Any, n)
        if isinstance(got, int):
            raise DDSException(got, f"taking from {self!r}")
        return [data for data, info in got if info.valid_data]


class BytesWriter(DataWriter[Any]):
    """cyclonedds's ``DataWriter`` that also writes a sample's bytes, without its ``serialize``."""

    def write_bytes(self, data: bytes) -> None:
        """Write a serialized sample (the CDR header and body, a multiple of 4 bytes long)."""
        ret = ddspy_write(self._ref, data)
        if ret < 0:
            raise DDSException(ret, f"writing to {self!r}")


@dataclass
class Endpoint:
    """A participant with one writer and one reader of the protocol's topics (which is which depends on
    the side: the robot writes ``rt/lowstate`` and reads ``rt/lowcmd``, a controller the reverse)."""

    participant: Any
    kind: type
    writer: Any
    reader: Any
    waitset: Any
    condition: Any
    domain: Any

    def take(self, n: int = 64) -> list[Any]:
        """The samples received since the last take (data only: no dispose or unregister notices), oldest first."""
        return [s for s in self.reader.take(N=n) if isinstance(s, self.kind)]

    def take_bytes(self, n: int = 64) -> list[bytes]:
        """The serialized samples received since the last take (data only), oldest first: what
        :meth:`take` deserializes, for a reader of the bytes (:mod:`gaitshift.dds.cdr`)."""
        out: list[bytes] = self.reader.take_bytes(n)
        return out

    def write_bytes(self, data: bytes) -> None:
        """Write a serialized sample (its CDR bytes with the header, a multiple of 4 bytes long)."""
        self.writer.write_bytes(data)

    def wait(self, seconds: float) -> bool:
        """Block until a sample is there to take or ``seconds`` have passed; True when one is there."""
        return bool(self.waitset.wait(duration(seconds=max(seconds, 0.0))))


def check_domain(domain: int) -> int:
    """``domain`` when it is a DDS domain id CycloneDDS supports; :class:`InputError` otherwise."""
    if isinstance(domain, bool) or not isinstance(domain, int) or not 0 <= domain <= DOMAIN_MAX:
        raise InputError("--domain", domain, f"an integer in [0, {DOMAIN_MAX}] (0: the real robot's network)")
    return domain


@dataclass
class Participant:
    """A DDS participant (and its domain, kept alive with it), without the protocol's topics: for a program
    that only talks gaitshift's own topics (``gaitshift dds cmd``)."""

    participant: Any
    domain: Any


def open_participant(domain: int, iface: str) -> Participant:
    """A participant on DDS ``domain`` over ``iface`` (:func:`cyclone_config`; the first participant of the
    process on ``domain`` sets its interface)."""
    if not iface or any(c in iface for c in "<>\"'&"):
        raise InputError("--iface", iface, "a network interface name, e.g. lo or eth0")
    if check_domain(domain) not in _DOMAINS:  # a process configures a domain once (a second Domain is refused)
        _DOMAINS[domain] = Domain(domain, cyclone_config(iface))
    return Participant(DomainParticipant(domain), _DOMAINS[domain])


def open_endpoint(domain: int, iface: str, side: str) -> Endpoint:
    """The :class:`Endpoint` of ``side`` ("robot" or "controller") on DDS ``domain`` over ``iface``."""
    if side not in ("robot", "controller"):
        raise InputError("side", side, "robot or controller")
    p = open_participant(domain, iface)
    participant, dom = p.participant, p.domain
    cmd = Topic(participant, LOWCMD_TOPIC, LowCmd_)
    state = Topic(participant, LOWSTATE_TOPIC, LowState_)
    out, inp = (state, cmd) if side == "robot" else (cmd, state)
    writer: Any = BytesWriter(participant, out, qos=Qos(Policy.History.KeepLast(WRITER_DEPTH)))
    reader: Any = BytesReader(participant, inp, qos=Qos(Policy.History.KeepLast(READER_DEPTH)))
    condition = ReadCondition(reader, ViewState.Any | InstanceState.Any | SampleState.NotRead)
    waitset = WaitSet(participant)
    waitset.attach(condition)
    kind = LowCmd_ if side == "robot" else LowState_
    return Endpoint(participant, kind, writer, reader, waitset, condition, dom)


def topic_writer(endpoint: Endpoint | Participant, name: str, kind: type) -> Any:
    """A writer of topic ``name`` (IDL type ``kind``) on ``endpoint``'s participant: gaitshift's own topics
    (:mod:`gaitshift.dds.own_messages`), beside the protocol's."""
    topic: Any = Topic(endpoint.participant, name, kind)
    qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(WRITER_DEPTH))
    return DataWriter(endpoint.participant, topic, qos=qos)


def topic_reader(endpoint: Endpoint | Participant, name: str, kind: type, depth: int = READER_DEPTH) -> Any:
    """A reader of topic ``name`` (IDL type ``kind``) on ``endpoint``'s participant, keeping ``depth`` samples
    between two takes (it is polled: not attached to the endpoint's wait set). Both ends reliable."""
    topic: Any = Topic(endpoint.participant, name, kind)
    qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(depth))
    return DataReader(endpoint.participant, topic, qos=qos)
