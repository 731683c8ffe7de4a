"""The scripted command driver: each command is applied at the first tick at or after its time, the
stop at the first tick at or after ``stop_at``, and the driver advances in blocks between events.

Oracle: a recording stand-in generator (plain Python, no gaitshift code) whose log of calls is
compared with the ticks computed by hand from the times.
"""

import math

import pytest

import gaitshift
from gaitshift.errors import InfeasibleError
from gaitshift.planners.streaming.script import CommandScript
from gaitshift.planners.vhip.generator import VhipGenerator


class Recorder:
    """A streaming generator that only counts ticks and logs its inputs; at rest 5 steps after the stop."""

    def __init__(self, dt=0.01, step_ticks=7):
        self.dt, self.step_ticks = dt, step_ticks
        self.tick_index = 0
        self.log: list[tuple] = []
        self.steps_after_stop: int | None = None

    @property
    def t(self):
        return self.tick_index * self.dt

    @property
    def finished(self):
        return self.steps_after_stop is not None and self.steps_after_stop >= 5

    def command(self, vx, vy=0.0):
        self.log.append(("command", self.tick_index, vx, vy))

    def stop(self):
        self.log.append(("stop", self.tick_index))
        self.steps_after_stop = 0

    def advance(self, n):
        assert n >= 1
        self.log.append(("advance", self.tick_index, n))
        self.tick_index += n

    def step(self):
        self.log.append(("step", self.tick_index))
        self.tick_index += self.step_ticks
        self.steps_after_stop += 1


def test_commands_and_the_stop_are_applied_at_the_first_tick_at_or_after_their_time():
    gen = Recorder()
    script = CommandScript([(0.255, 0.6, 0.0), (0.0, 0.3, 0.1), (0.255, 0.9, 0.0), (0.4, 0.0, 0.0)], stop_at=0.5)
    script.run(gen)
    applied = [e for e in gen.log if e[0] in ("command", "stop")]
    # ticks of 10 ms: 0.255 s is first reached at tick 26; equal times in the given order
    assert applied == [
        ("command", 0, 0.3, 0.1),
        ("command", 26, 0.6, 0.0),
        ("command", 26, 0.9, 0.0),
        ("command", 40, 0.0, 0.0),
        ("stop", 50),
    ]
    # between events the driver advanced in single blocks, after the stop step by step until at rest
    assert [e for e in gen.log if e[0] == "advance"] == [("advance", 0, 26), ("advance", 26, 14), ("advance", 40, 10)]
    assert [e[0] for e in gen.log if e[1] >= 50][1:] == ["step"] * 5
    assert script.stop_requested and script.pending == () and gen.finished


def test_a_time_within_rounding_of_a_tick_is_reached_at_that_tick():
    gen = Recorder(dt=0.1)
    CommandScript([(0.3, 1.0, 0.0)], stop_at=0.7).run(gen)  # 3 * 0.1 = 0.30000000000000004
    assert ("command", 3, 1.0, 0.0) in gen.log and ("stop", 7) in gen.log


def test_advance_to_follows_time_and_remaining_keeps_what_is_not_applied():
    gen = Recorder()
    script = CommandScript([(0.05, 0.3, 0.0), (0.5, 0.6, 0.0)], stop_at=2.0)
    script.apply_due(gen)
    script.advance_to(gen, 30)
    assert gen.tick_index == 30 and ("command", 5, 0.3, 0.0) in gen.log
    assert script.next_time() == 0.5 and script.next_tick(gen) == 50
    rest = script.remaining()
    assert rest.pending == ((0.5, 0.6, 0.0),) and rest.stop_at == 2.0 and not rest.stop_requested
    script.advance_to(gen, 300)  # past the stop: the stop is requested, then no more events
    assert script.stop_requested and script.next_time() == math.inf and script.next_tick(gen) is None


def test_a_run_that_never_stops_is_an_error():
    class Endless(Recorder):
        @property
        def finished(self):
            return False

    with pytest.raises(InfeasibleError, match="did not stop"):
        CommandScript([(0.0, 0.3, 0.0)], stop_at=0.1).run(Endless(), max_time=2.0)


def test_the_scenario_script_stops_two_seconds_after_the_last_command_by_default():
    sc = gaitshift.load_scenario({"planner": "vhip", "dt": 0.004, "commands": [{"t": 0.0, "vx": 0.3}, {"t": 2.0}]})
    script = CommandScript.from_scenario(sc)
    assert script.commands == ((0.0, 0.3, 0.0), (2.0, 0.0, 0.0)) and script.stop_at == 4.0
    gen = VhipGenerator(sc)
    script.run(gen)
    assert gen.finished and gen.command_velocity.tolist() == [0.0, 0.0]
    assert any(e.kind == "stop" and abs(e.t - 4.0) < 1e-9 for e in gen.events)
