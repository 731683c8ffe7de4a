"""The online-planner tests share :mod:`switching_cases` (the start problem and an independent dense
eq. (13) solve): put this folder on the path, as tests/conftest.py does for :mod:`physics`."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
