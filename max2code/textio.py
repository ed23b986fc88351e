"""Reading the user's text files and writing the outputs, with one-line errors.

Inputs (.mxm, scenes, traces, case files) are UTF-8; a byte-order mark is
dropped and CRLF or CR line ends read as LF.  A file that is missing, a
folder, unreadable or not UTF-8 is a `FILE[:LINE:COL]: error: ...` naming
that file.  Outputs: `-` is standard output; a device or a named pipe is
written in place; a missing folder, a folder as the file, or a file that
cannot be written is an error naming the `-o` argument (or standard
output), raised before any work is lost where the caller checks first
(`check_output`).
"""
from __future__ import annotations

import os
import stat
import sys
import tempfile
from contextlib import contextmanager
from typing import IO, Iterator

from max2code.errors import Max2CodeError


class InputError(Max2CodeError):
    """An input file that cannot be read as UTF-8 text."""


class OutputError(Max2CodeError):
    """An output that cannot be written."""


def decode(data: bytes, path: str) -> str:
    """UTF-8 text of `data` (BOM dropped, line ends made LF); else InputError at the bad byte."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        start = exc.start + (3 if data.startswith(b"\xef\xbb\xbf") else 0)
        line = data.count(b"\n", 0, start) + 1
        col = start - (data.rfind(b"\n", 0, start) + 1) + 1
        raise InputError(f"{path}:{line}:{col}: error: not UTF-8 text (byte 0x{data[start]:02x}: {exc.reason}); "
                         "save the file as UTF-8") from None
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text


def read_text(path: str) -> str:
    """The UTF-8 text of the file at `path` (see `decode`)."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except FileNotFoundError:
        raise InputError(f"{path}: error: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: error: is a folder, expected a file") from None
    except OSError as exc:
        raise InputError(f"{path}: error: cannot read: {exc.strerror or exc}") from None
    return decode(data, path)


def check_output(path: str | None, option: str = "-o") -> None:
    """Refuse an output path that cannot be written, before doing the work."""
    if path is None or path == "-":
        return
    if not path.strip():
        raise OutputError(f"{option} '{path}': error: expected a file name (or '-' for standard output)")
    if os.path.isdir(path):
        raise OutputError(f"{option} {path}: error: is a folder; give a file name")
    folder = os.path.dirname(path) or "."
    if not os.path.isdir(folder):
        raise OutputError(f"{option} {path}: error: the folder '{folder}' does not exist")
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise OutputError(f"{option} {path}: error: not writable")


@contextmanager
def open_output(path: str | None, option: str = "-o") -> Iterator[IO[str]]:
    """A text stream for `path` (`-` or None: standard output).  A file is
    written under a temporary name and renamed when the block ends without an
    exception, so a failed run leaves no half-written file."""
    if path is None or path == "-":
        try:
            yield sys.stdout
            sys.stdout.flush()
        except BrokenPipeError:
            raise           # the reader is gone: the caller ends quietly (cli.main)
        except OSError as exc:
            if exc.filename is not None:
                raise       # another file's fault, as below
            raise OutputError(f"standard output: error: cannot write: {exc.strerror or exc}") from None
        return
    check_output(path, option)
    try:
        special = not stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        special = False     # not there yet (or not to be seen): written under a temporary name, as any file
    if special:
        # a device or a named pipe (/dev/null, a FIFO): written in place; a file renamed over it would replace it
        # (as root, even /dev/null)
        try:
            fh = open(path, "w", encoding="utf-8", newline="\n")
        except OSError as exc:
            raise OutputError(f"{option} {path}: error: cannot write: {exc.strerror or exc}") from None
        try:
            with fh:
                yield fh
        except BrokenPipeError:
            raise           # the pipe's reader is gone: the caller ends quietly (cli.main)
        except OSError as exc:
            if exc.filename not in (None, path):
                raise       # another file's fault, as below
            raise OutputError(f"{option} {path}: error: cannot write: {exc.strerror or exc}") from None
        return
    folder = os.path.dirname(path) or "."
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise OutputError(f"{option} {path}: error: cannot write: {exc.strerror or exc}") from None
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            yield fh
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        if exc.filename not in (None, tmp, path):
            raise           # another file's fault (a program that cannot start, an input): not the output's
        raise OutputError(f"{option} {path}: error: cannot write: {exc.strerror or exc}") from None
    except BaseException:
        _remove(tmp)
        raise


def write_output(path: str | None, text: str, option: str = "-o") -> None:
    with open_output(path, option) as fh:
        fh.write(text)


def _remove(p: str) -> None:
    try:
        os.unlink(p)
    except OSError:
        pass


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
