"""The key loop (:mod:`gaitshift.cli.keys`) on a pseudo-terminal, no real terminal needed: keys typed on the
pty's master side, read in cbreak mode on its slave side, become the commands of ``gaitshift teleop``'s
key map (0.1 m/s forward, 0.05 m/s sideways, 0.2 rad/s a press; an arrow key's escape sequence split over
two reads is one key) until q, the stop; the terminal's modes are restored afterwards. The commands go
through the brain's command input (the same checks as the DDS topic's) to the controller; the loop also
ends when told, with no key typed."""

import io
import os
import pty
import termios
import threading
import time

import pytest

from gaitshift.cli.keys import KeyReader, key_loop
from gaitshift.dds.cmdvel import CommandInput, CommandLimits, CommandQueue, KeySteer

LIMITS = CommandLimits(forward=1.0, backward=0.5, sideways=0.3, yaw_rate=0.8)


@pytest.fixture
def terminal():
    """A pseudo-terminal: (master fd, slave fd), closed afterwards."""
    master, slave = pty.openpty()
    yield master, slave
    os.close(master)
    os.close(slave)


def test_keys_typed_on_a_pty_become_the_brains_commands_until_q(terminal):
    master, slave = terminal
    before = termios.tcgetattr(slave)
    queue, out = CommandQueue("the keyboard"), io.StringIO()
    with KeyReader(fd=slave, out=out) as keys:
        assert not termios.tcgetattr(slave)[3] & termios.ICANON  # cbreak: keys arrive one by one
        os.write(master, b"ww\x1b[")  # up, up, and half of the left arrow's escape sequence
        thread = threading.Thread(target=key_loop, args=(keys, KeySteer(), queue.put, threading.Event()))
        thread.start()
        time.sleep(0.3)
        os.write(master, b"Dz?q")  # its rest, turn left, an unknown key, q: the stop
        thread.join(timeout=10)
        assert not thread.is_alive()
    assert termios.tcgetattr(slave) == before and out.getvalue() == "\n"
    msgs = queue.take()
    assert [(m.vx, m.vy, m.yaw_rate, m.stop) for m in msgs] == [
        (0.1, 0.0, 0.0, 0),
        (0.2, 0.0, 0.0, 0),
        (0.2, 0.05, 0.0, 0),
        (0.2, 0.05, 0.2, 0),
        (0.2, 0.05, 0.2, 1),
    ]
    lines: list[str] = []
    inp = CommandInput([queue], LIMITS, lines.append)
    for m in msgs:
        queue.put(m)
    inp.poll()
    assert (inp.received, inp.accepted, inp.dropped) == (5, 5, 0) and inp.pending.stop == 1 and not lines


def test_the_key_loop_ends_when_told_without_a_key(terminal):
    _, slave = terminal
    done = threading.Event()
    with KeyReader(fd=slave, out=io.StringIO()) as keys:
        thread = threading.Thread(target=key_loop, args=(keys, KeySteer(), print, done))
        thread.start()
        done.set()
        thread.join(timeout=10)  # it polls every 0.1 s; no key ever comes
    assert not thread.is_alive()
