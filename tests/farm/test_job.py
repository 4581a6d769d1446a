"""The worker side of a job, without Dask: process groups, timeouts, atomic outputs."""
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time

import psutil
import pytest

from conftest import FAKE_ZIGZAG, REAL_ZIGZAG, ROOT, fake_render, read, wait_for, write_scene
from zigzag_farm import job


def spec(scene, out, **kw):
    s = {"key": "k", "what": "test", "zigzag": FAKE_ZIGZAG, "scene": scene, "frame": 3,
         "camera": 0, "region": None, "output": out, "args": [], "timeout": 60}
    s.update(kw)
    return s


def test_output_appears_whole_and_twice_the_same(workdir):
    scene = write_scene(workdir, "s")
    out = os.path.join(workdir, "out", "s.png")
    r1 = job.render(spec(scene, out))
    first = read(out)
    r2 = job.render(spec(scene, out))
    assert read(out) == first == fake_render(scene, os.path.join(workdir, "ref.png"), "--frame", "3")
    assert r1["sha256"] == r2["sha256"] == job.sha256_of(out) and r1["size"] == len(first)
    assert r1["stats"]["rays"]["primary"] == 48 * 32
    assert os.listdir(os.path.dirname(out)) == ["s.png"]  # no temporary or stats file left


def test_an_output_that_is_a_link_writes_its_target(workdir):
    """As zigzag render does: the link is kept and its target, made if missing, gets the
    image (os.replace had put a plain file in the link's place)."""
    scene = write_scene(workdir, "s")
    os.makedirs(os.path.join(workdir, "shots"))
    out = os.path.join(workdir, "latest.png")
    os.symlink(os.path.join("shots", "v1.png"), out)
    result = job.render(spec(scene, out))
    assert os.path.islink(out)
    target = os.path.join(workdir, "shots", "v1.png")
    assert read(target) == fake_render(scene, os.path.join(workdir, "ref.png"), "--frame", "3")
    assert result["output"] == out and result["sha256"] == job.sha256_of(target)
    assert os.listdir(os.path.join(workdir, "shots")) == ["v1.png"]  # no temporary left


def test_a_write_protected_output_is_refused_and_kept(workdir):
    """As zigzag render: the rename needs only the folder's permission, so a finished frame
    the user made read-only was replaced. Refused instead, not retried (a usage failure)."""
    scene = write_scene(workdir, "s")
    out = os.path.join(workdir, "s.png")
    with open(out, "wb") as f:
        f.write(b"FINAL")
    os.chmod(out, 0o444)
    with pytest.raises(job.UsageFailure, match="write-protected"):
        job.render(spec(scene, out))
    assert read(out) == b"FINAL"
    assert sorted(os.listdir(workdir)) == ["s.json", "s.png"]
    assert job.write_protected(out) and not job.write_protected(os.path.join(workdir, "s.json"))


def test_a_failure_carries_stderr_and_keeps_the_old_output(workdir):
    scene = write_scene(workdir, "s", fail="no such material")
    out = os.path.join(workdir, "s.png")
    with open(out, "wb") as f:
        f.write(b"an earlier render")
    with pytest.raises(job.JobError, match="exit code 1(.|\n)*no such material"):
        job.render(spec(scene, out))
    assert read(out) == b"an earlier render"
    assert sorted(os.listdir(workdir)) == ["s.json", "s.png"]


def test_a_region_job_passes_the_region(workdir):
    scene = write_scene(workdir, "s")
    out = os.path.join(workdir, "part.exr")
    job.render(spec(scene, out, region=[8, 4, 40, 20]))
    assert read(out).startswith(b"FAKE 8 4 40 20 48 32\n")


GROUP_SCRIPT = "import subprocess, time; subprocess.Popen(['sleep', '60']); time.sleep(60)"


def group_members(pgid):
    out = []
    for p in psutil.process_iter(["pid"]):
        try:
            if os.getpgid(p.pid) == pgid:
                out.append(p.pid)
        except (ProcessLookupError, PermissionError):
            pass
    return out


