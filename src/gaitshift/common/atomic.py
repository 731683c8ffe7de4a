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

#: room a file's name leaves for its temporary name (``.NAME.xxxxxxxx``), bytes
TEMP_ROOM = 15
#: the limits when the file system does not say (Linux's NAME_MAX and PATH_MAX), bytes
NAME_MAX, PATH_MAX = 255, 4096
#: the longest file name the tools write where the file system allows NAME_MAX (255), bytes
MAX_NAME = NAME_MAX - TEMP_ROOM


def fs_limits(path: Path) -> tuple[int, int]:
    """(NAME_MAX, PATH_MAX) of the file system holding ``path``'s nearest existing folder, bytes
    (``os.pathconf``; :data:`NAME_MAX`, :data:`PATH_MAX` when it does not say)."""
    base = path.absolute()
    while not _is_dir(base) and base != base.parent:
        base = base.parent
    try:
        return int(os.pathconf(base, "PC_NAME_MAX")), int(os.pathconf(base, "PC_PATH_MAX"))
    except (OSError, ValueError):
        return NAME_MAX, PATH_MAX


def _is_dir(path: Path) -> bool:
    """``path`` is a folder (False also when the name is too long to look up)."""
    try:
        return path.is_dir()
    except OSError:
        return False


def check_suffix(path: object, field: str, suffixes: tuple[str, ...], what: str = "") -> Path:
    """``path`` (a str or path) as a :class:`Path` whose name has a stem and ends in one of ``suffixes`` (in
    any case); else :class:`InputError` naming ``field``, the value and the suffixes (then ``what``)."""
    if not isinstance(path, str | os.PathLike) or Path(path).suffix.lower() not in suffixes or not Path(path).stem:
        value = str(path) if isinstance(path, str | os.PathLike) else path
        raise InputError(field, value, "a file name ending in " + ", ".join(suffixes) + what)
    return Path(path)


def check_name(path: Path, field: str) -> None:
    """:class:`InputError` naming ``field`` when a name in ``path`` (the file's or a folder's) is longer
    than the file system allows (its NAME_MAX; the file's less :data:`TEMP_ROOM`, the room for its
    temporary file), or the whole path, made absolute, longer than its PATH_MAX less that room."""
    name_max, path_max = fs_limits(path)
    *folders, name = path.parts or ("",)
    for part, limit in [*((p, name_max) for p in folders), (name, name_max - TEMP_ROOM)]:
        size = len(part.encode())
        if size > limit:
            raise InputError(field, f"{part[:40]}... ({size} bytes)", f"names of at most {limit} bytes in the path")
    size, limit = len(str(path.absolute()).encode()), path_max - TEMP_ROOM
    if size > limit:
        raise InputError(field, f"{str(path)[:40]}... ({size} bytes)", f"a path of at most {limit} bytes")


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
