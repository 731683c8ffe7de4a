"""Shared test set-up: headless MuJoCo rendering, and ``tests/`` on the path for the independent checks
of :mod:`physics`."""

import os
import sys
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")
sys.path.insert(0, str(Path(__file__).parent))
