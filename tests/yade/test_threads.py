"""Determinism: the same run twice is bitwise identical with one thread; with two threads,
and between -j1 and -j2, results agree to round-off.

YADE's InteractionLoop hands interactions to threads with schedule(guided) and sums per-thread
force buffers, so with two threads the order of additions changes from run to run (last-bit
differences, measured 2e-16 m); that is YADE's design, not ours (FlexElementEngine uses a
static schedule). Nonlinear dynamics amplify that: on the net impact below the
difference is ~1e-18 m after 100 steps, ~1e-12 m after 300 and visible after 1000 (measured;
a sagging net without contact shows the same growth, and its energy is conserved to 0.04%
over 60,000 steps, so it is sensitivity, not instability). The comparison therefore uses a
horizon with contacts active but before that amplification."""
import json
import os

from conftest import run_yade, HERE


def _run(j, steps=400, kind="impact"):
    out = run_yade(os.path.join(HERE, "scripts", "threads_scene.py"), threads=j, args=[steps, kind])
    line = [l for l in out.splitlines() if l.startswith("POS ")][-1]
    return json.loads(line[4:])


def _maxdiff(a, b):
    return max(abs(x - y) for pa, pb in zip(a["pos"], b["pos"]) for x, y in zip(pa, pb))


def test_one_thread_is_bitwise_reproducible():
    a, b = _run(1), _run(1)
    assert a["contacts"] > 0
    assert _maxdiff(a, b) == 0.0


def test_two_threads_reproduce_to_round_off():
    a, b = _run(2), _run(2)
    assert a["contacts"] > 0 and a["contacts"] == b["contacts"]
    assert _maxdiff(a, b) < 1e-13


def test_one_and_two_threads_agree_to_round_off():
    a, b = _run(1), _run(2)
    assert a["contacts"] > 0 and a["contacts"] == b["contacts"]
    d = _maxdiff(a, b)
    assert d < 1e-13, f"-j1 vs -j2 position difference {d} m after 200 steps"
