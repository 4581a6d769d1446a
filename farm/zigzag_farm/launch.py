"""The driver's entry point (`zigzag-farm`, `python -m zigzag_farm`): a Ctrl-C while its
modules import (about 0.1 s, before cli.main handles it) ends the run as one during the run
does, one line and exit 130, not with an import's KeyboardInterrupt traceback."""
import os
import signal
import sys


def _interrupted_while_starting(signum, frame):
    sys.stderr.write("zigzag-farm: interrupted; nothing was started\n")
    sys.stderr.flush()
    os._exit(130)  # half-imported modules: nothing to clean up, nothing worth unwinding


def main() -> int:
    # Only Python's own handler is replaced: an ignored SIGINT (a background job) stays ignored.
    quiet = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    if quiet:
        signal.signal(signal.SIGINT, _interrupted_while_starting)
    from .cli import main as run
    if quiet:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    return run()
