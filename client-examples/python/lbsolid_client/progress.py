"""A one-line progress bar for a terminal (silent elsewhere, so logs and pipes stay clean)."""
import sys


class ProgressBar:
    def __init__(self, label: str, stream=None, width: int = 30):
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty()
        self.label = label
        self.width = width
        self._shown = False

    def update(self, step: int, target: int, steps_per_second: float = 0.0, seconds_left: float = 0.0):
        if not self.enabled or target <= 0:
            return
        done = min(max(step / target, 0.0), 1.0)
        filled = int(done * self.width)
        bar = "#" * filled + "-" * (self.width - filled)
        rate = f" {steps_per_second:8.0f} steps/s  ETA {seconds_left:6.1f} s" if steps_per_second > 0 else ""
        self.stream.write(f"\r{self.label} [{bar}] {step}/{target}{rate}")
        self.stream.flush()
        self._shown = True

    def close(self):
        if self._shown:
            self.stream.write("\n")
            self.stream.flush()
            self._shown = False
