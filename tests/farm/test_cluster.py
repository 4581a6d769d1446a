"""The driver end to end on LocalClusters, against the fake renderer (always) and the real
zigzag (once it has `info` and `merge`): regions, a worker killed mid-job, the driver killed
and re-run, a bad scene in the batch, and every listening socket on 127.0.0.1."""
import json
import os
import signal
import subprocess
import sys
import time

import psutil
import pytest

from conftest import (FAKE_ZIGZAG, REAL_ZIGZAG, ROOT, SMALL, LoopbackWatch, descendants, fake_render,
                      farm_cmd, farm_env, frame_records, listening_sockets, manifest_records,
                      process_tree, read, real_renderer_supports_farm, renderer_children, run_farm,
                      start_farm, wait_for, write_scene)


class Fake:
    name = "fake"
    zigzag = FAKE_ZIGZAG
    args: list = []

    def __init__(self, folder):
        self.folder = folder

    def still(self):
        return write_scene(self.folder, "room", width=96, height=64, sleep=0.7)

    def animated(self, sleep=1.0):
        return write_scene(self.folder, "animated", animated=True, frame_range=[1, 48], fps=24,
                           sleep=sleep)

    def failing(self):
        return write_scene(self.folder, "failing", fail="material 3 has no texture")


class Real:
    name = "real"
    zigzag = REAL_ZIGZAG
    args = list(SMALL)

    def __init__(self, folder):
        self.folder = folder

    def still(self):
        return os.path.join(ROOT, "scenes", "room.json")

    def animated(self, sleep=None):
        scene = os.path.join(ROOT, "scenes", "animated.json")
        helps = subprocess.run([self.zigzag, "render", "--help"], capture_output=True, text=True).stdout
        if not os.path.exists(scene) or "--frame" not in helps:
            pytest.skip("no scenes/animated.json or zigzag render --frame yet (issue #14, renderer half)")
        return scene

    def failing(self):
        return None


@pytest.fixture(params=["fake", "real"])
def renderer(request, tmp_path):
    if request.param == "real":
        if not real_renderer_supports_farm():
            pytest.skip(f"{REAL_ZIGZAG} has no `info`/`merge` yet (regions half of issue #14)")
        return Real(str(tmp_path))
    return Fake(str(tmp_path))


