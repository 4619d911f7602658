"""Ctrl-C stops a study that runs in worker processes (issue 14: never a
hang). Leaving the process pool by its context manager waited for every
queued parameter set; a Ctrl-C on the terminal (SIGINT to the whole process
group, the workers included) then hung until killed."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

SCRIPT = textwrap.dedent(
    """
    import signal, sys, time
    from pathlib import Path
    import hbmfric as hf

    MARK = Path(sys.argv[1])

    def build(p):
        MARK.touch()
        time.sleep(2.0)
        return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 1.0))

    if __name__ == "__main__":
        signal.signal(signal.SIGINT, signal.default_int_handler)
        hf.study(build, hf.grid(force=[0.1] * 30), (0.5, 3.0), workers=2,
                 harmonics=1, progress=False)
        print("finished every set")
    """
)


@pytest.mark.skipif(sys.platform == "win32", reason="process groups and SIGINT")
def test_ctrl_c_stops_a_process_study(tmp_path):
    script = tmp_path / "interrupted_study.py"
    script.write_text(SCRIPT)
    mark = tmp_path / "started"
    root = Path(__file__).resolve().parents[1]
    env = {
        **os.environ,
        "PYTHONPATH": f"{root}{os.pathsep}" + os.environ.get("PYTHONPATH", ""),
    }
    proc = subprocess.Popen(
        [sys.executable, str(script), str(mark)],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,  # its own process group, as on a terminal
    )
    try:
        deadline = time.monotonic() + 120.0
        while not mark.exists():
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "the study never started"
            time.sleep(0.05)
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: the main and the workers
        sent = time.monotonic()
        try:
            out, err = proc.communicate(timeout=30.0)
        except subprocess.TimeoutExpired:
            pytest.fail("the study did not stop within 30 s of Ctrl-C")
        # 30 sets of 2 s on 2 workers: finishing them would take 30 s
        assert time.monotonic() - sent < 10.0
        assert proc.returncode != 0
        assert b"KeyboardInterrupt" in err
        assert b"finished every set" not in out
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
