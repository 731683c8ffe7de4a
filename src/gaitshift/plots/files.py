"""Writing a matplotlib figure: atomically (no partial PNG), and always closing the figure."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from gaitshift.common.atomic import atomic_path


def save_figure(fig: Any, path: str | Path, **savefig: Any) -> Path:
    """Write ``fig`` to ``path`` with ``fig.savefig(**savefig)`` (default 120 dpi, tight box), then
    close it, also when writing fails."""
    options = {"dpi": 120, "bbox_inches": "tight"} | savefig
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, **options)
    finally:
        plt.close(fig)
    return Path(path)