def reference(r, scene, out, *extra):
    """The same image rendered by one plain `zigzag render` process."""
    p = subprocess.run([r.zigzag, "render", scene, "-o", out, "-q", *r.args, *extra],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return read(out)


def farm(r, *args):
    extra = ["--", *r.args] if r.args else []
    return [*args, "--zigzag", r.zigzag, *extra]


def visible_files(folder):
    return sorted(f for f in os.listdir(folder) if not f.startswith("."))


def assert_loopback_only(pid, min_sockets):
    socks = listening_sockets(process_tree(pid))
    assert len(socks) >= min_sockets, socks
    assert all(s.laddr.ip == "127.0.0.1" for s in socks), [(s.pid, s.laddr) for s in socks]
    return socks


def test_regions_merge_bit_identical_on_three_workers_all_on_loopback(renderer, workdir):
    scene = renderer.still()
    out = os.path.join(workdir, "out")
    driver = start_farm(*farm(renderer, scene, "-o", f"{out}/{{scene}}.png", "--regions", "4",
                              "--workers", "3", "--stats", f"{out}/{{scene}}.json"))
    try:
        wait_for(lambda: renderer_children(driver.pid) or driver.poll() is not None, 120,
                 "a renderer to start")
        # Scheduler + its dashboard, and per worker its comm and dashboard and its nanny.
        socks = assert_loopback_only(driver.pid, min_sockets=2 + 3 * 3)
        _, err = driver.communicate(timeout=180)
    finally:
        if driver.poll() is None:
            driver.kill()
    assert driver.returncode == 0, err
    ref_stats = os.path.join(workdir, "ref.json")
    assert read(f"{out}/room.png") == reference(renderer, scene, os.path.join(workdir, "ref.png"),
                                                "--stats", ref_stats)
    stats = json.load(open(f"{out}/room.json"))
    # Each part traces its own level 1 (aa/corner_field.h): the corners at its seams (the
    # pixel corners there and the curvature ring) are traced by both parts, once by the whole
    # frame. Levels 2-3 are per pixel: the same rays. So the parts trace more camera rays than
    # the frame by those corners alone (plus each part's packet padding), and no fewer of any kind.
    # The fake renderer counts one ray per pixel: its parts add up exactly.
    full, parts = json.load(open(ref_stats))["rays"], stats["rays"]
    if renderer.name == "fake":
        assert parts == full
    else:
        regions = stats["farm"]["regions"]
        width, height = max(r[2] for r in regions), max(r[3] for r in regions)
        seams = sum((r[2] - r[0] + 3) * (r[3] - r[1] + 3) for r in regions) - (width + 3) * (height + 3)
        padding = sum((r[2] - r[0] + 4) + (r[3] - r[1] + 4) for r in regions)
        assert 0 < parts["primary"] - full["primary"] <= seams + padding, (parts, full, seams)
        assert all(parts[kind] >= full[kind] for kind in full), (parts, full)
    assert stats["farm"]["jobs"] == 4 and len(stats["farm"]["regions"]) == 4
    assert len(set(stats["farm"]["workers"])) >= 2  # the parts really were spread
    assert not os.path.exists(os.path.join(out, ".zigzag-farm-parts"))  # parts and folder removed
    assert visible_files(out) == ["room.json", "room.png"]
    assert len({s.pid for s in socks}) >= 4


def test_a_worker_killed_mid_job_loses_and_duplicates_nothing(renderer, workdir):
    scene = renderer.animated(sleep=0.5)
    out, log = os.path.join(workdir, "out"), os.path.join(workdir, "renders.log")
    driver = start_farm(*farm(renderer, scene, "-o", f"{out}/f{{frame:04}}.png", "--frames", "1-8",
                              "--workers", "2", "--summary", f"{workdir}/summary.json"),
                        env={"FAKE_ZIGZAG_LOG": log})

    def running_renderer():  # one still at work, not one that just finished
        for proc, parent in renderer_children(driver.pid):
            try:
                if proc.status() != psutil.STATUS_ZOMBIE:
                    return proc, parent
            except psutil.Error:
                continue
        return None

    try:
        renderer_proc, worker = wait_for(running_renderer, 120, "a renderer to start")
        if renderer.name == "fake":
            # The fake sleeps half-way through its output: kill it there, so the lost attempt
            # always leaves a half-written temporary behind. (The real zigzag writes its own
            # temporary and renames it at the very end: no window to aim at.)
            cmd = renderer_proc.cmdline()
            its_temporary = cmd[cmd.index("-o") + 1]
            wait_for(lambda: os.path.exists(its_temporary), 60, "the renderer to start writing")
        worker.send_signal(signal.SIGKILL)
        wait_for(lambda: not renderer_proc.is_running() or renderer_proc.status() == psutil.STATUS_ZOMBIE,
                 10, "the killed worker's renderer to die with it")
        _, err = driver.communicate(timeout=240)
    finally:
        if driver.poll() is None:
            driver.kill()
    assert driver.returncode == 0, err
    names = [f"f{n:04}.png" for n in range(1, 9)]
    assert visible_files(out) == names
    for n, name in enumerate(names, start=1):
        assert read(f"{out}/{name}") == reference(renderer, scene, f"{workdir}/ref.png", "--frame", str(n)), name
    records = frame_records(f"{out}/.zigzag-farm-manifest.jsonl")
    assert sorted(r["output"] for r in records) == [f"{out}/{n}" for n in names]  # each once
    assert [f for f in os.listdir(out) if ".tmp" in f] == []
    if renderer.name == "fake":  # the real zigzag keeps no log
        # 8 frames and the attempt lost with the worker, run again: a job really was lost.
        assert len(logged_renders(log)) >= 9, logged_renders(log)


def test_fake_a_worker_killed_after_finishing_jobs_renders_none_of_them_again(workdir):
    """Results the driver has recorded are released: a worker that dies holding them in memory
    costs only the job it was running (distributed re-runs any result still wanted)."""
    scene = write_scene(workdir, "animated", animated=True, frame_range=[1, 48], fps=24, sleep=0.6)
    out, log = os.path.join(workdir, "out"), os.path.join(workdir, "renders.log")
    manifest = f"{out}/.zigzag-farm-manifest.jsonl"
    driver = start_farm(*fake_farm(scene, "-o", f"{out}/f{{frame:04}}.png", "--frames", "1-10",
                                   "--workers", "2"), env={"FAKE_ZIGZAG_LOG": log})

    def a_worker_with_two_recorded_frames():
        by_worker = {}
        for r in manifest_records(manifest, "render"):
            by_worker.setdefault(r["worker"], []).append(r["output"])
        # The parents as listed: asking a renderer for its parent again races with its exit
        # (psutil.NoSuchProcess failed the test once, on a fresh clone).
        busy_parents = {parent.pid for _, parent in renderer_children(driver.pid) if parent is not None}
        for worker, outputs in by_worker.items():
            pid = int(worker.rsplit(":", 1)[1])
            if len(outputs) >= 2 and pid in busy_parents:  # and rendering another
                return pid, outputs
        return None

    try:
        pid, recorded = wait_for(a_worker_with_two_recorded_frames, 120, "a worker with two frames recorded")
        os.kill(pid, signal.SIGKILL)
        _, err = driver.communicate(timeout=240)
    finally:
        if driver.poll() is None:
            driver.kill()
    assert driver.returncode == 0, err
    assert visible_files(out) == [f"f{n:04}.png" for n in range(1, 11)]
    renders = logged_renders(log)
    for output in recorded:
        frame = str(int(os.path.basename(output)[1:5]))
        assert sum(1 for args in renders if args[args.index("--frame") + 1] == frame) == 1, (output, renders)
    assert len(renders) <= 10 + 1, renders  # the frames, and at most the attempt lost with the worker


def test_the_driver_killed_and_rerun_renders_only_what_is_missing(renderer, workdir):
    scene = renderer.animated(sleep=0.4)
    out = os.path.join(workdir, "out")
    manifest = f"{out}/.zigzag-farm-manifest.jsonl"
    args = farm(renderer, scene, "-o", f"{out}/f{{frame:04}}.png", "--frames", "1-8",
                "--workers", "1", "--summary", f"{workdir}/summary.json")
    driver = start_farm(*args)
    try:
        wait_for(lambda: len(frame_records(manifest)) >= 3 or driver.poll() is not None, 120,
                 "three frames to finish")
        tree = descendants(driver.pid)
        driver.send_signal(signal.SIGKILL)
        driver.wait(10)
    finally:
        if driver.poll() is None:
            driver.kill()
    assert driver.returncode == -signal.SIGKILL, "the driver finished before it could be killed"
    # The workers and their renderers end with the driver.
    wait_for(lambda: not any(p.is_running() and p.status() != psutil.STATUS_ZOMBIE for p in tree),
             20, "the killed driver's workers and renderers to exit")
    done_before = {r["key"] for r in frame_records(manifest)}
    assert 3 <= len(done_before) < 8

    p = run_farm(*args)
    assert p.returncode == 0, p.stderr
    summary = json.load(open(f"{workdir}/summary.json"))
    assert summary["skipped"] == len(done_before)
    assert summary["rendered"] == summary["jobs_run"] == 8 - len(done_before)
    assert visible_files(out) == [f"f{n:04}.png" for n in range(1, 9)]
    for n in range(1, 9):
        assert read(f"{out}/f{n:04}.png") == reference(renderer, scene, f"{workdir}/ref.png", "--frame", str(n))
    assert len(frame_records(manifest)) == 8

    again = run_farm(*args)  # everything verified on disk: nothing to run, no cluster
    assert again.returncode == 0, again.stderr
    assert json.load(open(f"{workdir}/summary.json"))["jobs_run"] == 0


def test_a_bad_scene_is_reported_and_the_others_complete(renderer, workdir):
    good = renderer.still()
    broken = os.path.join(workdir, "broken.json")
    with open(broken, "w") as f:
        f.write("{ this is not json")
    scenes = [good, broken] + ([renderer.failing()] if renderer.failing() else [])
    out = os.path.join(workdir, "out")
    p = run_farm(*farm(renderer, *scenes, "-o", f"{out}/{{scene}}.png", "--workers", "2",
                       "--retries", "1", "--summary", f"{workdir}/summary.json"))
    assert p.returncode == 1, p.stderr
    assert visible_files(out) == ["room.png"]
    assert read(f"{out}/room.png") == reference(renderer, good, f"{workdir}/ref.png")
    summary = json.load(open(f"{workdir}/summary.json"))
    failed = {f["what"].split()[0] for f in summary["failures"]}
    assert broken in failed
    assert "broken.json" in p.stderr
    if renderer.failing():
        assert "failing" in failed and "material 3 has no texture" in p.stderr
    assert summary["rendered"] == 1
    # A scene that does not load is no failed image: it has none in the plan.
    assert summary["failed_scenes"] == 1
    assert summary["failed_frames"] == (1 if renderer.failing() else 0)
    assert "1 scene(s) failed to load" in p.stderr


def test_fake_an_existing_scheduler_on_loopback(workdir):
    """--scheduler: a `dask scheduler` and a `dask worker` started as the README says (named
    test_fake_...: the fake renderer, so ctest's `-k fake` selection runs it)."""
    dask = os.path.join(os.path.dirname(sys.executable), "dask")
    sched_file = os.path.join(workdir, "scheduler.json")
    loopback = ["--host", "127.0.0.1", "--dashboard-address", "127.0.0.1:0"]
    procs = [subprocess.Popen([dask, "scheduler", "--port", "0", "--scheduler-file", sched_file, *loopback],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        wait_for(lambda: os.path.exists(sched_file) and os.path.getsize(sched_file) > 0, 60, "the scheduler")
        address = json.load(open(sched_file))["address"]
        fake = Fake(workdir)
        scene = fake.animated(sleep=0.1)
        out = os.path.join(workdir, "out")
        args = [scene, "-o", f"{out}/f{{frame}}.png", "--frames", "1-3", "--scheduler", address,
                "--zigzag", FAKE_ZIGZAG]
        lonely = run_farm(*args, "--wait", "2")
        assert lonely.returncode == 2 and "no Dask worker joined" in lonely.stderr, lonely.stderr
        procs.append(subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--resources", "render=1",
                                       *loopback], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        p = run_farm(*args)
        assert p.returncode == 0, p.stderr
        assert visible_files(out) == ["f1.png", "f2.png", "f3.png"]
        for proc in procs:  # scheduler, its dashboard, the worker, its dashboard, its nanny
            assert_loopback_only(proc.pid, min_sockets=2)

        # The only worker stops mid-batch (a walltime, a lost node) and none comes back: the
        # jobs left fail once --wait seconds pass without one, instead of waiting for ever.
        slow = write_scene(workdir, "slow", animated=True, frame_range=[1, 48], fps=24, sleep=3.0)
        driver = start_farm(slow, "-o", f"{workdir}/out2/f{{frame}}.png", "--frames", "1-4", "--scheduler",
                            address, "--zigzag", FAKE_ZIGZAG, "--wait", "3", "--summary",
                            f"{workdir}/summary.json")
        try:
            wait_for(lambda: renderer_children(procs[1].pid), 60, "a renderer on the worker")
            procs[1].terminate()
            procs[1].wait(30)
            _, err = driver.communicate(timeout=60)
        finally:
            if driver.poll() is None:
                driver.kill()
        assert driver.returncode == 1, err
        assert "no worker offering render=1 for 3 s" in err, err
        summary = summary_of(workdir)
        assert summary["failed_frames"] >= 3 and summary["rendered"] + summary["failed_frames"] == 4, summary
    finally:
        for proc in procs:
            proc.terminate()
        for proc in procs:
            try:
                proc.wait(20)
            except subprocess.TimeoutExpired:
                proc.kill()


# -- the fake renderer only: options, keys, outputs and signals (fast, one small cluster each) --

def fake_farm(*args):
    return [*args, "--zigzag", FAKE_ZIGZAG]


def summary_of(workdir):
    return json.load(open(f"{workdir}/summary.json"))


def logged_renders(log):
    return [json.loads(line) for line in open(log)] if os.path.exists(log) else []


def test_fake_keep_parts_keeps_the_parts(workdir):
    scene = write_scene(workdir, "still", width=40, height=30)
    out = os.path.join(workdir, "out")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--regions", "3", "--keep-parts"))
    assert p.returncode == 0, p.stderr
    parts = os.listdir(os.path.join(out, ".zigzag-farm-parts"))
    assert len(parts) == 3 and all(n.endswith(".exr") for n in parts)


def test_fake_parts_an_interrupted_run_left_with_other_regions_are_removed(workdir):
    """A frame stopped before its merge, run again with another --regions: the old parts
    (gigabytes for a large frame) go once the frame is written; another output's stay."""
    scene = write_scene(workdir, "still", width=40, height=30)
    out = os.path.join(workdir, "out")
    parts = os.path.join(out, ".zigzag-farm-parts")
    for name, regions in (("a", "4"), ("b", "3")):
        p = run_farm(*fake_farm(scene, "-o", f"{out}/{name}.png", "--regions", regions, "--keep-parts"))
        assert p.returncode == 0, p.stderr
    b_parts = sorted(n for n in os.listdir(parts) if "of3-" in n)
    assert len(os.listdir(parts)) == 7 and len(b_parts) == 3
    os.remove(f"{out}/a.png")  # as if its run had stopped before the merge
    p = run_farm(*fake_farm(scene, "-o", f"{out}/a.png", "--regions", "2"))
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(parts)) == b_parts
    assert read(f"{out}/a.png") == fake_render(scene, f"{workdir}/ref.png")
    os.remove(f"{out}/b.png")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/b.png"))  # now whole: its parts go, and the folder
    assert p.returncode == 0, p.stderr
    assert not os.path.exists(parts)


def test_fake_regions_split_each_cameras_own_size(workdir):
    """Two cameras of other aspects and only --width: each camera's frame follows its aspect."""
    scene = write_scene(workdir, "two", cameras=2, camera_aspects=[2.0, 0.5])
    out = os.path.join(workdir, "out")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/c{{camera}}.png", "--camera", "all", "--regions", "4",
                            "--width", "40", "--stats", f"{out}/c{{camera}}.json"))
    assert p.returncode == 0, p.stderr
    for camera, size in ((0, (40, 20)), (1, (40, 80))):
        ref = fake_render(scene, f"{workdir}/ref.png", "--camera", str(camera), "--width", "40")
        assert read(f"{out}/c{camera}.png") == ref
        stats = json.load(open(f"{out}/c{camera}.json"))
        assert stats["region"] == [0, 0, *size] and stats["pixels"] == size[0] * size[1]


