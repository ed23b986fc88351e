"""Errors that max2code reports to the user as `FILE:LINE:COL: message`."""
from __future__ import annotations

import argparse

from max2code.record import FrozenRecord


class Max2CodeError(Exception):
    """An error meant for the user; printed without a traceback."""


class Span(FrozenRecord):
    """A place in a source file: 1-based line and column."""
    _fields = ("file", "line", "column")

    def __init__(self, file: str, line: int, column: int):
        self._set(file=file, line=line, column=column)

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


class SourceError(Max2CodeError):
    """An error at a place in a .mxm file (or another input file)."""

    def __init__(self, span: Span, message: str):
        self.span = span
        self.message = message
        super().__init__(f"{span}: error: {message}")


class InternalError(Max2CodeError):
    """A bug in max2code caught by one of its own checks (e.g. generated code
    that differs from Maxima's polynomial): printed in one line, without a
    traceback, with exit status 2 (kept for bugs)."""

    exit_status = 2


class UsageError(Max2CodeError):
    """A bad command line: an unknown option, a missing or malformed value."""


class ArgumentParser(argparse.ArgumentParser):
    """argparse, but a usage mistake is one line and exit status 1 like every
    other user mistake (argparse itself prints the usage and exits 2, which
    max2code keeps for bugs)."""

    def error(self, message: str):
        raise UsageError(f"{self.prog}: error: {message} (see '{self.prog} --help')")
