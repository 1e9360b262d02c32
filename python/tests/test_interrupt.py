"""Ctrl-C during Model.simulate (issue 28): the run stops within a step and
KeyboardInterrupt is raised in the caller (before: the signal waited until
the run ended, minutes later, and its result was then discarded)."""
import os
import signal
import subprocess
import sys
import textwrap
import time

from conftest import model

SCRIPT = textwrap.dedent("""
    import sys, time
    import ldaec
    m = ldaec.compile(sys.argv[1], cache=False)
    print("ready", flush=True)
    t0 = time.monotonic()
    try:
        m.simulate(stop=1e6, interval=0.1, rtol=1e-10)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("KeyboardInterrupt after %.1f s" % (time.monotonic() - t0),
              flush=True)
""")


def test_ctrl_c_raises_keyboard_interrupt(tmp_path):
    path = tmp_path / "oscillator.lsd"
    path.write_text("model Oscillator\n"
                    "  Real x(start = 1, fixed = true), v(start = 0, fixed = true);\n"
                    "equation\n  der(x) = v;\n  der(v) = -x;\n"
                    "end Oscillator;\n")
    p = subprocess.Popen([sys.executable, "-c", SCRIPT, str(path)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=os.environ)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)  # integrating: a million seconds take minutes
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    assert "KeyboardInterrupt after" in out, (out, err)
    assert "finished" not in out