@pytest.mark.parametrize("how", ["timeout", "cancel"])
def test_timeout_and_cancel_kill_the_whole_process_group(how):
    started = time.monotonic()
    seen = {}

    def cancelled():
        kids = psutil.Process().children()
        if kids:
            seen["pgid"] = os.getpgid(kids[0].pid)
            seen["members"] = group_members(seen["pgid"])
        return how == "cancel" and len(seen.get("members", [])) >= 2

    with pytest.raises(job.JobError, match="timed out" if how == "timeout" else "cancelled"):
        job.run_child([sys.executable, "-c", GROUP_SCRIPT], timeout=5.0 if how == "timeout" else 30,
                      cancelled=cancelled, poll_s=0.1)
    assert time.monotonic() - started < 15
    assert len(seen["members"]) >= 2  # the child and its grandchild shared the group
    assert seen["pgid"] != os.getpgid(0)  # ... which is not ours
    wait_for(lambda: not group_members(seen["pgid"]), 5, "the process group to be gone")


def test_a_killed_worker_takes_its_renderer_along(workdir):
    """The renderer dies with the thread waiting on it (PR_SET_PDEATHSIG), so a SIGKILLed
    worker leaves nothing running."""
    pidfile = os.path.join(workdir, "pid")
    worker = textwrap.dedent(f"""
        import sys, threading
        sys.path.insert(0, {os.path.dirname(job.__file__)!r} + "/..")
        from zigzag_farm import job
        cmd = [sys.executable, "-c", "import os, time; open({pidfile!r}, 'w').write(str(os.getpid())); time.sleep(60)"]
        t = threading.Thread(target=job.run_child, args=(cmd,), kwargs={{"timeout": None}})
        t.start(); t.join()
    """)
    w = subprocess.Popen([sys.executable, "-c", worker])
    try:
        wait_for(lambda: os.path.exists(pidfile) and open(pidfile).read(), 20, "the renderer to start")
        child = psutil.Process(int(open(pidfile).read()))
        assert child.is_running()
        w.send_signal(signal.SIGKILL)
        w.wait(10)
        wait_for(lambda: not child.is_running() or child.status() == psutil.STATUS_ZOMBIE, 10,
                 "the renderer to die with its worker")
    finally:
        if w.poll() is None:
            w.kill()


def test_temporary_names_keep_the_extension_and_hide():
    t = job.temporary_name("/a/b/frame_0001.exr")
    assert t.startswith("/a/b/.frame_0001.") and t.endswith(".tmp.exr")
    assert job.temporary_name("/a/b/frame_0001.exr") != t


def test_temporary_names_have_no_braces():
    """zigzag expands braces in -o/--stats as placeholders and has no escape."""
    t = os.path.basename(job.temporary_name("/a/shot{camera}%7B.png"))
    assert "{" not in t and "}" not in t and t.startswith(".shot%7Bcamera%7D%257B.") and t.endswith(".tmp.png")


@pytest.mark.parametrize("renderer", ["fake", "real"])
def test_a_scene_and_output_named_with_braces_are_written_as_named(workdir, renderer):
    """A scene `shot{camera}.json` rendered to `{scene}.png`: the job's temporary was named after
    it, the renderer expanded its braces and wrote `.shot0....tmp.png`, so every attempt failed
    ("exited 0 but wrote no ...") and left that file and its stats behind (review)."""
    if renderer == "real":
        if not os.access(REAL_ZIGZAG, os.X_OK):
            pytest.skip(f"no {REAL_ZIGZAG}")
        for name in ("default.gltf", "default.bin"):
            shutil.copy(os.path.join(ROOT, "scenes", name), workdir)
        scene = os.path.join(workdir, "shot{camera}.json")
        shutil.copy(os.path.join(ROOT, "scenes", "default.json"), scene)
        s = spec(scene, "", zigzag=REAL_ZIGZAG, frame=None, args=["--width", "16"])
    else:
        scene = write_scene(workdir, "shot{camera}")
        s = spec(scene, "")
    out = os.path.join(workdir, "out", "shot{camera}.png")
    s["output"] = out
    r = job.render(s)
    assert r["stats"] is not None and r["sha256"] == job.sha256_of(out)
    assert os.listdir(os.path.dirname(out)) == ["shot{camera}.png"]


def test_what_a_failed_attempt_wrote_is_removed(workdir):
    """A renderer that fails after writing its output and a temporary of its own (as zigzag's
    atomic files name them): nothing of the attempt stays beside the output."""
    fake = os.path.join(workdir, "zigzag")
    with open(fake, "w") as f:
        f.write(textwrap.dedent("""\
            #!/bin/sh
            while [ $# -gt 0 ]; do [ "$1" = -o ] && out="$2"; shift; done
            dir=$(dirname "$out"); base=$(basename "$out" .png)
            echo part > "$dir/.$base.zz-77-0123456789abcdef-0.png"
            echo torn > "$out"; echo torn > "$out.stats.json"
            echo "zigzag: error: out of memory" >&2; exit 1
            """))
    os.chmod(fake, 0o755)
    out = os.path.join(workdir, "out", "f.png")
    with pytest.raises(job.JobError, match="out of memory"):
        job.render(spec(write_scene(workdir, "s"), out, zigzag=fake))
    assert os.listdir(os.path.dirname(out)) == []


