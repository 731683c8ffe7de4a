"""The test oracle: Unitree's own Python SDK (the PyPI wheel ``unitree-sdk2==1.0.1``), its hg IDL classes
and its CRC routine, loaded past the wheel's broken package ``__init__`` (it imports a ``b2`` module the
wheel lacks) and its missing compiled CRC library (the pure-Python routine is used instead).

``make venv`` installs the wheel with ``pip install --no-deps --target .venv/oracle``: never a runtime
dependency of gaitshift. :func:`load` gives None when that folder is missing (the callers skip, saying so).
"""

from __future__ import annotations

import importlib
import sys
import types
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from unittest import mock

#: where the Makefile installs the wheel: next to the interpreter's environment
ORACLE_DIR = Path(sys.prefix) / "oracle"
SKIP_REASON = (
    f"the official SDK oracle is not installed at {ORACLE_DIR} "
    "(make venv: pip install --no-deps --target .venv/oracle unitree-sdk2==1.0.1)"
)


@dataclass(frozen=True)
class Oracle:
    """The SDK's hg IDL module (``LowCmd_``, ``LowState_``, ...) and its ``CRC`` object (built on the
    SDK's non-Linux branch: its pure-Python routine): ``crc(msg)`` -> uint32."""

    hg: Any
    crc_object: Any

    def crc(self, msg: Any) -> int:
        """``CRC().Crc(msg)`` of the SDK: its packing of the message type and its pure-Python CRC-32."""
        return int(self.crc_object.Crc(msg))


def _stub_package(name: str, path: Path) -> None:
    """An empty package ``name`` whose submodules are found in ``path`` (its real ``__init__`` not run)."""
    if name not in sys.modules:
        module = types.ModuleType(name)
        module.__path__ = [str(path)]
        sys.modules[name] = module


def load() -> Oracle | None:
    """The oracle, or None when the wheel is not installed at :data:`ORACLE_DIR`."""
    root = ORACLE_DIR / "unitree_sdk2py"
    if not (root / "idl" / "unitree_hg" / "msg" / "dds_" / "_LowCmd_.py").is_file():
        return None
    _stub_package("unitree_sdk2py", root)
    _stub_package("unitree_sdk2py.idl", root / "idl")
    _stub_package("unitree_sdk2py.utils", root / "utils")
    hg = importlib.import_module("unitree_sdk2py.idl.unitree_hg.msg.dds_")
    crc_module = importlib.import_module("unitree_sdk2py.utils.crc")
    # no compiled CRC library in the wheel: the SDK's own non-Linux branch, its pure-Python routine
    with mock.patch.object(crc_module.platform, "system", return_value="Oracle"):
        crc_object = crc_module.CRC()
    return Oracle(hg=hg, crc_object=crc_object)


# --- random field values, the same for gaitshift's classes and the SDK's ---------------------------------


def _f32(rng: Any, size: int) -> list[float]:
    """``size`` float32 values (as Python floats) over many magnitudes, signs and zeros."""
    import numpy as np

    x = rng.normal(size=size) * 10.0 ** rng.integers(-6, 7, size=size)
    x[rng.random(size) < 0.1] = 0.0
    return [float(v) for v in x.astype(np.float32)]


def _u(rng: Any, bits: int, size: int) -> list[int]:
    return [int(v) for v in rng.integers(0, 1 << bits, size=size, dtype="uint64")]


def lowcmd_fields(rng: Any) -> dict[str, Any]:
    """Random values for every field of a hg ``LowCmd_`` (motors as dicts), ``rng`` a numpy Generator."""
    motors = []
    for _ in range(35):
        q, dq, tau, kp, kd = _f32(rng, 5)
        motors.append(
            {"mode": _u(rng, 8, 1)[0], "q": q, "dq": dq, "tau": tau, "kp": kp, "kd": kd, "reserve": _u(rng, 32, 1)[0]}
        )
    return {
        "mode_pr": _u(rng, 8, 1)[0],
        "mode_machine": _u(rng, 8, 1)[0],
        "motor_cmd": motors,
        "reserve": _u(rng, 32, 4),
        "crc": _u(rng, 32, 1)[0],
    }


def lowstate_fields(rng: Any) -> dict[str, Any]:
    """Random values for every field of a hg ``LowState_`` (nested structs as dicts)."""
    motors = []
    for _ in range(35):
        q, dq, ddq, tau_est, vol = _f32(rng, 5)
        temperature = [int(v) for v in rng.integers(-(1 << 15), 1 << 15, size=2)]
        motors.append(
            {
                "mode": _u(rng, 8, 1)[0],
                "q": q,
                "dq": dq,
                "ddq": ddq,
                "tau_est": tau_est,
                "temperature": temperature,
                "vol": vol,
                "sensor": _u(rng, 32, 2),
                "motorstate": _u(rng, 32, 1)[0],
                "reserve": _u(rng, 32, 4),
            }
        )
    imu = {
        "quaternion": _f32(rng, 4),
        "gyroscope": _f32(rng, 3),
        "accelerometer": _f32(rng, 3),
        "rpy": _f32(rng, 3),
        "temperature": int(rng.integers(-(1 << 15), 1 << 15)),
    }
    return {
        "version": _u(rng, 32, 2),
        "mode_pr": _u(rng, 8, 1)[0],
        "mode_machine": _u(rng, 8, 1)[0],
        "tick": _u(rng, 32, 1)[0],
        "imu_state": imu,
        "motor_state": motors,
        "wireless_remote": _u(rng, 8, 40),
        "reserve": _u(rng, 32, 4),
        "crc": _u(rng, 32, 1)[0],
    }


def build_lowcmd(module: Any, fields: dict[str, Any]) -> Any:
    """``module.LowCmd_`` (gaitshift's :mod:`gaitshift.dds.messages` or the SDK's hg module) of ``fields``."""
    motors = [module.MotorCmd_(**m) for m in fields["motor_cmd"]]
    return module.LowCmd_(**{**fields, "motor_cmd": motors})


def build_lowstate(module: Any, fields: dict[str, Any]) -> Any:
    """``module.LowState_`` of ``fields`` (see :func:`build_lowcmd`)."""
    motors = [module.MotorState_(**m) for m in fields["motor_state"]]
    imu = module.IMUState_(**fields["imu_state"])
    return module.LowState_(**{**fields, "imu_state": imu, "motor_state": motors})
