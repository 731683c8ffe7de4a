"""Atomic file output: write to a temporary file in the target folder, then rename.

No gaitshift command leaves a partial output file behind, whatever fails.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

from gaitshift.errors import InputError


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], field: str = "output file") -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it onto ``path``.

    The temporary name keeps the suffix of ``path`` so that writers choosing a format by suffix
    (``np.savez``, ``matplotlib``) behave the same. On any exception the temporary file is removed.

    Raises:
        InputError: naming ``field`` and the path, when ``path`` exists and is not a regular file (a
            folder, a device, a FIFO) or no file can be created in its folder.
    """
    target = Path(path)
    if target.exists() and not target.is_file():
        raise InputError(field, str(target), "a regular file path (this is a folder or a special file)")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent)
    except OSError as exc:
        raise InputError(field, str(target), f"a path in a writable folder ({exc.strerror})") from None
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the file the usual permissions
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.replace(tmp_path, target)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()
