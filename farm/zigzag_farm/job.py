"""One job on a worker: a `zigzag render` or `zigzag merge` subprocess, made safe to run twice.

Dask runs a task at least once (a worker that dies holding a finished result makes the
scheduler run it again, and the dead worker's child may still be running), so:
- the child writes under a unique temporary name in the output's folder and the finished
  file is renamed over the final name (atomic on one file system; both runs write the same
  bytes, so whichever rename lands last changes nothing);
- the child runs in its own process group, killed as a group on timeout or cancellation,
  and dies with the worker thread that started it (PR_SET_PDEATHSIG), so a killed worker
  leaves no renderer running.

Standard library only, so a worker's environment needs nothing beyond Dask and this package.
"""
from __future__ import annotations

import ctypes
import errno
import fcntl
import hashlib
import json
import os
import signal
import socket
import stat
import subprocess
import sys
import time
import uuid

STDERR_TAIL = 4000  # bytes of a failed child's stderr kept for the report
# zigzag's usage errors (CLI11 parse errors: an unknown option, a value out of range, a
# missing argument) exit with 100-127. Run again they fail the same way: never retried.
USAGE_EXIT_CODES = range(100, 128)
KILL_GRACE_S = 3.0

try:
    _prctl = ctypes.CDLL(None, use_errno=True).prctl
except (OSError, AttributeError):  # not Linux: no parent-death signal, the timeout still holds
    _prctl = None
_PR_SET_PDEATHSIG = 1


class JobError(RuntimeError):
    """A child exited non-zero, timed out or was cancelled; the message carries its stderr."""


class UsageFailure(JobError):
    """The renderer refused its options: a retry would fail the same way."""


def _child_setup() -> None:
    # Runs in the child between fork and exec. setsid (start_new_session) gives it its own
    # process group; the parent-death signal ends it with the thread that waits on it.
    if _prctl is not None:
        _prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)


def _kill_group(proc: subprocess.Popen) -> None:
    for sig, wait in ((signal.SIGTERM, KILL_GRACE_S), (signal.SIGKILL, None)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            continue


def run_child(cmd: list[str], *, timeout: float | None, cancelled=lambda: False,
              poll_s: float = 0.5) -> tuple[int, str]:
    """Run cmd in its own process group -> (exit code, stderr tail). Raises JobError on
    timeout or cancellation, after killing the whole group."""
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, start_new_session=True,
                            preexec_fn=_child_setup)
    try:
        while True:
            try:
                _, err = proc.communicate(timeout=poll_s)
                return proc.returncode, err.decode(errors="replace")[-STDERR_TAIL:]
            except subprocess.TimeoutExpired:
                pass
            if timeout is not None and time.monotonic() - start > timeout:
                _kill_group(proc)
                raise JobError(f"timed out after {timeout:g} s (process group killed): {' '.join(cmd)}")
            if cancelled():
                _kill_group(proc)
                raise JobError(f"cancelled (process group killed): {' '.join(cmd)}")
    except BaseException:
        if proc.poll() is None:
            _kill_group(proc)
        raise


def plain_name(name: str) -> str:
    """name without '{' or '}': zigzag expands braces in -o/--stats as placeholders, with no
    escape, so a temporary named after `shot{camera}.png` would be written as `shot0...`.
    '%' is escaped too, so that two outputs' temporaries never share a form."""
    return name.replace("%", "%25").replace("{", "%7B").replace("}", "%7D")


def temporary_name(final: str, tag: str | None = None) -> str:
    """A unique sibling of `final` that keeps its extension (the renderer picks the format
    from it), starts with a dot (never mistaken for an output) and has no braces (plain_name).
    tag: the attempt's temporary_tag() (a new one if not given)."""
    folder, name = os.path.split(final)
    stem, ext = os.path.splitext(plain_name(name))
    return os.path.join(folder, f".{stem}.{tag or temporary_tag()}.tmp{ext}")


def _remove_attempt_files(folder: str, tag: str) -> None:
    """Every file of one attempt (its tag is unique): the job's temporaries and what the
    renderer may have left of its own temporaries of them (a killed or failed render)."""
    try:
        names = os.listdir(folder or ".")
    except OSError:
        return
    for name in names:
        if f".{tag}.tmp" in name:
            try:
                os.remove(os.path.join(folder, name))
            except OSError:
                pass


# The longest host part of a tag: a longer host name keeps its first bytes and a hash of
# the whole. With it a job temporary of the longest output name (plan.MAX_OUTPUT_NAME), and
# its stats, stay short enough that zigzag never cuts their own temporaries' names to fit
# 255 bytes: a cut loses the extension, and the cut stats temporary of shot.png could not be
# told from shot.exr's (both end ".json") when the two batches share a folder.
MAX_TAG_HOST = 20


