#!/usr/bin/env python3
"""Benchmark of the render farm driver (zigzag-farm), loopback only.

1. Per-job overhead: jobs of a renderer that does nothing, through the driver on a
   1-worker LocalCluster, against the same subprocesses run in a plain loop.
2. Wall time with 1 and 2 workers here: the real zigzag on frames of scenes/animated.json,
   which also measures the distribution of frame times.
3. Simulated clusters of N = 4, 16, 64 workers (threads of one LocalCluster; each job a
   subprocess that sleeps for a frame time drawn from the measured distribution) on a
   240-frame animation: scaling efficiency = serial time / (N x wall), and a check that every
   output is there exactly once and right (zero lost or duplicated).

Run: build/venv/bin/python tools/bench_farm/bench_farm.py --build build [--quick]
"""
from __future__ import annotations

import argparse
import json
import os
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

import psutil

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "farm"))

from zigzag_farm.cluster import local_cluster  # noqa: E402
from zigzag_farm.manifest import Manifest  # noqa: E402
from zigzag_farm.plan import SceneInfo, plan_batch  # noqa: E402
from zigzag_farm.runner import RunSettings, Runner  # noqa: E402

SLEEPER = os.path.join(HERE, "sleep_zigzag.sh")


def assert_loopback_only():
    pids = {os.getpid()} | {p.pid for p in psutil.Process().children(recursive=True)}
    socks = [c for c in psutil.net_connections("inet") if c.status == psutil.CONN_LISTEN and c.pid in pids]
    bad = [c.laddr for c in socks if c.laddr.ip != "127.0.0.1"]
    assert socks and not bad, f"servers not on loopback: {bad}"


def sleeper_scene(folder, durations):
    path = os.path.join(folder, "sim.txt")
    with open(path, "w") as f:
        f.writelines(f"{i + 1} {d:.4f}\n" for i, d in enumerate(durations))
    return path


def run_plan(client, folder, scene, frames, name):
    info = SceneInfo(path=scene, name="sim", width=64, height=64, cameras=1, animated=True,
                     frame_range=(1, frames))
    out = os.path.join(folder, name)
    plan = plan_batch([info], os.path.join(out, "f{frame:04}.png"), frames=None, camera="0",
                      regions=1, work_dir=os.path.join(out, ".parts"))
    with Manifest(os.path.join(out, ".manifest.jsonl")) as manifest:
        runner = Runner(plan, manifest, RunSettings(zigzag=SLEEPER, retries=0),
                        progress_stream=open(os.devnull, "w"), live=False)
        t = time.perf_counter()
        outcome = runner.run(client)
        wall = time.perf_counter() - t
        records = [r for r in manifest.records.values() if r["kind"] == "frame"]
    return out, outcome, wall, records


def check_outputs(out, frames, records):
    """Zero lost or duplicated: each frame's file once, with its own content, recorded once."""
    files = sorted(f for f in os.listdir(out) if not f.startswith("."))
    lost = [n for n in range(1, frames + 1) if f"f{n:04}.png" not in files]
    wrong = [n for n in range(1, frames + 1) if f"f{n:04}.png" in files
             and open(os.path.join(out, f"f{n:04}.png")).read() != f"frame {n}\n"]
    outputs = [r["output"] for r in records]
    duplicated = len(outputs) - len(set(outputs)) + max(0, len(files) - frames)
    temporaries = [f for f in os.listdir(out) if ".tmp" in f]
    return {"lost": len(lost), "wrong": len(wrong), "duplicated": duplicated,
            "temporaries": len(temporaries)}


