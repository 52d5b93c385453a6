"""yadeflex.xdisplay: the private virtual X display that pvpython and YADE's view render on.

Xvfb, like every X server, by default resets itself when its last client disconnects; a client
that connects during the reset is refused. pvpython connects several times in a row, so on a
loaded machine it was refused on its own live display ("bad X server connection", then SIGABRT).
The display must therefore not reset: a root-window property set by one client is still there
for the next (a reset clears it)."""
import concurrent.futures
import shutil
import subprocess

import pytest

from yadeflex.xdisplay import virtual_display

pytestmark = pytest.mark.skipif(shutil.which("Xvfb") is None or shutil.which("xprop") is None,
                                reason="needs Xvfb (Debian xvfb) and xprop (Debian x11-utils)")


def _xprop(display, *args):
    return subprocess.run(["xprop", "-display", display, "-root", *args], capture_output=True, text=True, timeout=60)


def test_display_keeps_its_state_when_its_last_client_leaves():
    with virtual_display(320, 240) as d:
        assert _xprop(d, "-f", "YADEFLEX_MARK", "8s", "-set", "YADEFLEX_MARK", "kept").returncode == 0
        # xprop has disconnected: the server had no client left
        for _ in range(3):
            r = _xprop(d, "YADEFLEX_MARK")
            assert r.returncode == 0 and '"kept"' in r.stdout, r.stdout + r.stderr


def test_displays_started_at_once_are_distinct_and_live():
    def one(_):
        with virtual_display(320, 240) as d:
            return d, _xprop(d, "-f", "YADEFLEX_MARK", "8s", "-set", "YADEFLEX_MARK", d).returncode, _xprop(d, "YADEFLEX_MARK").stdout
    with concurrent.futures.ThreadPoolExecutor(4) as ex:
        got = list(ex.map(one, range(4)))
    assert len({d for d, _, _ in got}) == 4, got
    # each display holds what was set on it, not another's value
    assert all(rc == 0 and f'"{d}"' in out for d, rc, out in got), got