def test_fake_a_camera_by_name_renders_that_camera(workdir):
    """--camera NAME as zigzag render takes it: {camera} is the index `zigzag info` gives."""
    scene = write_scene(workdir, "two", cameras=2, camera_names=["wide", "tall"], camera_aspects=[2.0, 0.5])
    out = os.path.join(workdir, "out")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/c{{camera}}.png", "--camera", "tall", "--width", "40"))
    assert p.returncode == 0, p.stderr
    assert visible_files(out) == ["c1.png"]
    assert read(f"{out}/c1.png") == fake_render(scene, f"{workdir}/ref.png", "--camera", "1", "--width", "40")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/c{{camera}}.png", "--camera", "side"))
    assert p.returncode == 2 and "no camera named 'side' (cameras: 0 'wide', 1 'tall')" in p.stderr, p.stderr


def test_fake_options_after_dashes_reach_info_and_render_in_either_form(workdir):
    """--assets for a scene that needs them (info too), and --width=/--threads= given once."""
    assets = os.path.join(workdir, "assets")
    os.makedirs(assets)
    open(os.path.join(assets, "car.glb"), "w").close()
    scene = write_scene(workdir, "car", needs_assets="car.glb")
    out, log = os.path.join(workdir, "out"), os.path.join(workdir, "renders.log")
    env = {"FAKE_ZIGZAG_LOG": log}
    p = run_farm(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--regions", "2"), "--",
                 f"--assets={assets}", "--width=40", "--threads=1", env=env)
    assert p.returncode == 0, p.stderr
    assert read(f"{out}/car.png") == fake_render(scene, f"{workdir}/ref.png", "--assets", assets,
                                                 "--width", "40")
    renders = logged_renders(log)
    assert len(renders) == 2  # the two regions (the reference render is not logged)
    for args in renders:
        assert sum(a.startswith("--width") for a in args) == 1
        assert sum(a.startswith("--threads") for a in args) == 1


