"""A private virtual X display, for programs that render through X on a machine without a screen
(pvpython, YADE's Qt view).

Xvfb picks its own display number with -displayfd: it takes the first free one by creating its
lock file, so that two callers starting at the same moment get two displays (xvfb-run -a looks
for a free number first and starts the server after, so that two of them can pick the same one:
one program then draws on the other's server, or on one that is going away).

The server runs with -noreset: an X server by default resets when its last client disconnects
and refuses connections meanwhile, and pvpython connects several times in a row (refused on a
loaded machine: "bad X server connection", then an abort)."""
import contextlib
import os
import shutil
import subprocess
import tempfile


@contextlib.contextmanager
def virtual_display(width=1600, height=1200):
    """Start Xvfb (screen width x height, 24 bits) and yield its DISPLAY (':N'); stop it on exit.
    Raises RuntimeError if Xvfb is not installed or does not start."""
    exe = shutil.which("Xvfb")
    if exe is None:
        raise RuntimeError("Xvfb not found (Debian package xvfb): it is needed to render without a display")
    r, w = os.pipe()
    with tempfile.TemporaryFile(mode="w+") as log:
        try:
            p = subprocess.Popen([exe, "-displayfd", str(w), "-screen", "0", f"{width}x{height}x24", "-nolisten", "tcp", "-noreset"],
                                 pass_fds=(w,), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=log)
        finally:
            os.close(w)
        with os.fdopen(r) as f:
            number = f.readline().strip()  # written once the server accepts clients; nothing if it died
        if not number.isdigit():
            p.kill()
            p.wait()
            log.seek(0)
            raise RuntimeError(f"Xvfb did not start (exit {p.returncode}): {log.read()[-500:].strip()}")
        try:
            yield ":" + number
        finally:
            p.terminate()
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
