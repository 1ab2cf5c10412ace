"""SciPy's own interpolate tests against splinegpu.interpolate (scipy_suite/run.py): no file's
pass count may fall below the ratchet, and every test SciPy passes that fails here must be a
listed, documented difference. And the runner itself: a crash or a hang in one test costs that
test, not the session."""

import shutil
import subprocess
import sys
from pathlib import Path

SUITE = Path(__file__).parent / "scipy_suite"
sys.path.insert(0, str(SUITE))

import run  # noqa: E402


def test_scipys_suite_passes_up_to_the_ratchet():
    done = subprocess.run([sys.executable, str(SUITE / "run.py"), "--check"],
                          capture_output=True, text=True, timeout=1800, check=False)
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_runner_survives_a_crash_and_a_hang(tmp_path):
    (tmp_path / "test_probe.py").write_text(
        "import os, time\n"
        "from math import sqrt\n"
        "def test_passes():\n    assert sqrt(4) == 2\n"
        "def test_aborts():\n    sqrt(1)\n    os.abort()\n"
        "def test_hangs():\n    sqrt(1)\n    time.sleep(60)\n"
        "def test_fails():\n    assert sqrt(4) == 3\n"
        "def test_unselected():\n    pass\n", encoding="utf-8")
    shutil.copy(SUITE / "plugin.py", tmp_path / "suite_plugin.py")
    outcomes = run.run_session(tmp_path, {"test_probe.py": ["sqrt"]}, timeout=3.0,
                               files=("test_probe.py",))
    assert {k: v[0] for k, v in outcomes.items()} == {
        "test_probe.py::test_passes": "passed",
        "test_probe.py::test_aborts": "failed",
        "test_probe.py::test_hangs": "failed",
        "test_probe.py::test_fails": "failed",
    }