def test_fake_other_worker_counts_and_threads_render_nothing_again(workdir):
    scene = write_scene(workdir, "anim", animated=True, frame_range=[1, 3])
    out, log = os.path.join(workdir, "out"), os.path.join(workdir, "renders.log")
    common = fake_farm(scene, "-o", f"{out}/f{{frame}}.png", "--summary", f"{workdir}/summary.json")
    p = run_farm(*common, "--workers", "1", env={"FAKE_ZIGZAG_LOG": log})
    assert p.returncode == 0, p.stderr
    assert len(logged_renders(log)) == 3
    assert all("--threads" in args for args in logged_renders(log))  # derived: cores / workers
    for again in (["--workers", "2"], ["--workers", "1", "--", "--threads=1"], ["--", "--threads", "2"]):
        p = run_farm(*common, *again, env={"FAKE_ZIGZAG_LOG": log})
        assert p.returncode == 0, p.stderr
        assert summary_of(workdir)["jobs_run"] == 0, again
    assert len(logged_renders(log)) == 3


def test_fake_edits_to_any_file_of_a_scene_render_it_again(workdir):
    texture = os.path.join(workdir, "wood.png")
    with open(texture, "w") as f:
        f.write("grain 1")
    scene = write_scene(workdir, "room", files=["wood.png"])
    other = write_scene(workdir, "other")
    out = os.path.join(workdir, "out")
    args = fake_farm(scene, other, "-o", f"{out}/{{scene}}.png", "--summary", f"{workdir}/summary.json")
    assert run_farm(*args).returncode == 0
    os.utime(texture)  # touched, the same bytes: nothing to do
    assert run_farm(*args).returncode == 0 and summary_of(workdir)["jobs_run"] == 0
    with open(texture, "w") as f:
        f.write("grain 2")  # the same size, other bytes
    p = run_farm(*args)
    assert p.returncode == 0, p.stderr
    assert summary_of(workdir)["jobs_run"] == 1 and summary_of(workdir)["skipped"] == 1
    assert read(f"{out}/room.png") == fake_render(scene, f"{workdir}/ref.png")


