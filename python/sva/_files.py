"""Files the package writes (results, bags): whole or not at all, and with the mode any file of the user's gets.

A temporary file beside the target is renamed into place when complete, as the engine's writer does
(host/io/text_file.hpp). ``tempfile.mkstemp`` makes that file 0600 whatever the umask, a mode meant for temporary
files: a results file or a bag is meant to be shared, so it gets ``0666 & ~umask`` (0644 under the usual 022), the
mode ``open(path, "w")`` and the engine's files get.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import BinaryIO, Iterator, Union

from ._sva_core import Error

PathLike = Union[str, "os.PathLike[str]"]


def _umask() -> int:
    """The process's umask. Linux shows it in /proc/self/status; elsewhere it is read by setting it and back, which
    another thread creating a file in between would see, hence only the fallback."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_output(file: PathLike) -> Iterator[BinaryIO]:
    """A binary file to write ``file``'s bytes to: renamed into place when the block ends without an exception,
    removed otherwise (any earlier ``file`` is then left as it was)."""
    path = Path(file)
    try:
        fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
    except OSError as e:
        raise Error(f"{os.fspath(file)}: cannot write: {e.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as out:
            os.fchmod(out.fileno(), 0o666 & ~_umask())
            yield out
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
