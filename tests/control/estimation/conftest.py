"""Puts this folder on the path so the test modules share :mod:`estimation_truth` (independent
ground-truth helpers: SE_2(3) logarithm with scipy, run loops)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
