"""The driver's command line, in process and without a cluster: options after `--`, and every
usage error a clean one-line message with exit code 2 (nothing rendered, no traceback)."""
import argparse
import json
import os
import subprocess
import sys
import time

import pytest

from conftest import FAKE_ZIGZAG, REAL_ZIGZAG, ROOT, write_scene
from zigzag_farm import cli
from zigzag_farm.scene_info import InfoUsageError, SceneError, scene_info


def options(*farm_args, passed=()):
    o = argparse.Namespace(width=None, height=None, scheduler=None, slurm=None, workers=1)
    for name, value in zip(farm_args[::2], farm_args[1::2]):
        setattr(o, name, value)
    return cli.render_options(o, list(passed))


def test_an_option_written_with_or_without_equals_gives_one_key():
    assert options(passed=["--eps=0.03", "--max-depth", "3"]).key_args == \
        options(passed=["--eps", "0.03", "--max-depth=3"]).key_args == ["--eps", "0.03", "--max-depth", "3"]
    # A flag's value is not split off (it would reach zigzag render as a scene file).
    r = options(passed=["--allow-missing-textures=1", "--edges-serial=false", "--eps", "0.1"])
    assert r.key_args == ["--allow-missing-textures=1", "--edges-serial=false", "--eps", "0.1"]


@pytest.mark.parametrize("passed", [["--width=64", "--threads=2"], ["--width", "64", "--threads", "2"]])
def test_options_after_dashes_in_either_form_are_taken_once(passed):
    r = options("width", 64, passed=passed)
    assert r.key_args == ["--width", "64"]
    assert r.runtime_args == ["--threads", "2"]
    assert r.info_args == ["--width", "64"]


def test_threads_given_or_derived_stay_out_of_the_keys():
    keys = {tuple(options("workers", n, passed=extra).key_args)
            for n in (1, 2, 7) for extra in ([], ["--threads", "3"], ["--threads=1"])}
    assert keys == {()}
    assert options("workers", 1).runtime_args[0] == "--threads"
    assert options("scheduler", "tcp://x:1").runtime_args == []  # remote workers: their own cores


def test_how_a_job_runs_is_not_part_of_its_key():
    """Flags that change how a render runs, not its bytes, travel beside the keys."""
    r = options(passed=["-q", "--eps", "0.1", "--vk-validate", "--vk-device=1", "--edges-serial", "--threads", "2"])
    assert r.key_args == ["--eps", "0.1"]
    assert r.runtime_args == ["--threads", "2", "-q", "--vk-validate", "--edges-serial", "--vk-device", "1"]


def test_option_values_after_dashes_are_no_scenes():
    assert options(passed=["--eps", "0.1", "-q", "--aov", "depth", "--max-depth", "3",
                           "--vk-validate", "--edges-serial=false", "--assets", "a"]).key_args == [
        "--eps", "0.1", "--aov", "depth", "--max-depth", "3", "--edges-serial=false", "--assets", "a"]


def test_info_gets_the_options_it_takes_in_either_form():
    r = options(passed=["--assets=/a", "--eps", "0.1", "--fps", "30", "--height=90"])
    pairs = dict(zip(r.info_args[::2], r.info_args[1::2]))
    assert pairs == {"--assets": "/a", "--fps": "30", "--height": "90"}
    assert r.key_args == ["--assets", "/a", "--eps", "0.1", "--fps", "30", "--height", "90"]


def run(capsys, *args):
    code = cli.main(["render", "-q", *args])
    return code, capsys.readouterr().err


@pytest.fixture
def scene(workdir):
    return write_scene(workdir, "anim", animated=True, frame_range=[0, 3])


def usage_error(capsys, *args):
    code, err = run(capsys, *args)
    assert code == 2, err
    assert "Traceback" not in err and err.startswith("zigzag-farm: error: "), err
    return err