# -- streams and the replaced files' modes, as zigzag render writes them (core/atomic_file) --

def write_json_in_child(path, stdout):
    """job.write_json_atomically(path) in a child whose standard output is `stdout`."""
    code = f"from zigzag_farm import job; job.write_json_atomically({path!r}, {{'a': 1}})"
    return subprocess.run([sys.executable, "-c", code], stdout=stdout, stderr=subprocess.PIPE,
                          env={**os.environ, "PYTHONPATH": os.path.join(ROOT, "farm")}, timeout=60)


def test_json_into_dev_stdout_appends_to_a_log_and_reaches_a_pipe(workdir):
    """A rename over /dev/stdout replaced the file `>> log` appends to (review: the log's
    earlier lines lost), and through a pipe failed with FileNotFoundError."""
    log = os.path.join(workdir, "log.txt")
    with open(log, "w") as f:
        f.write("earlier line\n")
    with open(log, "a") as f:
        p = write_json_in_child("/dev/stdout", f)
    assert p.returncode == 0, p.stderr
    assert read(log) == b'earlier line\n{\n  "a": 1\n}\n'
    p = write_json_in_child("/dev/stdout", subprocess.PIPE)
    assert p.returncode == 0 and p.stdout == b'{\n  "a": 1\n}\n', p.stderr


def test_json_into_a_fifo_is_written_into_it_and_one_nobody_reads_fails_at_once(workdir):
    fifo = os.path.join(workdir, "stats.json")
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="no process is reading the pipe"):
        job.write_json_atomically(fifo, {"a": 1})
    reader = subprocess.Popen(["cat", fifo], stdout=subprocess.PIPE)
    try:
        wait_for(lambda: any(fifo in " ".join(p.cmdline()) for p in psutil.Process().children()), 10, "reader")
        time.sleep(0.2)  # cat opens the FIFO just after it starts
        job.write_json_atomically(fifo, {"a": 1})
    finally:
        out, _ = reader.communicate(timeout=10)
    assert out == b'{\n  "a": 1\n}\n'
    assert os.listdir(workdir) == ["stats.json"] and os.path.exists(fifo) and not os.path.isfile(fifo)


@pytest.mark.skipif(os.geteuid() != 0, reason="mknod needs root")
def test_json_into_a_character_device_keeps_the_device(workdir):
    """As root, --stats /dev/null replaced the system's /dev/null with a file: here a copy."""
    null = os.path.join(workdir, "null")
    os.mknod(null, 0o666 | __import__("stat").S_IFCHR, os.makedev(1, 3))
    job.write_json_atomically(null, {"a": 1})
    assert __import__("stat").S_ISCHR(os.stat(null).st_mode) and os.listdir(workdir) == ["null"]


def test_a_write_protected_json_is_refused_and_kept(workdir):
    path = os.path.join(workdir, "s.json")
    with open(path, "w") as f:
        f.write("MINE")
    os.chmod(path, 0o444)
    with pytest.raises(PermissionError, match="write-protected"):
        job.write_json_atomically(path, {"a": 1})
    assert read(path) == b"MINE" and os.listdir(workdir) == ["s.json"]


@pytest.mark.parametrize("mode", [0o660, 0o600, 0o444 | 0o200])
def test_replaced_images_and_json_keep_their_mode(workdir, mode):
    """os.replace gave every replaced file the temporary's 0644 (a 0600 image became
    readable by all); zigzag render keeps the mode bits, never setuid/setgid/sticky."""
    scene = write_scene(workdir, "s")
    out, stats = os.path.join(workdir, "s.png"), os.path.join(workdir, "s.stats.json")
    for path in (out, stats):
        with open(path, "w") as f:
            f.write("OLD")
        os.chmod(path, mode | 0o4000)  # setuid: dropped
    job.render(spec(scene, out))
    job.write_json_atomically(stats, {"a": 1})
    for path in (out, stats):
        assert oct(os.stat(path).st_mode & 0o7777) == oct(mode), path
    assert read(out) != b"OLD" and read(stats) != b"OLD"