def temporary_tag() -> str:
    """HOST-PID-UUID8 with no dot in it (a host name's dots become _), so that a temporary's
    name tells exactly which output it belongs to (runner.remove_stale_temporaries)."""
    host = socket.gethostname().replace(".", "_").replace("/", "_") or "host"
    if len(host.encode()) > MAX_TAG_HOST:
        digest = hashlib.sha256(host.encode()).hexdigest()[:8]
        host = host.encode()[:MAX_TAG_HOST - 9].decode(errors="ignore") + "_" + digest
    return f"{host}-{os.getpid()}-{uuid.uuid4().hex[:8]}"


def sha256_of(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def written_path(final: str) -> str:
    """Where writing `final` lands: a symbolic link's target (the link is kept), as zigzag
    render writes through one; `final` itself when it is no link."""
    return os.path.realpath(final) if os.path.islink(final) else final


def write_protected(path: str) -> bool:
    """As zigzag render decides it: an existing file the caller may not write; as root, one
    with no write bit at all. Such a file is refused, not replaced."""
    try:
        st = os.stat(path)
    except OSError:
        return False
    if not stat.S_ISREG(st.st_mode):
        return False
    if os.geteuid() == 0:
        return st.st_mode & 0o222 == 0
    return not os.access(path, os.W_OK)


def _temporary_beside(final: str) -> tuple[str, str]:
    """A fresh temporary beside the file `final` writes (a link's target: one file system for
    the rename), its folder made -> (temporary, the attempt's tag)."""
    target = written_path(final)
    os.makedirs(os.path.dirname(target) or ".", exist_ok=True)
    tag = temporary_tag()
    return temporary_name(target, tag), tag


def _publish_job_output(tmp: str, final: str) -> dict:
    """A job's finished image published over `final`, unless the user write-protected it:
    then refused, not replaced, as zigzag render refuses one (the rename needs only the
    folder's permission)."""
    if is_stream(final):  # refused before the run (cli); a rename would replace the device
        raise UsageFailure(f"{final}: a device or pipe, not a file: the farm renames its images into place")
    if write_protected(final):
        raise UsageFailure(f"{final}: the file is write-protected (make it writable to let the farm replace it)")
    return _publish(tmp, final)


def _publish(tmp: str, final: str) -> dict:
    """fsync the finished temporary file and rename it over the final name, with the replaced
    file's group and permission bits (not setuid/setgid/sticky), as zigzag render keeps them."""
    fd = os.open(tmp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    digest = sha256_of(tmp)
    size = os.path.getsize(tmp)
    target = written_path(final)
    _take_mode(tmp, target)
    os.replace(tmp, target)
    return {"output": final, "size": size, "sha256": digest}


def _take_mode(tmp: str, target: str) -> None:
    """A 0660 image stays 0660 and a 0600 one is never readable by others: the temporary
    takes the file it replaces' group (best effort: if ours to give) and mode bits."""
    try:
        old = os.stat(target)
    except FileNotFoundError:
        return
    if not stat.S_ISREG(old.st_mode):
        return
    try:
        os.chown(tmp, -1, old.st_gid)
    except OSError:
        pass
    os.chmod(tmp, stat.S_IMODE(old.st_mode) & 0o777)


def _refuse_write_protected(path: str) -> None:
    if write_protected(path):
        raise PermissionError(errno.EACCES, "the file is write-protected (make it writable to let the "
                                            "farm replace it)", path)


def write_json_atomically(path: str, data) -> dict | None:
    """JSON written whole to a temporary, fsynced and renamed over `path` (a failure keeps
    what was there and removes the temporary) -> the file as the manifest records it. A
    stream (a device, pipe, /dev/stdout) gets the bytes instead, as zigzag render writes one
    -> None: nothing on disk to record (a record no stream could prove would have it written
    again by every look at the frame). A write-protected file is refused (PermissionError)."""
    text = json.dumps(data, indent=2) + "\n"
    if is_stream(path):
        write_to_stream(path, text.encode())
        return None
    _refuse_write_protected(path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = temporary_name(os.path.abspath(written_path(path)))
    try:
        # 0600 until _publish gives it the replaced file's mode: never readable meanwhile.
        with os.fdopen(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL,
                               0o600 if os.path.isfile(path) else 0o666), "w") as fh:
            fh.write(text)
        return _publish(tmp, path)
    except BaseException:
        _remove(tmp)
        raise


# -- streams: as zigzag render writes them (core/atomic_file) ----------------------------

def own_descriptor(path: str) -> int | None:
    """The descriptor of this process that `path` names (/dev/stdout, /dev/stderr, /dev/fd/N,
    /proc/self/fd/N, /proc/PID/fd/N, or a link to one), if open for writing: written through,
    so that `>> log` appends and a pipe gets the bytes. Its file may be no path at all."""
    p = path
    for _ in range(40):  # the kernel's own limit of links
        name = os.path.normpath(os.path.abspath(p))
        fd = {"/dev/stdout": 1, "/dev/stderr": 2}.get(name)
        for folder in ("/dev/fd/", "/proc/self/fd/", f"/proc/{os.getpid()}/fd/"):
            rest = name[len(folder):]
            if fd is None and name.startswith(folder) and rest.isdigit() and len(rest) <= 9:
                fd = int(rest)
        if fd is not None:
            try:
                writable = fcntl.fcntl(fd, fcntl.F_GETFL) & os.O_ACCMODE != os.O_RDONLY
            except OSError:
                return None
            return fd if writable else None
        if not os.path.islink(p):
            return None
        try:
            to = os.readlink(p)
        except OSError:
            return None
        p = os.path.join(os.path.dirname(p), to)
    return None


def is_stream(path: str) -> bool:
    """A character device, FIFO or socket, or one of our descriptors: it takes the bytes;
    a rename would put a regular file in its place (as root even over /dev/null)."""
    if own_descriptor(path) is not None:
        return True
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode)


def write_to_stream(path: str, data: bytes) -> None:
    """data written into the stream `path`. A FIFO nobody reads fails (ENXIO) instead of
    hanging the run; a closed pipe fails too (Python ignores SIGPIPE: EPIPE)."""
    own = own_descriptor(path)
    if own is not None:
        for f in (sys.stdout, sys.stderr):  # what Python holds for it goes first
            try:
                f.flush()
            except (OSError, ValueError, AttributeError):
                pass
        _write_all(own, data, path)
        return
    try:
        fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as e:
        if e.errno == errno.ENXIO:
            raise OSError(errno.ENXIO, "no process is reading the pipe", path) from None
        raise
    try:
        # Blocking again: the writes then wait, as a shell's > does, while the reader catches up.
        fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) & ~os.O_NONBLOCK)
        _write_all(fd, data, path)
    finally:
        os.close(fd)