@pytest.mark.parametrize("regions", ["1", "2"])
def test_fake_stats_of_complete_frames_are_written_without_rendering(workdir, regions):
    scene = write_scene(workdir, "still")
    out = os.path.join(workdir, "out")
    args = fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--regions", regions,
                     "--summary", f"{workdir}/summary.json")
    assert run_farm(*args).returncode == 0
    image = read(f"{out}/still.png")
    for step in ("asked for later", "deleted"):
        p = run_farm(*args, "--stats", f"{out}/{{scene}}.json")
        assert p.returncode == 0, p.stderr
        assert summary_of(workdir)["jobs_run"] == 0, step
        stats = json.load(open(f"{out}/still.json"))
        assert stats["pixels"] == 48 * 32 and stats["farm"]["jobs"] == int(regions)
        os.remove(f"{out}/still.json")
    assert read(f"{out}/still.png") == image


def test_fake_no_cluster_is_started_when_no_job_is_left_to_run(workdir):
    """Frames an earlier run's recorded jobs complete (only their frame records lost) and a
    write-protected image: nothing for Dask, so no cluster (an unreachable scheduler would
    fail the run with a usage error)."""
    scene = write_scene(workdir, "anim", animated=True, frame_range=[0, 2])
    out = os.path.join(workdir, "out")
    args = fake_farm(scene, "-o", f"{out}/f{{frame}}.png", "--summary", f"{workdir}/summary.json",
                     "--scheduler", "tcp://127.0.0.1:9", "--wait", "1")
    assert run_farm(*fake_farm(scene, "-o", f"{out}/f{{frame}}.png")).returncode == 0
    manifest = f"{out}/.zigzag-farm-manifest.jsonl"
    records = [json.loads(line) for line in open(manifest)]
    with open(manifest, "w") as f:  # the driver died between the jobs' records and their frames'
        f.writelines(json.dumps(r) + "\n" for r in records if r["kind"] != "frame")
    with open(f"{out}/f2.png", "wb") as f:
        f.write(b"MINE")
    os.chmod(f"{out}/f2.png", 0o444)
    p = run_farm(*args)
    assert p.returncode == 1, p.stderr
    assert "f2.png: the file is write-protected" in p.stderr and "cannot reach" not in p.stderr, p.stderr
    assert summary_of(workdir)["jobs_run"] == 0 and summary_of(workdir)["skipped"] == 2
    assert read(f"{out}/f2.png") == b"MINE"
    os.chmod(f"{out}/f2.png", 0o644)
    p = run_farm(*args)  # f2 has a job now
    assert p.returncode == 2 and "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in p.stderr, p.stderr


