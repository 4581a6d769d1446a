"""The driver's side of a run without Dask: which temporaries it cleans, what it calls running."""
import os

from zigzag_farm import job
from zigzag_farm.plan import FrameJob, RenderJob
from zigzag_farm.plan import MAX_OUTPUT_NAME
from zigzag_farm.runner import Runner, RunSettings, _temporaries_of, remove_stale_temporaries, render_spec


def image_with_its_job_recorded(f, manifest):
    """f's image on disk and its render job (with stats) recorded, as an earlier run leaves them."""
    with open(f.output, "wb") as fh:
        fh.write(b"an image")
    manifest.record("r", "render", {"output": f.output, "size": 8, "sha256": job.sha256_of(f.output)},
                    stats={"pixels": 4, "rays": {"total": 4}}, seconds=1.0, worker="w")


def quiet_runner(f, manifest):
    from zigzag_farm.plan import Plan
    return Runner(Plan(frames=[f]), manifest, RunSettings(zigzag="zigzag"), progress_stream=open(os.devnull, "w"),
                  live=False)


def frame_job(folder):
    out = os.path.join(folder, "shot.png")
    part = RenderJob(key="r", scene="/s.json", scene_name="s", frame=None, camera=0, region=None,
                     output=out)
    return FrameJob(key="f", output=out, stats=os.path.join(folder, "shot.json"), scene_name="s",
                    frame=None, camera=0, parts=(part,), merged=False)


def test_stale_temporaries_are_exactly_this_outputs(workdir):
    tag = "node_7_example_org-4242-0123abcd"
    zz = "zz-99-c36ddd58c2531d1b"  # core/atomic_file's: PID, 64 random bits, then a serial
    ours = [os.path.basename(job.temporary_name(os.path.join(workdir, "shot.png"))),
            f".shot.{tag}.tmp.png", f".shot.{tag}.tmp.png.stats.json",       # the job's
            f"..shot.{tag}.tmp.{zz}-0.png", f"..shot.{tag}.tmp.png.stats.{zz}-1.json",  # zigzag's
            f".shot.{tag}.tmp.json", f"..shot.{tag}.tmp.zz-5-0123456789abcdef-3.json"]  # the stats file's
    others = ["shot.png", "shot.json", f".shot.v2.{tag}.tmp.png",          # shot.v2.png's
              f"..shot.v2.{tag}.tmp.{zz}-0.png", f".shotgun.{tag}.tmp.png",
              f".shot.{tag}.tmp.exr", ".shot.png.keep", f".shot.{tag}.tmp.png.bak",
              f"..shot.{tag}.tmp.zz-99-0.png"]                             # no random part: not zigzag's
    for name in ours + others:
        open(os.path.join(workdir, name), "w").close()
    remove_stale_temporaries(frame_job(workdir))
    assert sorted(os.listdir(workdir)) == sorted(others)


def zigzag_temporary(target: str, pid: int, token: str, serial: int, limit: int = 255) -> str:
    """core/atomic_file.cpp's temporary_name, for a name within `limit` bytes: ".STEM" then
    ".zz-PID-TOKEN-N.EXT", the stem cut and "~FNV1A32" put in its place when too long."""
    stem, ext = os.path.splitext(target)
    if target.startswith(".") and stem == "":
        stem, ext = target, ""
    suffix = f".zz-{pid}-{token}-{serial}{ext}"
    if 1 + len(stem.encode()) + len(suffix) > limit:
        h = 2166136261
        for c in target.encode():
            h = ((h ^ c) * 16777619) & 0xFFFFFFFF
        stem = stem.encode()[:limit - 1 - len(suffix) - 9].decode() + f"~{h:08x}"
    return "." + stem + suffix


