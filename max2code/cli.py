"""Command line: `max2code --lang=LANG FILE.mxm -o OUT` and the subcommands.

The generator form is the paper's figure 11.  Other jobs are subcommands,
registered by name in SUBCOMMANDS as "module:function"; each function takes
the remaining argv and returns an exit status.
"""
from __future__ import annotations

import argparse
import math
import os
import importlib
import signal
import sys
import threading

from max2code.errors import ArgumentParser, Max2CodeError
from max2code.targets import LANGUAGES
from max2code.textio import check_output, write_output

# name -> "module:function(argv) -> int"
SUBCOMMANDS: dict[str, str] = {
    "conformance": "max2code.conformance.runner:main",
    "cases": "max2code.conformance.user_cases:main",
    "table": "max2code.reports.table:main",
    "bench-variants": "max2code.reports.bench_variants:main",
    "accuracy": "max2code.reports.accuracy:main",
    "simulate": "max2code.sim.commands:simulate_main",
    "crosscheck": "max2code.sim.commands:crosscheck_main",
    "event-vs-frame": "max2code.reports.event_vs_frame:main",
    "render": "max2code.draw.render:render_main",
    "runtime": "max2code.toolchain.install:runtime_main",
    "choose-language": "max2code.reports.choose_language:main",
    "bundled": "max2code.toolchain.install:bundled_main",
}


def _generate_parser() -> argparse.ArgumentParser:
    # imported here: a subcommand (simulate, above all) starts without the generator's modules
    from max2code import __version__
    from max2code.generate.maxima import DEFAULT_TIMEOUT

    p = ArgumentParser(
        prog="max2code",
        description=(
            "Generate time-of-collision coefficient code from a .mxm file. "
            "The Maxima text between 'begin' and 'end' is expanded by Maxima into a "
            "polynomial in t; max2code collects its coefficients by power of t, proves "
            "the collection equals Maxima's polynomial, and prints code for LANG.  "
            "Subcommands: " + ", ".join(sorted(SUBCOMMANDS)) + " (run 'max2code SUB --help')."
        ),
        epilog="example: max2code --lang=m2 point-line.mxm -o point-line.mxd",
    )
    p.add_argument("--version", action="version", version=f"max2code {__version__}",
                   help="print the version of max2code and exit")
    p.add_argument("--lang", "-l", choices=sorted(LANGUAGES),
                   help="target language")
    p.add_argument("file", help="the .mxm file")
    p.add_argument("-o", "--output", default="-",
                   help="output file ('-' for standard output, the default)")
    p.add_argument("--no-line", action="store_true",
                   help="omit #line directives (C, Modula-2) and origin comments (Python, Rust)")
    p.add_argument("--option", "-D", action="append", default=[], metavar="NAME=VALUE",
                   help="override an 'option' declared in the .mxm file, e.g. -D order=6")
    p.add_argument("--naive", action="store_true",
                   help="print each coefficient as its plain expansion (no shared subexpressions)")
    p.add_argument("--effects", metavar="LIST",
                   help="the effects your world uses, comma-separated from: acceleration, orbit "
                        "(e.g. --effects=acceleration for gravity without rotation; 'none' for neither); "
                        "only the variants such a world reaches are generated.  Default: all")
    p.add_argument("--exact", action="store_true",
                   help="also generate the exact-motion entries from the file's 'exact' and 'shift' declarations: "
                        "NAME_gap, NAME_gap_dt, NAME_shift, ... and NAME_toc_exact; for a file whose polynomial is "
                        "the exact gap (no 'exact', no Taylor sum, no rotation) NAME_toc_exact on the polynomial "
                        "itself (docs/exact-motion.md)")
    p.add_argument("--real", choices=["double", "float"], default="double",
                   help="arithmetic of the generated code: double (default) or float (C float, Rust f32, "
                        "Modula-2 SHORTREAL: the same bits in all three, sin and cos being the C library's sinf and "
                        "cosf, which Modula-2 imports from runtimes/m2/ShortMath.def; interfaces stay double; "
                        "Python has no float)")
    p.add_argument("--no-variants", action="store_true",
                   help="only the full equation, no variants and no selection logic")
    p.add_argument("--list-variants", action="store_true",
                   help="print the variants as JSON (name, conditions, degree, terms, multiplications) and exit")
    p.add_argument("--header", action=argparse.BooleanOptionalAction, default=None,
                   help="also write the declarations next to -o FILE (C: FILE.h with every entry's prototype and "
                        "degree constants); default: on for C with -o FILE")
    p.add_argument("--no-cache", action="store_true", help="do not read or write the Maxima result cache")
    p.add_argument("--maxima-timeout", type=_seconds, default=DEFAULT_TIMEOUT, metavar="SECONDS",
                   help=f"give up on a Maxima run after this many seconds (default {DEFAULT_TIMEOUT:g})")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress messages on stderr")
    return p


