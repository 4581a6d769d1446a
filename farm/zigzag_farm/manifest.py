"""The batch manifest: what finished, so a re-run after the driver died renders only the rest.

An append-only JSON-lines file, one record per finished render job or frame, flushed and
fsynced as each arrives; a record torn by a crash mid-write is ignored on reading. A record
alone proves nothing: a job counts as done only while its output still exists with the
recorded size and SHA-256 (an output deleted, truncated or re-rendered with other settings
since is rendered again), and so do the other files recorded with it ("also": a frame's
stats file).
"""
from __future__ import annotations

import fcntl
import json
import os

from .job import sha256_of


class ManifestBusy(RuntimeError):
    pass


class ManifestUnwritable(RuntimeError):
    """A finished job could not be recorded (a full disk): the run stops, since nothing it
    finishes from then on would count as done."""


def verified(record: dict | None, image_only: bool = False, hashed: dict | None = None) -> bool:
    """The record's output (and, unless image_only, each file in its "also") is on disk,
    complete, and the same bytes as when recorded. `hashed` remembers each file's SHA-256
    under its identity on disk (size, inode, mtime, ctime), so that a re-run over large
    finished EXRs reads each once, however often it asks."""
    if not record:
        return False
    if not image_only and not all(verified(other, hashed=hashed) for other in record.get("also", ())):
        return False
    path = record.get("output")
    try:
        st = os.stat(path) if path else None
        if st is None or st.st_size != record.get("size"):
            return False
        identity = (path, st.st_size, st.st_ino, st.st_mtime_ns, st.st_ctime_ns)
        if hashed is None:
            return sha256_of(path) == record.get("sha256")
        if identity not in hashed:
            hashed[identity] = sha256_of(path)
        return hashed[identity] == record.get("sha256")
    except OSError:
        return False


def _file_record(record) -> bool:
    """{"output": path, "size": bytes, "sha256": hex, ...}: what verified() reads."""
    return (isinstance(record, dict) and isinstance(record.get("output"), str)
            and type(record.get("size")) is int and isinstance(record.get("sha256"), str))


def well_formed(record) -> bool:
    """A record as Manifest.record writes it, in the shapes the driver reads: anything else
    (a hand-edited or damaged line) counts as no record, not as a crash of every re-run."""
    optional = {"also": list, "stats": dict, "stats_file": str, "seconds": (int, float), "worker": str}
    return (_file_record(record) and isinstance(record.get("key"), str)
            and all(record.get(k) is None or isinstance(record[k], t) for k, t in optional.items())
            and all(_file_record(other) for other in record.get("also") or ()))


class Manifest:
    def __init__(self, path: str):
        self.path = path
        self.records: dict[str, dict] = {}
        self._hashed: dict[tuple, str] = {}  # verified()'s memo for this run
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        # Binary: records are written as encoded bytes (record), and a line of bytes that are
        # no UTF-8 (a damaged disk) must cost that line only, not the decoding of the file.
        self._file = open(path, "a+b")
        try:
            fcntl.flock(self._file, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self._file.close()
            # One manifest per output folder: the other run may be this batch or another
            # one writing into the same folder.
            raise ManifestBusy(f"{path}: another zigzag-farm run is using this manifest: wait for it "
                               "if it renders the same images (two runs of one batch would render "
                               "and merge the same parts); a batch of other images writing into the "
                               "same output folder can take its own --manifest FILE") from None
        self._file.seek(0)
        data = self._file.read()
        # A tail torn by a crash ends without a newline: the next record starts a fresh line.
        self._torn = bool(data) and not data.endswith(b"\n")
        # Lines that are no records (bytes that are no UTF-8, wrong shapes) are skipped as a
        # torn line is: their jobs are rendered again. Counted for one warning (the driver's);
        # a line torn by a crash is no news and is not.
        self.skipped = 0
        for line in data.split(b"\n"):
            try:
                record = json.loads(line.decode("utf-8"))  # as written (json guesses UTF-16 from bytes)
            except UnicodeDecodeError:
                record = None
            except json.JSONDecodeError:
                continue  # a line torn by a crash
            if well_formed(record):
                self.records[record["key"]] = record
            else:
                self.skipped += 1

    def done(self, key: str, image_only: bool = False) -> bool:
        return verified(self.records.get(key), image_only, self._hashed)

    def get(self, key: str) -> dict | None:
        return self.records.get(key)

    def record(self, key: str, kind: str, result: dict, **extra) -> None:
        rec = {"key": key, "kind": kind, "output": result["output"], "size": result["size"],
               "sha256": result["sha256"], **extra}
        try:
            # Unbuffered (the file is opened to append): a line that fails leaves nothing
            # behind in a buffer for close() to fail on again.
            data = (("\n" if self._torn else "") + json.dumps(rec, sort_keys=True) + "\n").encode()
            while data:
                data = data[os.write(self._file.fileno(), data):]
            os.fsync(self._file.fileno())
        except OSError as e:
            self._torn = True  # a part of the line may have reached the file
            raise ManifestUnwritable(f"cannot record finished jobs in the manifest {self.path}: "
                                     f"{e.strerror or e}") from None
        self._torn = False
        self.records[key] = rec

    def close(self) -> None:
        if not self._file.closed:
            fcntl.flock(self._file, fcntl.LOCK_UN)
            self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
