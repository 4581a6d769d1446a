"""The manifest: a record counts only while its output is on disk, complete and unchanged."""
import json
import os

import pytest

from zigzag_farm.job import sha256_of
from zigzag_farm.manifest import Manifest, ManifestBusy


def output(folder, name, data):
    path = os.path.join(folder, name)
    with open(path, "wb") as f:
        f.write(data)
    return {"output": path, "size": len(data), "sha256": sha256_of(path)}


def test_records_survive_a_reopen(workdir):
    m_path = os.path.join(workdir, "m.jsonl")
    a = output(workdir, "a.png", b"a" * 100)
    with Manifest(m_path) as m:
        m.record("ka", "frame", a, stats_file=None)
        assert m.done("ka") and not m.done("kb")
    with Manifest(m_path) as m:
        assert m.done("ka") and m.get("ka")["kind"] == "frame"


@pytest.mark.parametrize("damage", ["delete", "truncate", "same_size_other_bytes"])
def test_a_damaged_output_is_not_done(workdir, damage):
    m_path = os.path.join(workdir, "m.jsonl")
    a = output(workdir, "a.png", b"abcdef" * 50)
    with Manifest(m_path) as m:
        m.record("ka", "frame", a)
    if damage == "delete":
        os.remove(a["output"])
    elif damage == "truncate":
        with open(a["output"], "r+b") as f:
            f.truncate(10)
    else:
        with open(a["output"], "r+b") as f:
            f.write(b"X")
    with Manifest(m_path) as m:
        assert not m.done("ka")


def test_a_torn_last_line_is_ignored_and_the_next_record_starts_fresh(workdir):
    m_path = os.path.join(workdir, "m.jsonl")
    a = output(workdir, "a.png", b"a")
    b = output(workdir, "b.png", b"b")
    with Manifest(m_path) as m:
        m.record("ka", "frame", a)
    with open(m_path, "a") as f:
        f.write('{"key": "kb", "kind": "fra')  # the driver died mid-write
    with Manifest(m_path) as m:
        assert m.done("ka") and m.get("kb") is None
        m.record("kb", "frame", b)
    with Manifest(m_path) as m:
        assert m.done("ka") and m.done("kb")
    lines = open(m_path).read().splitlines()
    assert json.loads(lines[-1])["key"] == "kb"


@pytest.mark.parametrize("bad", [
    b"\xff\xfe garbage from a damaged disk",
    b'{"key": "kb", "kind": "frame", "output": "\xff.png", "size": 1, "sha256": "x"}',
    b'{"key": "kb", "kind": "frame", "output": "b.png", "size": 1, "sha256": "x", "also": "x"}',
    b'{"key": "kb", "kind": "frame", "output": "b.png", "size": 1, "sha256": "x", "also": [5]}',
    b'{"key": ["kb"], "kind": "frame", "output": "b.png", "size": 1, "sha256": "x"}',
    b'{"key": "kb", "kind": "frame", "output": 7, "size": "1", "sha256": null}',
    b'{"key": "kb", "kind": "frame", "output": "b.png", "size": 1, "sha256": "x", "stats": [1]}',
    b'[1, 2]',
])
def test_a_damaged_record_is_skipped_and_counted_not_a_crash_of_every_run(workdir, bad):
    """Such a line made every later run exit 1 with an internal error (a strict decode of the
    file, verified() taking "also" as a list of dicts, a list as a dict key)."""
    m_path = os.path.join(workdir, "m.jsonl")
    a = output(workdir, "a.png", b"a")
    b = output(workdir, "b.png", b"b")
    with Manifest(m_path) as m:
        m.record("ka", "frame", a)
    with open(m_path, "ab") as f:
        f.write(bad + b"\n")
    with Manifest(m_path) as m:
        assert m.done("ka") and not m.done("kb")
        assert m.skipped == 1  # for the driver's one warning line
        m.record("kb", "frame", b)
    with Manifest(m_path) as m:
        assert m.done("ka") and m.done("kb") and m.skipped == 1


def test_a_torn_line_is_not_counted_as_damaged(workdir):
    m_path = os.path.join(workdir, "m.jsonl")
    with open(m_path, "w") as f:
        f.write('{"key": "kb", "kind": "fra\n{"key": "kc"')
    with Manifest(m_path) as m:
        assert m.skipped == 0 and m.records == {}


def test_one_driver_per_manifest(workdir):
    m_path = os.path.join(workdir, "m.jsonl")
    with Manifest(m_path):
        # Not necessarily the same batch: any run writing into the same output folder. The
        # same batch must wait (its own manifest made two runs merge and delete the same
        # parts: review); only a batch of other images may take a manifest of its own.
        with pytest.raises(ManifestBusy, match="wait for it if it renders the same images") as busy:
            Manifest(m_path)
        assert "a batch of other images writing into the same output folder can take its own --manifest" \
            in str(busy.value)
    Manifest(m_path).close()  # free again once the first is closed


def test_a_record_counts_only_with_its_other_files(workdir):
    m_path = os.path.join(workdir, "m.jsonl")
    image = output(workdir, "a.png", b"image")
    stats = output(workdir, "a.json", b"{}")
    with Manifest(m_path) as m:
        m.record("ka", "frame", image, also=[stats])
    os.remove(stats["output"])
    with Manifest(m_path) as m:
        assert not m.done("ka") and m.done("ka", image_only=True)


def test_each_output_is_read_once_per_run_however_often_it_is_asked(workdir, monkeypatch):
    """A re-run asks about every finished image several times (pending, stats, the frame's
    own check); each is hashed once, and again only once its bytes on disk changed."""
    from zigzag_farm import manifest as manifest_module

    m_path = os.path.join(workdir, "m.jsonl")
    a = output(workdir, "a.exr", b"pixels" * 1000)
    reads = []
    monkeypatch.setattr(manifest_module, "sha256_of", lambda p: reads.append(p) or sha256_of(p))
    with Manifest(m_path) as m:
        m.record("ka", "frame", a)
        assert all(m.done("ka") for _ in range(4)) and m.done("ka", image_only=True)
        assert reads == [a["output"]]
        with open(a["output"], "r+b") as f:  # same size, other bytes, newer mtime/ctime
            f.write(b"X")
        os.utime(a["output"], ns=(1, 1))  # a changed identity on disk (a write within one clock tick
        # of the hash keeps it: the farm replaces outputs by rename, a new inode, never in place)
        assert not m.done("ka")
        assert len(reads) == 2


def test_a_record_that_cannot_be_written_stops_the_run_naming_the_manifest(workdir, monkeypatch):
    """A full disk under the manifest: each job used to fail with a bare OSError, and the run
    ended saying finished jobs were recorded when none was (review)."""
    from zigzag_farm.manifest import ManifestUnwritable

    m_path = os.path.join(workdir, "m.jsonl")
    with Manifest(m_path) as m:
        def full(*args):
            raise OSError(28, "No space left on device")

        for call in ("write", "fsync"):  # the line itself, or its sync
            with monkeypatch.context() as patch:
                patch.setattr(os, call, full)
                with pytest.raises(ManifestUnwritable, match=f"cannot record finished jobs in the manifest {m_path}: "
                                                             "No space left on device"):
                    m.record("k", "render", {"output": "x.png", "size": 1, "sha256": "00"})
            assert "k" not in m.records  # not done: a re-run renders it
    # Closed without a second error (a buffered line used to fail again at close, and that
    # OSError replaced the message).
