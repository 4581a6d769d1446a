"""Shared fixtures of the farm driver's tests: the fake and real renderers, scenes, and a
way to run the driver as the user does (a subprocess), plus process-tree inspection."""
import json
import os
import subprocess
import sys
import threading
import time

import psutil
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
FAKE_ZIGZAG = os.path.join(HERE, "fake_zigzag.py")
REAL_ZIGZAG = os.environ.get("ZIGZAG_BIN", os.path.join(ROOT, "build", "zigzag"))
SMALL = ["--width", "128", "--height", "128"]


def farm_env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(ROOT, "farm") + os.pathsep + env.get("PYTHONPATH", "")
    return env


def farm_cmd(*args):
    return [sys.executable, "-m", "zigzag_farm", "render", "-q", *args]


class LoopbackWatch:
    """Samples, while a driver runs, the listening sockets of its process tree (its scheduler,
    workers, nannies and dashboards): every one must be on 127.0.0.1. The autouse fixture
    below asserts it for every driver a test starts."""
    active: list["LoopbackWatch"] = []

    def __init__(self, proc, every_s=0.3):
        self.proc, self.every_s = proc, every_s
        self.seen: set[tuple[int, str, int]] = set()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()
        LoopbackWatch.active.append(self)

    def _run(self):
        while True:
            running = self.proc.poll() is None
            socks = listening_sockets(process_tree(self.proc.pid))
            self.seen |= {(c.pid, c.laddr.ip, c.laddr.port) for c in socks}
            if not running:
                return
            time.sleep(self.every_s)

    def elsewhere(self):
        self.thread.join(timeout=30)
        return sorted(s for s in self.seen if s[1] != "127.0.0.1")


@pytest.fixture(autouse=True)
def every_driver_listens_on_loopback_only():
    LoopbackWatch.active.clear()
    yield
    for watch in LoopbackWatch.active:
        if watch.proc.poll() is None:  # a test that failed early left it running
            watch.proc.kill()
            watch.proc.wait()
        assert watch.elsewhere() == [], f"listening beyond 127.0.0.1: {watch.elsewhere()}"
    LoopbackWatch.active.clear()


def run_farm(*args, timeout=180, env=None):
    """The driver as a user runs it -> CompletedProcess (text). env: more variables."""
    proc = start_farm(*args, env=env)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


def start_farm(*args, env=None):
    proc = subprocess.Popen(farm_cmd(*args), env={**farm_env(), **(env or {})}, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL)
    LoopbackWatch(proc)
    return proc


def write_scene(folder, name, **fields):
    scene = {"width": 48, "height": 32, "cameras": 1, **fields}
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def fake_render(scene, out, *extra):
    subprocess.run([FAKE_ZIGZAG, "render", scene, "-o", out, *extra], check=True)
    with open(out, "rb") as f:
        return f.read()


def read(path):
    with open(path, "rb") as f:
        return f.read()


def manifest_records(manifest, kind):
    """The manifest's records of one kind: "frame" (a finished image) or "render" (a job the
    driver collected)."""
    if not os.path.exists(manifest):
        return []
    out = []
    with open(manifest) as f:
        for line in f:
            try:
                r = json.loads(line)
            except ValueError:
                continue
            if r.get("kind") == kind:
                out.append(r)
    return out


def frame_records(manifest):
    return manifest_records(manifest, "frame")


def process_tree(pid):
    """The pids of a process and all its descendants."""
    return {pid} | {p.pid for p in descendants(pid)}


def descendants(pid):
    try:
        return psutil.Process(pid).children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def wait_for(predicate, timeout, what, poll=0.05):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(poll)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def renderer_children(pid):
    """The renderer processes (zigzag render) below the driver, with their parents (not the
    driver's own `zigzag render --dry-run` checks, which render nothing)."""
    out = []
    for p in descendants(pid):
        try:
            cmd = p.cmdline()
            if len(cmd) > 2 and "render" in cmd[1:3] and any("zigzag" in c for c in cmd[:2]) \
                    and "--dry-run" not in cmd:
                out.append((p, p.parent()))
        except psutil.Error:
            continue
    return out


def listening_sockets(pids):
    socks = []
    for c in psutil.net_connections(kind="inet"):
        if c.status == psutil.CONN_LISTEN and c.pid in pids:
            socks.append(c)
    return socks


def real_renderer_supports_farm():
    """True once the renderer has `info --json`, `--region` and `merge` (the renderer half of
    issue #14)."""
    if not os.access(REAL_ZIGZAG, os.X_OK):
        return False
    room = os.path.join(ROOT, "scenes", "room.json")
    p = subprocess.run([REAL_ZIGZAG, "info", room, "--json"], capture_output=True, text=True)
    try:
        json.loads(p.stdout)
    except ValueError:
        return False
    helps = subprocess.run([REAL_ZIGZAG, "render", "--help"], capture_output=True, text=True).stdout
    merge = subprocess.run([REAL_ZIGZAG, "merge", "--help"], capture_output=True, text=True).stdout
    return p.returncode == 0 and "--region" in helps and "merge" in merge.lower()


@pytest.fixture
def workdir(tmp_path):
    return str(tmp_path)
