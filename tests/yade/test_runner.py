"""The suite's own settings (tests/yade/pytest.ini): a pytest-xdist worker that crashes ends the
run, with the test it was running named, and is not replaced; a test that hangs fails at the
suite's timeout, and the run ends."""
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def test_a_crashed_worker_ends_the_run_with_its_test_named(tmp_path):
    shutil.copy(os.path.join(HERE, "pytest.ini"), tmp_path)
    (tmp_path / "test_crash.py").write_text("import os\nimport signal\n\n\ndef test_crash():\n    os.kill(os.getpid(), signal.SIGSEGV)\n")
    (tmp_path / "test_other.py").write_text("def test_fine():\n    pass\n")
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}  # (not this run's worker)
    res = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", "-n", "2", "--dist", "loadfile"], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=600)
    out = res.stdout + res.stderr
    assert res.returncode == 1, out
    assert "crashed while running 'test_crash.py::test_crash'" in out, out
    assert out.count("FAILED test_crash.py::test_crash") == 1, "a replacement worker ran the crashing test again:\n" + out


def test_a_hung_test_ends_the_run_with_its_test_named(tmp_path):
    """A test that never returns (here: waits on an event nobody sets) fails at the suite's
    timeout (pytest-timeout, shortened to 3 s here) with the stacks printed, and its worker is not
    replaced: the run ends instead of waiting for ever."""
    shutil.copy(os.path.join(HERE, "pytest.ini"), tmp_path)
    (tmp_path / "test_hang.py").write_text("import threading\n\n\ndef test_hang():\n    threading.Event().wait()\n")
    (tmp_path / "test_other.py").write_text("def test_fine():\n    pass\n")
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
    res = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", "-n", "2", "--dist", "loadfile", "-o", "timeout=3"],
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
    out = res.stdout + res.stderr
    assert res.returncode == 1, out
    assert "Timeout" in out and "test_hang" in out, out