def test_fake_a_usage_error_of_the_renderer_is_not_retried(workdir):
    """Options the renderer refuses once it has loaded the scene (its --dry-run before the
    cluster loads nothing, so they pass it): the job fails once, not retried."""
    scene = write_scene(workdir, "still", refuse="--aov geo needs the visibility map (--edges vulkan)")
    out, log = os.path.join(workdir, "out"), os.path.join(workdir, "renders.log")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--retries", "3"), "--", "--eps", "0.5",
                 env={"FAKE_ZIGZAG_LOG": log})
    assert p.returncode == 1
    assert "refused its options (exit code 105; not retried)" in p.stderr
    assert "--aov geo needs the visibility map" in p.stderr
    assert len(logged_renders(log)) == 1
    # Options refused as they are (a value out of range): by the --dry-run, before any job.
    p = run_farm(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--retries", "3"), "--", "--eps", "5",
                 env={"FAKE_ZIGZAG_LOG": log})
    assert p.returncode == 2
    assert "zigzag-farm: error: zigzag render refuses" in p.stderr and "--eps: Value 5 not in range" in p.stderr
    assert len(logged_renders(log)) == 1


def two_renderers(driver):
    wait_for(lambda: len(renderer_children(driver.pid)) >= 2 or driver.poll() is not None, 120,
             "two renderers to start")


def signalled(driver, send, until=None):
    """Once until() (if given) has waited for the moment, send() a signal: the driver's
    processes as they were then and its stderr once it exits (killed whatever fails)."""
    try:
        if until:
            until()
        tree = descendants(driver.pid)
        send()
        _, err = driver.communicate(timeout=60)
    finally:
        if driver.poll() is None:
            driver.kill()
    return tree, err