def test_zigzag_never_cuts_the_temporaries_of_the_longest_names(workdir, monkeypatch):
    """zigzag cuts a temporary's name past 255 bytes, and the cut loses the extension: the
    cut stats temporaries of shot.png and shot.exr both end '.json', and one batch's cleanup
    deleted the other's live file (a review). The longest output name and the longest host
    name leave zigzag's temporaries whole, and the cleanup takes exactly those."""
    # The mirror agrees with the renderer's own test of its rule (tests/core/atomic_file_test.cpp).
    pinned = zigzag_temporary("a" * 245 + ".json", "99", "c36ddd58c2531d1b", 0)
    assert len(pinned) == 255 and pinned[:-len(".zz-99-c36ddd58c2531d1b-0.json")].endswith("a~ba5594dc")
    monkeypatch.setattr(job.socket, "gethostname", lambda: "node-" + "h" * 59)  # 64 bytes, the most there is
    monkeypatch.setattr(job.os, "getpid", lambda: 4194304)                      # Linux's largest PID
    for ext in (".png", ".exr", ".tiff"):
        stem = "x" * (MAX_OUTPUT_NAME - len(ext))
        out = os.path.join(workdir, stem + ext)
        theirs = os.path.basename(job.temporary_name(out))
        assert len(theirs) < 255
        ours = [theirs, theirs + ".stats.json",
                zigzag_temporary(theirs, "4194304", "c36ddd58c2531d1b", 999),
                zigzag_temporary(theirs + ".stats.json", "4194304", "c36ddd58c2531d1b", 999)]
        assert not any("~" in n for n in ours[2:]), ours  # not cut
        pattern = _temporaries_of(out)
        assert all(pattern.fullmatch(n) for n in ours), ours
        other = _temporaries_of(os.path.join(workdir, stem + (".jpg" if ext != ".jpg" else ".bmp")))
        assert not any(other.fullmatch(n) for n in ours), ours


def test_the_users_options_come_after_the_drivers():
    """A user's option left without its value at the end took the driver's --threads as its
    value (`-- --assets`: a folder named --threads, and 1 a second scene; review)."""
    j = RenderJob(key="r", scene="/s.json", scene_name="s", frame=None, camera=0, region=None,
                  output="/o.png", args=("--eps", "0.1"))
    spec = render_spec(j, RunSettings(zigzag="zigzag", runtime_args=("--threads", "2")))
    assert spec["args"] == ["--threads", "2", "--eps", "0.1"]


class FakeClient:
    def processing(self):
        return {"w1": ["a", "b", "c"], "w2": ["d"], "w3": [], "w4": ["e", "f", "g"]}

    def scheduler_info(self):
        return {"workers": {"w1": {"resources": {"render": 1}}, "w2": {"resources": {"render": 1}},
                            "w3": {"resources": {"render": 1}}, "w4": {"resources": {"render": 2}}}}


def test_running_counts_jobs_in_render_slots_not_jobs_queued_on_workers():
    pending = {"a", "b", "c", "d", "e", "f", "g"}
    assert Runner._running(FakeClient(), pending) == (1 + 1 + 0 + 2, 4)
    assert Runner._running(FakeClient(), {"b", "c"}) == (1, 4)


def test_workers_without_a_render_slot_or_no_answer_are_told_apart():
    class NoRenderSlots(FakeClient):
        def scheduler_info(self):
            return {"workers": {"w1": {"resources": {}}, "w2": {}}}

    class Gone(FakeClient):
        def processing(self):
            raise OSError("scheduler unreachable")

    assert Runner._running(NoRenderSlots(), {"a"})[1] == 0  # none: the run may give up
    assert Runner._running(Gone(), {"a"}) == (0, None)  # unknown: it waits on


def test_stats_that_cannot_be_written_fail_the_frame_without_a_traceback(workdir, monkeypatch):
    """A frame whose image is recorded and whose stats are asked for: when the stats cannot be
    written (a full disk), the frame is reported failed and the run goes on."""
    from zigzag_farm.manifest import Manifest

    f = frame_job(workdir)
    with Manifest(os.path.join(workdir, "manifest.jsonl")) as manifest:
        image_with_its_job_recorded(f, manifest)

        def full_disk(path, data):
            raise OSError(28, "No space left on device", path)

        monkeypatch.setattr(job, "write_json_atomically", full_disk)
        runner = quiet_runner(f, manifest)
        outcome = runner.run(client=None)  # nothing to submit: the image is there
    assert outcome.failed_frames == 1
    assert [x.key for x in outcome.failures] == ["f"]
    assert "No space left on device" in outcome.failures[0].message
    assert not os.path.exists(f.stats)


