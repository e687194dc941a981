"""Atomic file writes (a result file is either complete or absent, never
half-written, even after a crash or Ctrl-C) and the output folders of the
commands.

An output folder is memsnav's when it holds :data:`MARKER`, which every
command writes into the folder it writes into. A command uses a folder that
is new, empty or memsnav's, and refuses anything else, naming it, before
any work: a regular file, or a folder of someone else's that is not empty.
``simulate``, ``study``, ``reproduce`` and ``calibrate`` write their files
into the folder (replacing files of the same names, leaving the others);
``navigate`` replaces its folder whole (:func:`fresh_output_folder`), and
only when every entry in it is one the marker lists as written by an
earlier ``navigate``; a run that fails replaces it too, with the failure's
summary and report, so an earlier run's files never pass for its own. No
command moves, renames or deletes anything else.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any


def _file_mode() -> int:
    """The mode ``open`` would give a new file: 0o666 less the umask (0644
    with the usual 022). ``mkstemp`` makes its files 0600."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w") -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; rename it over ``path`` on
    success, with the permissions of a plainly created file."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, _file_mode())
        with os.fdopen(fd, mode, encoding=None if "b" in mode else "utf-8") as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def write_text(path: str | os.PathLike[str], text: str) -> None:
    with atomic_open(path, "w") as f:
        f.write(text)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    with atomic_open(path, "wb") as f:
        f.write(data)


MARKER = ".memsnav-output"
"""The file that marks an output folder as memsnav's. ``navigate`` lists in
it the files it wrote (``"files"``): the only entries it may remove when
it replaces the folder."""


def _refuse(folder: Path, reason: str) -> ValueError:
    return ValueError(f"output folder {str(folder)!r}: {reason}")


def _marker(folder: Path) -> dict[str, Any] | None:
    """The marker's contents, or None when ``folder`` has none."""
    try:
        text = (folder / MARKER).read_text(encoding="utf-8")
    except FileNotFoundError:
        return None
    except (OSError, UnicodeDecodeError):
        return {}
    try:
        marker = json.loads(text)
    except ValueError:
        return {}
    return marker if isinstance(marker, dict) else {}


def _entries(folder: Path) -> list[str]:
    """Every file and folder below ``folder`` (relative POSIX paths), the
    marker left out, sorted."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.name != MARKER)


def _check_folder(folder: Path) -> bool:
    """Whether ``folder`` exists; raises when it is not one a command may
    write into: a file, or a non-empty folder without the marker."""
    if "\0" in str(folder):
        raise _refuse(folder, "contains a NUL character")
    if not folder.exists():
        if folder.is_symlink():
            raise _refuse(folder, "is a broken symbolic link; give a folder")
        return False
    if not folder.is_dir():
        raise _refuse(
            folder,
            "is a file, not a folder; memsnav does not replace, move or delete a file "
            "it was not asked to write",
        )
    if _marker(folder) is None and any(folder.iterdir()):
        raise _refuse(
            folder,
            f"is not empty and memsnav did not write it (no {MARKER} in it); "
            "give a new or empty folder",
        )
    return True


def output_folder(path: str | os.PathLike[str]) -> Path:
    """The output folder of a command that writes its files into it: checked
    (module docstring), created if needed, tested for writing and marked.

    Raises ``ValueError`` naming the folder when it may not be used, and
    ``OSError`` when it cannot be written into.
    """
    folder = Path(path)
    _check_folder(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as e:
        raise OSError(f"cannot write into {str(folder)!r}: {e.strerror or e}") from None
    if _marker(folder) is None:
        write_text(folder / MARKER, json.dumps({"written_by": "memsnav"}) + "\n")
    return folder


def check_replaceable(path: str | os.PathLike[str], command: str) -> None:
    """Raises ``ValueError`` naming the folder unless ``command`` may replace
    it whole: it does not exist, is empty, or holds only entries its marker
    lists as written by ``command``."""
    folder = Path(path)
    if not _check_folder(folder):
        return
    marker = _marker(folder) or {}
    written = set(marker.get("files", [])) if marker.get("written_by") == command else set()
    foreign = [entry for entry in _entries(folder) if entry not in written]
    if foreign:
        more = f" and {len(foreign) - 1} more entries" if len(foreign) > 1 else ""
        raise _refuse(
            folder,
            f"holds {foreign[0]!r}{more} that memsnav {command} did not write; {command} "
            "replaces its output folder whole: move them away or give another folder",
        )


@contextlib.contextmanager
def fresh_output_folder(path: str | os.PathLike[str], command: str) -> Iterator[Path]:
    """A new, empty folder beside ``path`` to write into; on success it
    replaces ``path`` (an earlier run's files go; :func:`check_replaceable`
    decides whether it may), on failure it is removed and ``path`` is left as
    it was: a run's outputs are never mixed with an earlier run's, nor half
    written. The marker lists what was written."""
    out = Path(path)
    check_replaceable(out, command)
    out = out.resolve()
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        raise _refuse(out, "cannot be created: a file is in the way") from None
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".new", dir=out.parent))
    try:
        yield tmp
        marker = {"written_by": command, "files": _entries(tmp)}
        write_text(tmp / MARKER, json.dumps(marker, indent=1) + "\n")
        os.chmod(tmp, 0o755)
        # Checked again: the folder may have changed during the run.
        check_replaceable(out, command)
        if out.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".old", dir=out.parent))
            old.rmdir()
            out.rename(old)
            tmp.rename(out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
