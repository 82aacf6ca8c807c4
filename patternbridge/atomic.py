"""Atomic file output: a reader never sees a half-written file.

Everything PatternBridge writes goes through :func:`atomic_path`: the data is
written to a temporary file in the target directory and moved into place with
``os.replace`` only when the writer finished without raising.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "write_bytes", "write_text"]


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``target``; move it to ``target`` on success.

    The suffix of ``target`` is kept so libraries that pick a format from the
    file name (matplotlib, trimesh) still work.
    """
    target = Path(target)
    if target.is_dir():
        from .errors import InputError

        raise InputError(f"{target}: is a folder; give the name of the file to write")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        from .errors import InputError

        raise InputError(f"{target}: a part of the folder path is a file; give a folder that can hold it") from None
    fd, tmp = tempfile.mkstemp(
        prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent
    )
    os.close(fd)
    tmp_path = Path(tmp)
    # mkstemp makes the file private (0600); give it the mode a plain open() would
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp_path, 0o666 & ~umask)
    try:
        yield tmp_path
        os.replace(tmp_path, target)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()


def write_bytes(target: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``target`` atomically and return the path."""
    with atomic_path(target) as tmp:
        tmp.write_bytes(data)
    return Path(target)


def write_text(
    target: str | os.PathLike, text: str, encoding: str = "utf-8", newline: str = "\n"
) -> Path:
    """Write ``text`` to ``target`` atomically (``newline`` as given) and return it."""
    with atomic_path(target) as tmp, open(
        tmp, "w", encoding=encoding, newline=newline
    ) as fh:
        fh.write(text)
    return Path(target)
