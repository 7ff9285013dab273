"""Starts a private lbsolidd on a free loopback port, for scripts and tests that bring their own.

    with LocalDaemon() as daemon:
        client = Client(daemon.address)

The daemon binds port 0 and writes the port it got to a file (--port_file), so two runs never
collide; it is stopped with SIGTERM (it pauses, saves and exits 0) when the block ends.
"""
import os
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

from . import _stubs


def default_binary() -> Path:
    """$LBSOLIDD, else the source tree's build, else lbsolidd on PATH (installed)."""
    if "LBSOLIDD" in os.environ:
        return Path(os.environ["LBSOLIDD"])
    built = _stubs.build_dir() / "server" / "lbsolidd"
    if built.exists():
        return built
    installed = shutil.which("lbsolidd")
    return Path(installed) if installed else built


class LocalDaemon:
    def __init__(self, binary=None, data_dir=None, workers=None, log_level="warn", start_timeout=30.0,
                 extra_args=()):
        """`extra_args`: more lbsolidd flags (e.g. --tls_cert, --tokens_file)."""
        self.binary = Path(binary) if binary else default_binary()
        if not self.binary.exists():
            raise FileNotFoundError(f"lbsolidd not found at {self.binary}: build the project or set LBSOLIDD")
        self._own_dir = data_dir is None
        self.data_dir = Path(data_dir) if data_dir else Path(tempfile.mkdtemp(prefix="lbsolidd-"))
        self.workers = workers
        self.log_level = log_level
        self.start_timeout = start_timeout
        self.extra_args = list(extra_args)
        self.process = None
        self.address = None

    def start(self):
        port_file = self.data_dir / "port"
        if port_file.exists():
            port_file.unlink()
        args = [str(self.binary), "--listen", "127.0.0.1:0", "--port_file", str(port_file),
                "--data_dir", str(self.data_dir / "data"), "--log_level", self.log_level]
        if self.workers:
            args += ["--workers", str(self.workers)]
        args += self.extra_args
        self.process = subprocess.Popen(args, stdout=subprocess.DEVNULL)
        deadline = time.monotonic() + self.start_timeout
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise RuntimeError(f"lbsolidd exited with code {self.process.returncode} while starting")
            text = port_file.read_text().strip() if port_file.exists() else ""
            if text.isdigit():
                self.address = f"127.0.0.1:{text}"
                return self
            time.sleep(0.02)
        self.stop()
        raise TimeoutError(f"lbsolidd did not report its port within {self.start_timeout} s")

    def stop(self):
        if self.process and self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self._own_dir:
            shutil.rmtree(self.data_dir, ignore_errors=True)

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
        return False