def _seconds(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not (v > 0 and math.isfinite(v)):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds, got {text!r}")
    return v


def _parse_options(items: list[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise Max2CodeError(f"--option expects NAME=VALUE, got {item!r}")
        out[name.strip()] = value.strip()
    return out


def generate_main(argv: list[str]) -> int:
    from max2code.generate.pipeline import GenerateRequest, generate_file  # here: subcommands start without it

    parser = _generate_parser()
    args = parser.parse_args(argv)
    effects = None
    if args.effects is not None:
        effects = tuple(e.strip() for e in args.effects.split(",") if e.strip() and e.strip() != "none")
    if args.list_variants:
        return list_variants(args, effects)
    if not args.lang:
        parser.error("--lang is required (c, m2, python or rust)")
    header = args.header if args.header is not None else (
        args.output != "-" and LANGUAGES[args.lang].header_extension is not None)
    if header and args.output == "-":
        parser.error("--header needs -o FILE (the header is written next to it)")
    req = GenerateRequest(
        path=args.file,
        lang=args.lang,
        line_directives=not args.no_line,
        options=_parse_options(args.option),
        shared=not args.naive,
        use_cache=not args.no_cache,
        maxima_timeout=args.maxima_timeout,
        progress=not args.quiet,
        out_name=None if args.output == "-" else os.path.basename(args.output),
        variants=not args.no_variants,
        effects=effects,
        exact=args.exact,
        real=args.real,
        header=header,
    )
    check_output(args.output)
    result = generate_file(req)
    write_output(args.output, result.text)
    if result.header is not None and args.output not in (None, "-"):
        write_output(os.path.join(os.path.dirname(args.output), result.header_name), result.header)
    return 0


def list_variants(args, effects) -> int:
    import json

    # imported here: subcommands start without the generator's modules
    from max2code.generate.mxm import read_mxm
    from max2code.generate.names import check_names
    from max2code.generate.pipeline import derive
    from max2code.generate.variants import derive_variants

    check_output(args.output)
    mod = read_mxm(args.file)
    check_names(mod)
    d = derive(mod, _parse_options(args.option), use_cache=not args.no_cache,
               timeout=args.maxima_timeout, progress=not args.quiet)
    vs = derive_variants(d, effects=effects, use_cache=not args.no_cache, timeout=args.maxima_timeout,
                         progress=not args.quiet)
    write_output(args.output, json.dumps([v.describe() for v in vs], indent=2) + "\n")
    return 0


class Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGINT, raised wherever the program is, so that every
    `finally` and `except BaseException` on the way out runs: a temporary
    output is removed (textio.open_output) and a child process stopped
    (simulate.stream_scene), which the default action of SIGTERM (the
    process ends at once) skipped."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


STOP_SIGNALS = (signal.SIGTERM, signal.SIGINT)


def _stop(signum: int, _frame) -> None:
    for s in STOP_SIGNALS:          # the cleanup on the way out is not cut short by a second signal
        signal.signal(s, signal.SIG_IGN)
    raise Interrupted(signum)


def _catch_signals() -> dict:
    """Handle STOP_SIGNALS with _stop (only the main thread may); the handlers they had."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    return {s: signal.signal(s, _stop) for s in STOP_SIGNALS}


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    previous = _catch_signals()
    try:
        return _main(argv)
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def _main(argv: list[str]) -> int:
    try:
        if argv and argv[0] in SUBCOMMANDS:
            mod_name, func_name = SUBCOMMANDS[argv[0]].split(":")
            func = getattr(importlib.import_module(mod_name), func_name)
            return int(func(argv[1:]) or 0)
        return generate_main(argv)
    except Max2CodeError as exc:
        print(str(exc), file=sys.stderr)
        return getattr(exc, "exit_status", 1)
    except KeyboardInterrupt as exc:        # Ctrl-C, SIGINT or SIGTERM (Interrupted): 128 + the signal, as a shell says
        signum = getattr(exc, "signum", signal.SIGINT)
        print(f"max2code: {'terminated' if signum == signal.SIGTERM else 'interrupted'}", file=sys.stderr)
        return 128 + signum
    except BrokenPipeError:     # the reader of standard output is gone (`| head`): quiet, as a Unix tool
        return BROKEN_PIPE
    except Exception as exc:  # a bug: say so in one line, never a traceback
        print(f"max2code: internal error: {type(exc).__name__}: {exc} (please report this; "
              "set MAX2CODE_DEBUG=1 for the traceback)", file=sys.stderr)
        if os.environ.get("MAX2CODE_DEBUG"):
            raise
        return 2


# the exit status of a program whose reader of standard output went away: what a shell reports for a Unix tool
# ended by SIGPIPE (128 + 13); Python ignores the signal, so the failed write raises BrokenPipeError instead
BROKEN_PIPE = 141

# subcommands that leave nothing to clean up when they return (every file closed and renamed, every child process
# and thread waited for): their process ends at once after standard output and error are flushed, without the
# interpreter's own shutdown, which takes longer than their work on a small scene (15-25 ms: freeing every module and
# object one by one)
QUICK_EXIT = frozenset({"simulate"})


def _flush_output(status: int) -> int:
    """Flush standard output and error after main() returned `status`; the
    status to exit with.  What cannot be written any more (reader gone, disk
    full) is dropped, with standard output pointed at the null device so that
    the interpreter's own last flush finds nothing to complain of: a gone
    reader ends quietly with BROKEN_PIPE, another failure says why on
    standard error and exits 1 (unless main() already failed and said so)."""
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        _drop(sys.stdout)
        status = BROKEN_PIPE
    except OSError as exc:
        _drop(sys.stdout)
        if status == 0:
            print(f"max2code: error: standard output: cannot write: {exc.strerror or exc}", file=sys.stderr)
            status = 1
    except ValueError:
        pass        # closed: nothing is left to write
    try:
        sys.stderr.flush()
    except (OSError, ValueError):
        _drop(sys.stderr)
    return status


def _drop(stream) -> None:
    """Point `stream`'s file descriptor at the null device (what is still
    buffered in it then goes nowhere)."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, stream.fileno())
        os.close(null)
    except (OSError, ValueError):
        pass


def run() -> None:
    """The program (`python -m max2code`, the `max2code` script): main(),
    then the exit; a subcommand of QUICK_EXIT ends with os._exit once its
    output is flushed (main() itself returns, as tests call it)."""
    argv = sys.argv[1:]
    status = _flush_output(main(argv))
    if argv and argv[0] in QUICK_EXIT and not os.environ.get("MAX2CODE_DEBUG"):
        os._exit(status)
    raise SystemExit(status)


if __name__ == "__main__":
    run()
