"""Running the fenestra binary: its progress lines read as they come, a clean stop (SIGINT,
as Ctrl-C: fenestra writes what it has), and no orphan when Blender dies."""

import ctypes
import os
import signal
import subprocess
import threading
from dataclasses import dataclass, field


def _die_with_parent():
    """In the child before exec: a SIGINT when the parent (Blender) goes away (Linux)."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGINT)  # PR_SET_DEATHSIG
    except (OSError, AttributeError):
        pass


@dataclass
class Progress:
    """What fenestra has said so far."""

    done: int = 0
    total: int = 0  # 0 when a time limit ends the render
    seconds: float = 0.0
    warnings: list = field(default_factory=list)
    log: list = field(default_factory=list)


class Fenestra:
    """A running fenestra command, its stderr parsed into `progress` by a reader thread."""

    def __init__(self, command, log_path=None):
        self.command = command
        self.progress = Progress()
        self._lock = threading.Lock()
        self._log = open(log_path, "w") if log_path else None
        self.process = subprocess.Popen(
            command,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=_die_with_parent if os.name == "posix" else None,
        )
        self._out = []
        self._readers = [
            threading.Thread(target=self._read_stderr, daemon=True),
            threading.Thread(target=self._read_stdout, daemon=True),
        ]
        for t in self._readers:
            t.start()

    def _read_stdout(self):
        for line in self.process.stdout:
            self._out.append(line)
            if self._log:
                self._log.write(line)

    def _read_stderr(self):
        for line in self.process.stderr:
            if self._log:
                self._log.write(line)
            line = line.rstrip("\n")
            parts = line.split()
            with self._lock:
                if len(parts) == 4 and parts[0] == "progress":
                    p = self.progress
                    p.done = int(parts[1])
                    p.total = 0 if parts[2] == "-" else int(parts[2])
                    p.seconds = float(parts[3])
                elif line.startswith("warning: "):
                    self.progress.warnings.append(line[len("warning: ") :])
                else:
                    self.progress.log.append(line)

    def snapshot(self):
        """A copy of the progress so far."""
        with self._lock:
            p = self.progress
            return Progress(p.done, p.total, p.seconds, list(p.warnings), list(p.log))

    def running(self):
        return self.process.poll() is None

    def stop(self):
        """Asks fenestra to stop as Ctrl-C does: it writes the image so far."""
        if self.running():
            self.process.send_signal(signal.SIGINT)

    def wait(self, timeout=None):
        """Waits for the end; the exit code, stdout and the stderr lines that were not
        progress or warnings."""
        code = self.process.wait(timeout)
        for t in self._readers:
            t.join()
        if self._log:
            self._log.close()
        return code, "".join(self._out), self.progress.log

    def kill(self):
        if self.running():
            self.process.kill()


def fraction(progress, time_limit):
    """How far the render is (0-1) and the seconds left, if known."""
    parts = []
    if progress.total:
        parts.append(progress.done / progress.total)
    if time_limit > 0:
        parts.append(progress.seconds / time_limit)
    if not parts:
        return 0.0, None
    f = min(1.0, max(parts))
    left = progress.seconds * (1 - f) / f if f > 0.01 else None
    return f, left