def _write_all(fd: int, data: bytes, path: str) -> None:
    view = memoryview(data)
    try:
        while view:
            view = view[os.write(fd, view):]
    except OSError as e:  # named: the report says which output failed
        raise OSError(e.errno, e.strerror, path) from None


def _remove(*paths: str) -> None:
    for p in paths:
        try:
            os.remove(p)
        except FileNotFoundError:
            pass


def _fail(code: int, stderr: str) -> JobError:
    reason = f"killed by signal {-code}" if code < 0 else f"exit code {code}"
    if code in USAGE_EXIT_CODES:
        return UsageFailure(f"zigzag refused its options ({reason}; not retried)\n{stderr.strip()}".strip())
    return JobError(f"zigzag {reason}\n{stderr.strip()}".strip())


def render(spec: dict, cancelled=lambda: False) -> dict:
    """Run one `zigzag render` job described by spec (see runner.render_spec)."""
    final = spec["output"]
    tmp, tag = _temporary_beside(final)
    tmp_stats = tmp + ".stats.json"
    cmd = [spec["zigzag"], "render", spec["scene"], "-o", tmp, "--stats", tmp_stats,
           "--camera", str(spec["camera"]), "-q"]
    if spec.get("frame") is not None:
        cmd += ["--frame", str(spec["frame"])]
    if spec.get("region"):
        cmd += ["--region", ",".join(str(v) for v in spec["region"])]
    cmd += list(spec.get("args", ()))
    start, started_at = time.monotonic(), time.time()
    try:
        code, err = run_child(cmd, timeout=spec.get("timeout"), cancelled=cancelled)
        if code != 0:
            raise _fail(code, err)
        if not os.path.exists(tmp):
            raise JobError(f"zigzag exited 0 but wrote no {tmp}\n{err.strip()}".strip())
        stats = None
        if os.path.exists(tmp_stats):
            with open(tmp_stats) as f:
                stats = json.load(f)
        result = _publish_job_output(tmp, final)
    finally:
        _remove(tmp, tmp_stats)
        _remove_attempt_files(os.path.dirname(tmp), tag)
    result.update(key=spec["key"], seconds=time.monotonic() - start, stats=stats,
                  started_at=started_at, finished_at=time.time(),
                  worker=f"{socket.gethostname()}:{os.getpid()}")
    return result


def merge(spec: dict, cancelled=lambda: False) -> dict:
    """`zigzag merge PARTS... -o OUTPUT` for one frame; the parts stay (the driver removes
    them once the frame is recorded, so a merge that runs twice still finds them)."""
    final = spec["output"]
    tmp, tag = _temporary_beside(final)
    cmd = [spec["zigzag"], "merge", *spec["parts"], "-o", tmp]
    start = time.monotonic()
    try:
        code, err = run_child(cmd, timeout=spec.get("timeout"), cancelled=cancelled)
        if code != 0:
            raise _fail(code, err)
        result = _publish_job_output(tmp, final)
    finally:
        _remove(tmp)
        _remove_attempt_files(os.path.dirname(tmp), tag)
    result.update(key=spec["key"], seconds=time.monotonic() - start,
                  worker=f"{socket.gethostname()}:{os.getpid()}")
    return result