def overhead(folder, jobs):
    scene = sleeper_scene(folder, [0.0] * jobs)
    t = time.perf_counter()
    for n in range(1, jobs + 1):
        subprocess.run([SLEEPER, "render", scene, "-o", os.path.join(folder, "direct.png"), "--frame", str(n)],
                       check=True)
    direct = (time.perf_counter() - t) / jobs
    t = time.perf_counter()
    with local_cluster(1) as client:
        startup = time.perf_counter() - t
        assert_loopback_only()
        out, outcome, wall, records = run_plan(client, folder, scene, jobs, "overhead")
    check = check_outputs(out, jobs, records)
    per_job = wall / jobs
    return {"jobs": jobs, "direct_s_per_job": direct, "driver_s_per_job": per_job,
            "overhead_s_per_job": per_job - direct, "cluster_startup_s": startup, "check": check}


def real_frames(build, folder, frames, size, workers):
    zigzag = os.path.join(build, "zigzag")
    scene = os.path.join(ROOT, "scenes", "animated.json")
    summary = os.path.join(folder, f"real{workers}.json")
    cmd = [sys.executable, "-m", "zigzag_farm", "render", "-q", scene, "-o",
           os.path.join(folder, f"real{workers}", "f{frame:04}.png"), "--frames", f"1-{frames}",
           "--workers", str(workers), "--zigzag", zigzag, "--summary", summary,
           "--width", str(size), "--height", str(size)]
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "farm"))
    t = time.perf_counter()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if p.returncode != 0:
        raise RuntimeError(f"real render failed:\n{p.stderr}")
    s = json.load(open(summary))
    return {"workers": workers, "frames": frames, "size": size, "wall_s": wall,
            "driver_wall_s": s["wall_s"], "job_seconds": s["job_seconds"]}


def kill_busy_workers(count):
    """SIGKILL `count` worker processes that are running a job (the nanny restarts them)."""
    killed = 0
    for p in psutil.Process().children(recursive=True):
        try:
            if killed < count and any("sleep_zigzag" in " ".join(c.cmdline()) for c in p.children()):
                p.send_signal(signal.SIGKILL)
                killed += 1
        except psutil.Error:
            continue
    return killed


def cost_model(durations, workers, per_job_s):
    """Makespan of the same jobs handed out in order to whichever worker frees first, each
    costing its duration plus the measured per-job overhead -> predicted efficiency."""
    free = [0.0] * workers
    for d in durations:
        i = min(range(workers), key=free.__getitem__)
        free[i] += d + per_job_s
    return sum(durations) / (workers * max(free))