def own_group_driver(*args):
    """The driver as a terminal's foreground job: its own process group, SIGINT not ignored."""
    driver = subprocess.Popen(farm_cmd(*args), env=farm_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, stdin=subprocess.DEVNULL, start_new_session=True,
                              preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    LoopbackWatch(driver)  # its own process group, so not start_farm: still on loopback only
    return driver


def test_fake_ctrl_c_stops_everything_quietly(workdir):
    """A terminal's Ctrl-C: SIGINT to the driver's whole process group (its workers too)."""
    scene = write_scene(workdir, "anim", animated=True, frame_range=[1, 8], sleep=2.0)
    out = os.path.join(workdir, "out")
    driver = own_group_driver(*fake_farm(scene, "-o", f"{out}/f{{frame}}.png", "--workers", "2"))
    tree, err = signalled(driver, lambda: os.killpg(driver.pid, signal.SIGINT), until=lambda: two_renderers(driver))
    assert driver.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert "interrupted" in err
    wait_for(lambda: not any(p.is_running() and p.status() != psutil.STATUS_ZOMBIE for p in tree),
             20, "the workers and renderers to exit")


@pytest.mark.parametrize("after_s", [1.5, 3.0, 4.0])
def test_fake_ctrl_c_while_the_cluster_starts_is_quiet_too(workdir, after_s):
    """Workers ignored SIGINT only in dask_setup, after their imports: a Ctrl-C while they
    started printed 69-115 lines of KeyboardInterrupt tracebacks and "Nanny failed to start",
    and one during the driver's Dask imports or its LocalCluster's start a traceback of its
    own (review). Workers are spawned with SIGINT blocked; the driver imports Dask where it
    handles Ctrl-C and takes one during the start once the cluster can be closed."""
    # 4 s of renders on 2 workers: the batch outlasts the latest signal (with 2 s, a fast
    # start had finished it at 4.0 s, and the signal came as Python exited: -2).
    scene = write_scene(workdir, "anim", animated=True, frame_range=[0, 7], sleep=1.0)
    driver = own_group_driver(*fake_farm(scene, "-o", f"{workdir}/out/f{{frame:04}}.png", "--workers", "2"))

    def start_up():
        try:
            driver.wait(timeout=after_s)
        except subprocess.TimeoutExpired:
            pass
    tree, err = signalled(driver, lambda: os.killpg(driver.pid, signal.SIGINT), until=start_up)
    assert driver.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err and "Nanny" not in err, err
    assert err.strip().splitlines()[-1].startswith("zigzag-farm: interrupted"), err
    wait_for(lambda: not any(p.is_running() and p.status() != psutil.STATUS_ZOMBIE for p in tree),
             20, "the workers to exit")


def test_fake_sigterm_stops_everything_and_exits_143(workdir):
    """SIGTERM exited 130 "interrupted" (review): 143 (128 + 15) as zigzag render, cleaned up as on Ctrl-C."""
    scene = write_scene(workdir, "anim", animated=True, frame_range=[1, 8], sleep=2.0)
    driver = start_farm(*fake_farm(scene, "-o", f"{workdir}/out/f{{frame}}.png", "--workers", "2"))
    tree, err = signalled(driver, lambda: driver.send_signal(signal.SIGTERM), until=lambda: two_renderers(driver))
    assert driver.returncode == 143, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert "zigzag-farm: terminated (SIGTERM); finished jobs are recorded" in err
    wait_for(lambda: not any(p.is_running() and p.status() != psutil.STATUS_ZOMBIE for p in tree),
             20, "the workers and renderers to exit")


def test_fake_work_dir_removes_exactly_the_folders_the_run_made(workdir):
    """--work-dir DIR removed a DIR the user had made, and of wd/mine/sub/deeper only `deeper`,
    leaving the `sub` the farm made (review): now the folders the run made, deepest first, once
    empty, and never one that was there before."""
    scene = write_scene(workdir, "still", width=40, height=30)
    os.makedirs(f"{workdir}/myscratch")
    os.makedirs(f"{workdir}/wd3/mine")
    for i, work in enumerate(["myscratch", "wd3/mine/sub/deeper", "fresh/a/b"]):
        p = run_farm(*fake_farm(scene, "-o", f"{workdir}/out/{i}.png", "--regions", "2",
                                "--work-dir", f"{workdir}/{work}"))
        assert p.returncode == 0, p.stderr
    assert os.listdir(f"{workdir}/myscratch") == []
    assert os.listdir(f"{workdir}/wd3") == ["mine"] and os.listdir(f"{workdir}/wd3/mine") == []
    assert not os.path.exists(f"{workdir}/fresh")
    assert sorted(n for n in os.listdir(f"{workdir}/out") if not n.startswith(".")) == ["0.png", "1.png", "2.png"]


def test_fake_stats_into_dev_stdout_reach_a_pipe_and_a_log_unreplaced(workdir):
    """--stats /dev/stdout: renamed over, it replaced the file `>> log` appends to, and through
    a pipe every frame failed (FileNotFoundError). Written into, as zigzag render does."""
    scene = write_scene(workdir, "still")
    out = os.path.join(workdir, "out")
    p = run_farm(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--stats", "/dev/stdout"))
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["pixels"] == 48 * 32
    # Once: the frame is done (no record could prove a stream's bytes, so none is kept; one
    # that always failed had the stats written at each of the driver's looks at the frame).
    p = run_farm(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--stats", "/dev/stdout"))
    assert p.returncode == 0 and p.stdout == "" and "1 already complete" in p.stderr, p.stderr
    assert run_farm(*fake_farm(scene, "-o", f"{workdir}/later/{{scene}}.png")).returncode == 0
    p = run_farm(*fake_farm(scene, "-o", f"{workdir}/later/{{scene}}.png", "--stats", "/dev/stdout"))
    assert p.returncode == 0 and json.loads(p.stdout)["pixels"] == 48 * 32, p.stderr  # asked for later: once
    assert "0 rendered, 1 already complete" in p.stderr, p.stderr
    log = os.path.join(workdir, "log.txt")
    with open(log, "w") as f:
        f.write("earlier line\n")
    with open(log, "a") as f:
        code = subprocess.run(farm_cmd(*fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--stats", "/dev/stdout",
                                                  "--manifest", f"{workdir}/m.jsonl")),
                              env=farm_env(), stdout=f, stderr=subprocess.PIPE, timeout=180).returncode
    assert code == 0
    first, rest = read(log).split(b"\n", 1)
    assert first == b"earlier line" and json.loads(rest)["pixels"] == 48 * 32


def test_fake_write_protected_stats_are_refused_and_modes_kept(workdir):
    """A 0444 stats file was replaced (the rename needs only the folder's permission) and
    every replaced file took 0644: refused like a write-protected image, modes kept."""
    scene = write_scene(workdir, "still")
    out = os.path.join(workdir, "out")
    args = fake_farm(scene, "-o", f"{out}/{{scene}}.png", "--stats", f"{out}/{{scene}}.json")
    assert run_farm(*args).returncode == 0
    os.chmod(f"{out}/still.png", 0o660)
    os.chmod(f"{out}/still.json", 0o600)
    p = run_farm(*args, "--", "--eps", "0.03")  # other options: rendered again
    assert p.returncode == 0, p.stderr
    assert oct(os.stat(f"{out}/still.png").st_mode & 0o7777) == "0o660"
    assert oct(os.stat(f"{out}/still.json").st_mode & 0o7777) == "0o600"
    stats = read(f"{out}/still.json")
    os.chmod(f"{out}/still.json", 0o444)
    p = run_farm(*args, "--", "--eps", "0.05")
    assert p.returncode == 1 and "still.json: the file is write-protected" in p.stderr, p.stderr
    assert "not rendered" in p.stderr and read(f"{out}/still.json") == stats
    assert oct(os.stat(f"{out}/still.json").st_mode & 0o7777) == "0o444"


def test_fake_damaged_manifest_lines_are_one_warning_not_a_failure_of_every_run(workdir):
    """Bytes that are no UTF-8, or a record of another shape, made every re-run exit 1 with
    an internal error: skipped, one warning line, and what they alone proved done rendered."""
    scene = write_scene(workdir, "anim", animated=True, frame_range=[0, 1])
    out = os.path.join(workdir, "out")
    args = fake_farm(scene, "-o", f"{out}/f{{frame}}.png", "--summary", f"{workdir}/summary.json")
    assert run_farm(*args).returncode == 0
    manifest = f"{out}/.zigzag-farm-manifest.jsonl"
    records = [json.loads(line) for line in open(manifest)]
    frame1 = next(r for r in records if r["kind"] == "frame" and r["output"].endswith("f1.png"))
    with open(manifest, "wb") as f:
        f.writelines((json.dumps(r) + "\n").encode() for r in records if r is not frame1)
        f.write(b"\xff\xfe damaged\n" + json.dumps({**frame1, "also": "x"}).encode() + b"\n")
    p = run_farm(*args)
    assert p.returncode == 0, p.stderr
    assert [line for line in p.stderr.splitlines() if "warning" in line] == [
        f"zigzag-farm: warning: {manifest}: skipped 2 damaged record(s) (what only they proved done is rendered again)"]
    assert summary_of(workdir)["rendered"] == 0 and summary_of(workdir)["skipped"] == 2  # f1's job record stands


def test_fake_ctrl_c_again_while_the_cluster_closes_is_quiet_and_ends(workdir):
    """A second Ctrl-C (or `timeout --foreground`'s second SIGINT) while the driver cancelled
    its jobs and closed the LocalCluster raised KeyboardInterrupt inside Dask's teardown:
    "internal error: RuntimeError: release unlocked lock" exit 1, a traceback at exit, or a
    driver hung for good (review: 3 in 60). Further signals are the same request now."""
    scene = write_scene(workdir, "anim", animated=True, frame_range=[0, 7], sleep=1.0)
    driver = own_group_driver(*fake_farm(scene, "-o", f"{workdir}/out/f{{frame}}.png", "--workers", "2",
                                         "--regions", "2"))

    def again_and_again():
        os.killpg(driver.pid, signal.SIGINT)
        for _ in range(200):  # through the whole teardown, every 10 ms
            time.sleep(0.01)
            try:
                driver.send_signal(signal.SIGINT)
            except ProcessLookupError:
                return
    tree, err = signalled(driver, again_and_again, until=lambda: two_renderers(driver))
    assert driver.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err and "internal error" not in err, err
    assert err.strip().splitlines()[-1].startswith("zigzag-farm: interrupted"), err
    wait_for(lambda: not any(p.is_running() and p.status() != psutil.STATUS_ZOMBIE for p in tree),
             20, "the workers and renderers to exit")
