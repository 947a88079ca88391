"""`corps teleop` at a terminal: run in a pseudo-terminal, it draws its display, keys steer
the robot in real time, and Ctrl-C ends the session with the terminal restored (canonical
mode and echo back on, the alternate screen left) and the report printed.

CORPS_BIN names the command (tools/test.sh passes the one `cargo test` built)."""

import fcntl
import os
import pty
import re
import select
import struct
import termios
import time
from pathlib import Path

import pytest

CORPS = os.environ.get("CORPS_BIN")
REPO = Path(__file__).resolve().parents[2]


def read_for(fd, seconds, out):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if ready:
            try:
                out.extend(os.read(fd, 65536))
            except OSError:  # the child closed the terminal
                return


@pytest.mark.skipif(not CORPS, reason="set CORPS_BIN to the corps command")
def test_keys_steer_the_robot_and_ctrl_c_restores_the_terminal(tmp_path):
    pid, fd = pty.fork()
    if pid == 0:
        os.chdir(REPO)
        os.environ["TERM"] = "xterm-256color"
        os.execv(CORPS, [CORPS, "teleop", "-o", str(tmp_path / "out"), "--duration", "60"])
    fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", 30, 110, 0, 0))
    out = bytearray()
    read_for(fd, 3.0, out)
    os.write(fd, b"i")
    read_for(fd, 0.3, out)
    os.write(fd, b"i")  # forward 0.2 m/s
    t_walk = time.monotonic()
    read_for(fd, 6.0, out)
    walked = time.monotonic() - t_walk
    os.write(fd, b"\x03")  # Ctrl-C, delivered as a key in raw mode
    read_for(fd, 10.0, out)
    _, status = os.waitpid(pid, 0)
    attrs = termios.tcgetattr(fd)
    os.close(fd)
    text = out.decode("utf-8", "replace")
    assert os.waitstatus_to_exitcode(status) == 0, text[-2000:]
    for shown in ("corps teleop", "commanded", "achieved", "steps", "µs/tick"):
        assert shown in text, shown
    assert "\x1b[?1049h" in text and "\x1b[?1049l" in text, "the alternate screen entered and left"
    lflag = attrs[3]
    assert lflag & termios.ICANON and lflag & termios.ECHO, "canonical mode and echo restored"
    report = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", text)
    stopped = re.search(r"stopped by the operator at t = ([0-9.]+) s", report)
    assert stopped, report[-2000:]
    # Real time: the simulated time at the stop is about the wall time since the start.
    t_stop = float(stopped.group(1))
    assert t_stop > walked, (t_stop, walked)
    travelled = float(re.search(r"travelled ([0-9.]+) m", report).group(1))
    # 0.2 m/s for about 6 s of which the first 1.2 s is the MPC's starting double support.
    assert 0.5 < travelled < 1.4, travelled