def simulate(folder, durations, workers, max_processes, kill=0):
    """workers job slots: one process each up to max_processes, else max_processes processes
    of workers/max_processes threads (64 Python processes do not fit on a small machine)."""
    scene = sleeper_scene(folder, durations)
    name = f"sim{workers}" + ("-faults" if kill else "")
    processes = min(workers, max_processes)
    if workers % processes:
        raise SystemExit(f"{workers} workers do not split evenly over {processes} processes")
    with local_cluster(processes, jobs_per_worker=workers // processes) as client:
        assert_loopback_only()
        killer = None
        if kill:
            # A third of the way in, kill workers in the middle of their jobs.
            delay = sum(durations) / workers / 3
            killer = threading.Timer(delay, lambda: killed.append(kill_busy_workers(kill)))
            killed: list[int] = []
            killer.start()
        out, outcome, wall, records = run_plan(client, folder, scene, len(durations), name)
        if killer:
            killer.join()
            assert killed and killed[0] == kill, f"killed {killed} of {kill} workers"
    check = check_outputs(out, len(durations), records)
    serial = sum(durations)
    ideal = max(serial / workers, max(durations))
    return {"workers": workers, "processes": processes, "threads_per_process": workers // processes, "frames": len(durations), "serial_s": serial, "wall_s": wall,
            "speedup": serial / wall, "efficiency": serial / (workers * wall),
            "ideal_wall_s": ideal, "failed": len(outcome.failures), "killed_workers": kill,
            "check": check}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--frames", type=int, default=8, help="real frames for the 1/2-worker runs")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--sim-frames", type=int, default=240)
    ap.add_argument("--sim-mean", type=float, default=2.0,
                    help="mean simulated frame time (s): the measured distribution's shape at this mean")
    ap.add_argument("--sim-workers", default="4,16,64")
    ap.add_argument("--max-processes", type=int, default=16,
                    help="simulated workers are processes up to this many, then threads of that many processes")
    ap.add_argument("--fault-workers", type=int, default=16,
                    help="one more simulated run with this many workers, 2 of them SIGKILLed mid-job (0: none)")
    ap.add_argument("--overhead-jobs", type=int, default=40)
    ap.add_argument("--skip-real", action="store_true")
    ap.add_argument("--out", help="write the results as JSON")
    o = ap.parse_args()
    results = {}
    with tempfile.TemporaryDirectory(prefix="bench_farm_") as folder:
        results["overhead"] = r = overhead(folder, o.overhead_jobs)
        print(f"per-job overhead: {r['overhead_s_per_job'] * 1e3:.1f} ms (driver {r['driver_s_per_job'] * 1e3:.1f} ms/job "
              f"vs plain subprocess {r['direct_s_per_job'] * 1e3:.1f} ms/job; {r['jobs']} jobs); "
              f"LocalCluster start {r['cluster_startup_s']:.1f} s; {r['check']}")
        measured = []
        helps = subprocess.run([os.path.join(o.build, "zigzag"), "render", "--help"],
                               capture_output=True, text=True).stdout
        if not o.skip_real and "--frame" not in helps:
            print("real: skipped (this zigzag has no --frame yet)")
        elif not o.skip_real:
            for w in (1, 2):
                results[f"real_{w}_workers"] = r = real_frames(o.build, folder, o.frames, o.size, w)
                measured = measured or r["job_seconds"]
                print(f"real: {r['frames']} frames of animated.json at {r['size']}², {w} worker(s): "
                      f"{r['wall_s']:.1f} s wall ({r['driver_wall_s']:.1f} s after cluster start), frame time "
                      f"median {statistics.median(r['job_seconds']):.2f} s, max {max(r['job_seconds']):.2f} s")
        if not measured:
            measured = [1.0]
            print("simulation: no measured frame times (--skip-real): constant durations")
        mean = statistics.fmean(measured)
        rng = random.Random(0)
        durations = [rng.choice(measured) / mean * o.sim_mean for _ in range(o.sim_frames)]
        for n in (int(x) for x in o.sim_workers.split(",")):
            results[f"sim_{n}"] = r = simulate(folder, durations, n, o.max_processes)
            r["model_efficiency"] = cost_model(durations, n, results["overhead"]["overhead_s_per_job"])
            verdict = "" if n != 16 else ("  (target >= 0.9: met)" if r["efficiency"] >= 0.9 else "  (target >= 0.9: MISSED)")
            print(f"simulated N={n:3} ({r['processes']} processes x {r['threads_per_process']}): {r['frames']} frames, serial {r['serial_s']:.0f} s, wall {r['wall_s']:.1f} s "
                  f"(ideal {r['ideal_wall_s']:.1f} s), speedup {r['speedup']:.1f}, efficiency {r['efficiency']:.2f}"
                  f"{verdict}; cost model {r['model_efficiency']:.2f}; {r['check']}")
            assert all(v == 0 for v in r["check"].values()) and r["failed"] == 0, r
        if o.fault_workers:
            n = o.fault_workers
            results["sim_faults"] = r = simulate(folder, durations, n, o.max_processes, kill=2)
            print(f"simulated N={n:3} with 2 workers SIGKILLed mid-job: wall {r['wall_s']:.1f} s, efficiency "
                  f"{r['efficiency']:.2f}; {r['check']}")
            assert all(v == 0 for v in r["check"].values()) and r["failed"] == 0, r
    if o.out:
        with open(o.out, "w") as f:
            json.dump(results, f, indent=2)


if __name__ == "__main__":
    main()