def test_stale_temporaries_of_an_output_named_with_braces_are_found(workdir):
    out = os.path.join(workdir, "shot{camera}.png")
    theirs = os.path.basename(job.temporary_name(out))
    names = [theirs, theirs + ".stats.json", zigzag_temporary(theirs, "7", "c36ddd58c2531d1b", 0)]
    for name in names + ["shot{camera}.png"]:
        open(os.path.join(workdir, name), "w").close()
    part = RenderJob(key="r", scene="/s.json", scene_name="s", frame=None, camera=0, region=None, output=out)
    remove_stale_temporaries(FrameJob(key="f", output=out, stats=None, scene_name="s", frame=None, camera=0,
                                      parts=(part,), merged=False))
    assert os.listdir(workdir) == ["shot{camera}.png"]


def test_a_write_protected_image_to_render_fails_before_any_job_is_submitted(workdir):
    """A frame whose image must be rendered but is write-protected would be refused at the
    end by its job, after the render (review: every region rendered, then the merge was
    refused): it fails at once, naming the file, and nothing is submitted."""
    from zigzag_farm.manifest import Manifest

    f = frame_job(workdir)
    with open(f.output, "wb") as fh:
        fh.write(b"an older image")
    os.chmod(f.output, 0o444)

    class NoSubmissions:
        def submit(self, *args, **kwargs):
            raise AssertionError("a job was submitted")

    with Manifest(os.path.join(workdir, "manifest.jsonl")) as manifest:
        runner = quiet_runner(f, manifest)
        outcome = runner.run(client=NoSubmissions())
    assert outcome.failed_frames == 1
    assert outcome.jobs_run == []
    assert "shot.png: the file is write-protected" in outcome.failures[0].message
    assert outcome.failures[0].what == "s camera 0"


def test_a_job_failed_by_worker_deaths_is_not_said_to_have_been_running():
    """Dask charges a worker's death to every job it holds, queued ones too (review: one kill
    failed frames that had never started, 'while running it')."""
    from distributed.scheduler import KilledWorker
    from zigzag_farm.runner import _failure_message

    message = _failure_message(KilledWorker("render-f7", None, 3))
    assert message == ("its worker died 4 time(s) while it ran or waited there "
                       "(distributed.scheduler.allowed-failures = 3); a re-run renders it")


def test_a_frame_completed_from_an_earlier_runs_job_is_not_counted_as_rendered(workdir):
    """Its job was recorded by an earlier run (whose stats write failed, or whose driver
    died): this run renders nothing for it (review: '20 rendered, 0 job(s) run'), and a user
    may have write-protected the finished image meanwhile."""
    from zigzag_farm.manifest import Manifest

    f = frame_job(workdir)
    with Manifest(os.path.join(workdir, "manifest.jsonl")) as manifest:
        image_with_its_job_recorded(f, manifest)
        os.chmod(f.output, 0o444)
        runner = quiet_runner(f, manifest)
        outcome = runner.run(client=None)
    assert (outcome.rendered, outcome.skipped, outcome.failed_frames, outcome.jobs_run) == (0, 1, 0, [])
    assert os.path.exists(f.stats)  # written from the recorded job's stats


def test_without_a_client_a_frame_that_has_a_job_after_all_fails_and_is_not_submitted(workdir):
    """run(None), when needs_cluster() saw no job (the recorded image, since deleted): the
    frame fails with a word to re-run, never an AttributeError on the missing client."""
    from zigzag_farm.manifest import Manifest

    f = frame_job(workdir)
    with Manifest(os.path.join(workdir, "manifest.jsonl")) as manifest:
        image_with_its_job_recorded(f, manifest)
        runner = quiet_runner(f, manifest)
        assert not runner.needs_cluster()
        os.remove(f.output)
        outcome = runner.run(None)
    assert outcome.failed_frames == 1 and outcome.jobs_run == []
    assert "changed while the run started; a re-run renders it" in outcome.failures[0].message