@pytest.mark.parametrize("args,message", [
    (["--workers", "-1"], "--workers -1: must be at least 1"),
    (["--workers", "0"], "--workers 0: must be at least 1"),
    (["--width", "0"], "--width 0: must be at least 1"),
    (["--width", "20000"], "--width 20000: the renderer's frames are at most 16384 pixels a side"),
    (["--regions", "0"], "--regions 0: must be at least 1"),
    (["--timeout", "0"], "--timeout 0: must be more than 0"),
    (["--frames=-2-1"], "the renderer's frames are 0 to 100000000"),
    (["--frames", "0-99999999"], "100000000 frames, more than a batch may have"),
    (["--", "--width", "abc"], "--width (after --) 'abc': expected a whole number"),
    (["--", "--height=-5"], "--height (after --) -5: must be at least 1"),
    (["--", "--threads=x"], "--threads (after --) 'x': expected a whole number"),
    (["--width", "64", "--", "--width=32"], "--width 64 and --width 32 after --: give it once"),
    (["--", "--threads", "1", "--assets"], "--assets after --: needs a value"),
    (["--", "--fps"], "--fps after --: needs a value"),
    (["--", "--frame", "3"], "--frame after --: zigzag-farm sets it for every job"),
    (["--", "--stats=x.json"], "--stats after --: zigzag-farm sets it"),
    (["--", "--time", "0.5"], "frames, not times"),
    (["--", "--aov", "rays", "rays.png"], "--aov ... rays.png after --: an AOV image of its own is not a farm output"),
    (["--", "--aov=level", "l.png", "--eps", "0.1"], "--aov ... l.png after --"),
    # zigzag render writes no image with these: every job failed and was retried (review).
    (["--", "--dry-run"], "--dry-run after --: a job that renders nothing cannot be a farm job"),
    (["--", "--eps", "0.1", "-h"], "-h after --: a job that renders nothing"),
    # Tested for truth: a local cluster and the scene's whole range ran instead (review).
    (["--scheduler", ""], "--scheduler '': needs a value"),
    (["--frames", ""], "--frames '': needs a value"),
    (["--frames= "], "--frames ' ': needs a value"),
    (["--stats", ""], "--stats '': needs a value"),
    (["--summary", ""], "--summary '': needs a value"),
    (["--manifest", ""], "--manifest '': needs a value"),
    (["--work-dir", ""], "--work-dir '': needs a value"),
    (["--zigzag", ""], "--zigzag '': needs a value"),
    # Passed the dry-run check (it took it as a second scene); every job then failed naming
    # its temporary (review).
    (["--", "other.json"], "other.json after --: scenes go before --"),
    (["--", "--eps", "0.1", "-q", "other.json"], "other.json after --: scenes go before --"),
    (["--", "--edges-serial=false", "other.json", "--spp", "4"], "other.json after --: scenes go before --"),
])
def test_bad_numbers_and_options_are_usage_errors(capsys, workdir, scene, args, message):
    err = usage_error(capsys, scene, "-o", f"{workdir}/out/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG, *args)
    assert message in err
    assert not os.path.exists(f"{workdir}/out")


@pytest.mark.parametrize("output,stats,message", [
    ("out/{}.png", None, "-o out/{}.png: unknown placeholder '{}' (known: {scene}, {camera}, {frame}, {frame:04})"),
    ("out/{frame:4}.png", "out/{scene:.3}.json", "--stats out/{scene:.3}.json: unknown placeholder '{scene:.3}'"),
    ("w3/{scene}_{camera:x}_{frame:4}.png", None, "-o w3/{scene}_{camera:x}_{frame:4}.png: unknown placeholder '{camera:x}'"),
    ("out/f{frame}.png", "out/f{frame}.png", "both the image of anim camera 0 f0 and the stats of anim camera 0 f0"),
    ("out/f{frame}.png", "out/stats.json", "both the stats of anim camera 0 f0 and the stats of anim camera 0 f1: add {frame} to --stats"),
])
def test_colliding_or_bad_output_patterns_are_usage_errors(capsys, workdir, scene, output, stats, message):
    os.chdir(workdir)
    extra = ["--stats", stats] if stats else []
    err = usage_error(capsys, scene, "-o", output, "--zigzag", FAKE_ZIGZAG, "--frames", "0-3", *extra)
    assert message in err


def test_a_summary_onto_an_output_is_a_usage_error(capsys, workdir, scene):
    err = usage_error(capsys, scene, "-o", f"{workdir}/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG,
                      "--summary", f"{workdir}/f2.png")
    assert "both the image of anim camera 0 f2 and the summary" in err
    assert os.listdir(workdir) == ["anim.json"]


def test_a_write_protected_summary_is_a_usage_error_before_anything_runs(capsys, workdir, scene):
    """It was replaced by the rename (and, once refused, only after the whole batch)."""
    with open(f"{workdir}/summary.json", "w") as f:
        f.write("MINE")
    os.chmod(f"{workdir}/summary.json", 0o444)
    err = usage_error(capsys, scene, "-o", f"{workdir}/out/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG,
                      "--summary", f"{workdir}/summary.json")
    assert f"--summary {workdir}/summary.json: the file is write-protected" in err
    assert not os.path.exists(f"{workdir}/out") and open(f"{workdir}/summary.json").read() == "MINE"


@pytest.mark.parametrize("where", ["output", "summary", "manifest", "stats"])
@pytest.mark.parametrize("how", ["parent is a file", "cannot be made"])
def test_unwritable_places_are_usage_errors_before_anything_runs(capsys, workdir, scene, where, how):
    afile = os.path.join(workdir, "afile")
    open(afile, "w").close()
    # Root may write anywhere a mode forbids; /proc is unwritable for everyone.
    bad = f"{afile}/x" if how == "parent is a file" else "/proc/zigzag-farm-test/x"
    args = {"output": ["-o", f"{bad}/f{{frame}}.png"], "summary": ["--summary", f"{bad}/s.json"],
            "manifest": ["--manifest", f"{bad}/m.jsonl"], "stats": ["--stats", f"{bad}/{{frame}}.json"]}[where]
    if where != "output":
        args += ["-o", f"{workdir}/out/f{{frame}}.png"]
    err = usage_error(capsys, scene, "--zigzag", FAKE_ZIGZAG, *args)
    assert "cannot write" in err
    if how == "parent is a file":
        assert f"{afile} is a file, not a folder" in err
    assert not os.path.exists(f"{workdir}/out")


def test_an_output_that_is_a_folder_is_a_usage_error_wherever_it_comes(capsys, workdir, scene):
    """Not only the first file of a folder: frame 2's image path being a folder is found too."""
    os.makedirs(f"{workdir}/out/f2.png")
    err = usage_error(capsys, scene, "-o", f"{workdir}/out/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG)
    assert f"cannot write the image of anim camera 0 f2 {workdir}/out/f2.png: it is a folder" in err


def test_an_image_output_that_is_a_stream_is_a_usage_error(capsys, workdir, scene):
    """Workers rename their images into place: a FIFO (or a device) as -o became a regular
    file. Refused before anything runs; --stats and --summary may be streams."""
    os.mkfifo(f"{workdir}/f1.png")
    err = usage_error(capsys, scene, "-o", f"{workdir}/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG)
    assert f"-o {workdir}/f1.png: a device or pipe, not a file" in err
    assert sorted(os.listdir(workdir)) == ["anim.json", "f1.png"] and not os.path.isfile(f"{workdir}/f1.png")


def test_layers_of_aovs_after_dashes_are_fine():
    assert options(passed=["--aov", "depth", "--aov=normal", "--eps", "0.1"]).key_args == [
        "--aov", "depth", "--aov", "normal", "--eps", "0.1"]


def test_a_bad_scheduler_address_is_a_usage_error(capsys, workdir, scene):
    err = usage_error(capsys, scene, "-o", f"{workdir}/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG,
                      "--scheduler", "bogus", "--wait", "2")
    assert "cannot reach the Dask scheduler at bogus" in err


@pytest.fixture
def garbage_server():
    """A service on 127.0.0.1 that is no Dask scheduler: answers anything with an HTTP 400,
    as a proxy or load balancer does -> its address."""
    import socket
    import threading
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(8)
    srv.settimeout(0.2)
    stop = threading.Event()

    def serve():
        while not stop.is_set():
            try:
                conn, _ = srv.accept()
            except OSError:
                continue
            with conn:
                try:
                    conn.recv(4096)
                    conn.sendall(b"HTTP/1.1 400 Bad Request\r\nconnection: close\r\ncontent-length: 0\r\n\r\n")
                except OSError:
                    pass

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    stop.set()
    thread.join(timeout=5)
    srv.close()


def test_a_scheduler_address_where_another_service_answers_is_a_usage_error(capsys, workdir, scene,
                                                                              garbage_server):
    """Its answer read as Dask's frames gave "internal error: MemoryError ...", exit 1."""
    err = usage_error(capsys, scene, "-o", f"{workdir}/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG,
                      "--scheduler", garbage_server, "--wait", "3")
    assert f"cannot reach the Dask scheduler at {garbage_server}: what answered there is no Dask scheduler" in err


@pytest.mark.parametrize("regions,message", [
    ("1000000000", "the batch would have 1000000001 jobs, more than a batch may have"),
    ("99991", "cannot split a 48x32 frame into 99991 regions (it has 1536 pixels)"),
])
def test_an_impossible_region_count_fails_at_once(capsys, workdir, scene, regions, message):
    started = time.monotonic()
    err = usage_error(capsys, scene, "-o", f"{workdir}/f{{frame}}.png", "--zigzag", FAKE_ZIGZAG,
                      "--frames", "0", "--regions", regions)
    assert message in err
    assert time.monotonic() - started < 5


@pytest.mark.parametrize("code,stderr,kind,message", [
    # CLI11 refusing an option zigzag info was passed: a usage error, said as the renderer says it
    (105, "--fps: Value 5000 not in range 0.001 to 1000\nRun with --help for more information.\n",
     InfoUsageError, "--fps: Value 5000 not in range 0.001 to 1000"),
    (109, "The following arguments were not expected: --bogus\nRun with --help for more information.\n",
     InfoUsageError, "The following arguments were not expected: --bogus"),
    # a scene that does not load: that scene's failure
    (1, "zigzag: error: s.json: cannot read: no such file\n", SceneError, "zigzag: error: s.json: cannot read"),
    (1, "warning: s.json: a light is black\nzigzag: error: s.json: no triangles\n", SceneError,
     "zigzag: error: s.json: no triangles"),
])
def test_info_errors_keep_the_renderers_message(tmp_path, code, stderr, kind, message):
    """The farm reported only stderr's last line, CLI11's "Run with --help for more
    information.", as a scene that failed to load (review)."""
    fake = tmp_path / "zigzag"
    fake.write_text(f"#!/bin/sh\nprintf '%s' '{stderr}' >&2\nexit {code}\n")
    fake.chmod(0o755)
    with pytest.raises(SceneError) as e:
        scene_info(str(fake), "s.json")
    assert type(e.value) is kind
    assert message in str(e.value) and "Run with --help" not in str(e.value) and "warning" not in str(e.value)


@pytest.mark.parametrize("renderer", ["fake", "real"])
@pytest.mark.parametrize("output,args,message", [
    ("ext/x.gif", [], "-o {w}/ext/x.gif: unsupported image format '.gif'"),
    ("ext/x.txt", ["--regions", "2"], "-o {w}/ext/x.txt: unsupported image format '.txt'"),
    ("y.png", ["--", "--aov", "normal"], "--aov normal without a file adds channels to the -o image, which must "
                                         "be an .exr (-o {w}/y.png)"),
    ("y.png", ["--regions", "2", "--", "--aov=normal"], "--aov normal without a file adds channels to the -o "
                                                        "image, which must be an .exr (-o {w}/y.png)"),
])
def test_what_the_renderer_refuses_is_a_usage_error_before_any_cluster(capsys, workdir, renderer, output, args,
                                                                       message):
    """The farm started its cluster and failed every job naming its temporary (-o x.gif), or
    with --regions rendered .exr parts and dropped --aov in the merge (review): the renderer's
    --dry-run, given the user's own outputs and options, refuses them first."""
    if renderer == "real":
        if not os.access(REAL_ZIGZAG, os.X_OK):
            pytest.skip(f"no {REAL_ZIGZAG}")
        zigzag, scene = REAL_ZIGZAG, os.path.join(ROOT, "scenes", "default.json")
    else:
        zigzag, scene = FAKE_ZIGZAG, write_scene(workdir, "default")
    before = sorted(os.listdir(workdir))
    started = time.monotonic()
    err = usage_error(capsys, scene, "-o", f"{workdir}/{output}", "--zigzag", zigzag, "--width", "64", *args)
    assert f"zigzag render refuses {scene}: " + message.format(w=workdir) in err
    assert ".tmp" not in err
    assert sorted(os.listdir(workdir)) == before
    assert time.monotonic() - started < 20  # no cluster started


def test_the_renderer_checks_the_users_patterns_with_the_jobs_options(capsys, workdir, monkeypatch):
    """One --dry-run per scene, as its first job: camera, frame, stats and the options after --."""
    log = os.path.join(workdir, "renders.log")
    monkeypatch.setenv("FAKE_ZIGZAG_DRY_RUN_LOG", log)
    scene = write_scene(workdir, "anim", animated=True, frame_range=[2, 5], sleep=0)
    other = write_scene(workdir, "still")
    err = usage_error(capsys, scene, other, "-o", f"{workdir}/o/{{scene}}_{{frame:04}}.png", "--zigzag", FAKE_ZIGZAG,
                      "--stats", f"{workdir}/o/{{scene}}{{frame}}.json", "--camera", "0", "--", "--eps", "0.5", "--aov", "depth")
    assert f"-o {workdir}/o/anim_0002.png" in err
    runs = [json.loads(line) for line in open(log)]
    assert len(runs) == 1 and "--dry-run" in runs[0]
    for pair in (["-o", f"{workdir}/o/{{scene}}_{{frame:04}}.png"], ["--stats", f"{workdir}/o/{{scene}}{{frame}}.json"],
                 ["--frame", "2"], ["--camera", "0"], ["--eps", "0.5"]):
        assert any(runs[0][i:i + 2] == pair for i in range(len(runs[0]))), (pair, runs[0])


def test_the_check_skips_a_frame_the_user_write_protected(capsys, workdir, monkeypatch):
    """A batch run again over finished frames the user made read-only: the renderer's check of
    the first frame refused the whole batch, though the run only adds the others. It checks
    the first frame it may write (the jobs refuse a protected image themselves: test_job)."""
    log = os.path.join(workdir, "renders.log")
    monkeypatch.setenv("FAKE_ZIGZAG_DRY_RUN_LOG", log)
    scene = write_scene(workdir, "anim", animated=True, frame_range=[2, 5], sleep=0)
    os.makedirs(f"{workdir}/o")
    with open(f"{workdir}/o/anim_0002.png", "wb") as f:
        f.write(b"FINAL")
    os.chmod(f"{workdir}/o/anim_0002.png", 0o444)
    usage_error(capsys, scene, "-o", f"{workdir}/o/{{scene}}_{{frame:04}}.png", "--zigzag", FAKE_ZIGZAG,
                "--", "--aov", "depth")  # the fake's check refuses --aov into a .png: the check ran
    runs = [json.loads(line) for line in open(log)]
    assert len(runs) == 1
    assert any(runs[0][i:i + 2] == ["--frame", "3"] for i in range(len(runs[0]))), runs[0]


def test_ctrl_c_while_the_driver_imports_is_one_line_and_exit_130(tmp_path):
    # The SIGINT arrives as zigzag_farm.cli starts importing (a finder sends it), where a
    # real Ctrl-C lands in the first 0.1 s of a run: no traceback, the run's own exit code.
    script = tmp_path / "start.py"
    script.write_text(
        "import importlib.abc, os, signal, sys\n"
        "class Interrupt(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        if name == 'zigzag_farm.cli':\n"
        "            os.kill(os.getpid(), signal.SIGINT)\n"
        "        return None\n"
        "sys.meta_path.insert(0, Interrupt())\n"
        "from zigzag_farm.launch import main\n"
        "sys.exit(main())\n")
    env = {**os.environ, "PYTHONPATH": os.path.join(ROOT, "farm")}
    p = subprocess.run([sys.executable, str(script), "render", "x.json", "-o", "x.png"], env=env,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 130, p.stderr
    assert p.stderr == "zigzag-farm: interrupted; nothing was started\n", p.stderr


def test_what_ends_a_run_is_said_in_one_line():
    """A lost scheduler cancels every pending job, and Dask's error lists each key on a line
    of its own (review: 4 lines for 12 jobs); any other error is one line too."""
    from distributed.client import CancelledFuturesGroup, FutureCancelledError, FuturesCancelledError

    def cancelled(reason):
        return FuturesCancelledError([CancelledFuturesGroup(
            [FutureCancelledError(k, reason) for k in ("render-a", "render-b")], reason)])

    assert cli.internal_error_line(cancelled("scheduler-connection-lost")) == \
        "lost the Dask scheduler: its pending jobs were cancelled"
    # Another reason is named, not taken for a lost scheduler (re-read of the diff).
    assert cli.internal_error_line(cancelled("scheduler-restart")) == \
        "the pending jobs were cancelled (scheduler-restart)"
    other = cli.internal_error_line(RuntimeError("first\nsecond " + "x" * 400))
    assert "\n" not in other and other.startswith("internal error: RuntimeError: first second ")
    assert other.endswith("...") and len(other) < 360


def test_a_stop_that_hangs_is_cut_short_killing_the_drivers_processes(monkeypatch, capsys):
    """Signals after the first are not acted on (cli._stop); what still bounds the stop is
    this: STOP_TIMEOUT_S after the signal, the driver's child processes are killed and it exits
    with the signal's code."""
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    exits = []
    monkeypatch.setattr(cli.time, "sleep", lambda s: None)
    monkeypatch.setattr(cli.os, "_exit", exits.append)
    monkeypatch.setattr(cli, "_terminated", True)
    cli._stop_or_give_up()
    assert child.wait(timeout=10) == -9 and exits == [143]
    assert "did not close within 60 s" in capsys.readouterr().err
