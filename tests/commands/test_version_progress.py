"""`max2code --version`, and the progress bar's plain lines when stderr is not a terminal."""
import io
import subprocess
import sys

import max2code
from max2code import progress


def test_version_is_the_package_version():
    r = subprocess.run([sys.executable, "-m", "max2code", "--version"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and r.stdout == f"max2code {max2code.__version__}\n", (r.stdout, r.stderr)


class _Stream(io.StringIO):
    def __init__(self, tty):
        super().__init__()
        self.tty = tty

    def isatty(self):
        return self.tty


def _draw(monkeypatch, tty, n):
    s = _Stream(tty)
    monkeypatch.setattr(sys, "stderr", s)
    for i in range(n + 1):
        progress.bar(i, n, f"step {i}")
    return s.getvalue()


def test_progress_in_a_log_is_plain_lines(monkeypatch):
    text = _draw(monkeypatch, False, 200)
    assert "\r" not in text
    lines = text.splitlines()
    # the start, every tenth of the work, the end
    assert [ln.split()[1] for ln in lines] == [f"{20 * k}/200" for k in range(11)], lines
    assert lines[-1] == "max2code: 200/200 step 200"
    assert len(_draw(monkeypatch, False, 3).splitlines()) == 4


def test_progress_on_a_terminal_is_one_redrawn_line(monkeypatch):
    text = _draw(monkeypatch, True, 5)
    assert text.count("\r") == 6 and text.count("\n") == 1 and text.endswith("\n")
