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

#: the longest file name the tools write, bytes: the file system's usual limit (255) less the
#: temporary name's prefix and random part (``.NAME.xxxxxxxx``)
MAX_NAME = 240
#: the longest path, bytes (Linux's PATH_MAX, 4096, less room for the temporary name)
MAX_PATH = 4000


def check_name(path: Path, field: str) -> None:
    """:class:`InputError` naming ``field`` when a name in ``path`` (the file's or a folder's) is longer
    than the file system allows (the file's: :data:`MAX_NAME` bytes, room left for its temporary file;
    a folder's: 255 bytes), or the whole path longer than :data:`MAX_PATH` bytes."""
    *folders, name = path.parts or ("",)
    for part, limit in [*((p, 255) for p in folders), (name, MAX_NAME)]:
        size = len(part.encode())
        if size > limit:
            raise InputError(field, f"{part[:40]}... ({size} bytes)", f"names of at most {limit} bytes in the path")
    if len(str(path).encode()) > MAX_PATH:
        raise InputError(field, f"{str(path)[:40]}...", f"a path of at most {MAX_PATH} bytes")


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], field: str = "output file") -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it onto ``path``.

    The temporary name keeps the suffix of ``path`` (in lower case) so that writers choosing a format by
    suffix (``np.savez``, ``matplotlib``) behave the same. On any exception the temporary file is removed.

    Raises:
        InputError: naming ``field`` and the path, when ``path`` exists and is not a regular file (a
            folder, a device, a FIFO) or no file can be created in its folder.
    """
    target = Path(path)
    check_name(target, field)
    if target.exists() and not target.is_file():
        raise InputError(field, str(target), "a regular file path (this is a folder or a special file)")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        # the suffix in lower case: a writer that appends its own suffix unless the name ends in it
        # (numpy's savez: ".npz") then writes exactly to the temporary file, whatever case was asked
        fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix.lower(), dir=target.parent)
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
