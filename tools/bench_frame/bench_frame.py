#!/usr/bin/env python3
"""Frame benchmark: 1 ray/px, adaptive and the 25-point lattice per scene, interleaved (every repetition runs every configuration once, so load
drifts hit all of them alike; the order rotates by repetition), medians of --reps runs, through the real `zigzag render`
path (times from its --stats JSON). The adaptive frame runs twice: as zigzag renders it
(the map alongside level 1; frame = wall of both) and with --edges-serial (map, then
render: the split). Prints the ratios of issue 11: the map's share of the serial adaptive
frame and lattice / adaptive frame (the map's thread holds its one-off set-up, the scene's
upload and the targets' allocation; both also with the wait for the Vulkan device that
loading did not hide, which precedes a scene's first frame: a single image pays it, a
sequence once), adaptive 2 threads vs 1 (`--threads 1`, whose map still runs on its own
thread and lavapipe's) and vs the same run confined to one core (sched_setaffinity: what a
second core buys), and the frame's distance to the ray-throughput limit: its rays by type /
bench_traversal's 4-ray-packet throughput for that type at the same thread count.

usage: bench_frame.py --build BUILD [--size 1024] [--reps 5] [--threads 2] [--no-traversal] [scene.json ...]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

CONFIGS = {  # name -> (zigzag options, uses the thread count given)
    "1rpp": ["--aa", "none"],
    "adaptive": [],
    "serial": ["--edges-serial"],
    "adaptive_1t": [],
    "adaptive_1core": [],
    "lattice": ["--aa", "uniform", "--spp", "25", "--pattern", "lattice"],
}


def render(zigzag, scene, size, threads, options, workdir, cpus=None):
    stats = os.path.join(workdir, "stats.json")
    cmd = [zigzag, "render", scene, "-q", "--width", str(size), "--height", str(size), "--threads", str(threads),
           "-o", os.path.join(workdir, "frame.png"), "--stats", stats] + options
    env = dict(os.environ, LP_NUM_THREADS=str(threads))  # lavapipe's workers too
    # cpus: the process and every thread it starts (the map's, lavapipe's) on these cores only.
    pin = (lambda: os.sched_setaffinity(0, cpus)) if cpus else None
    subprocess.run(cmd, check=True, env=env, preexec_fn=pin)
    with open(stats) as f:
        j = json.load(f)
    edges = j["time_s"].get("edges", {})
    return {"render": j["time_s"]["render"], "map": edges.get("total", 0.0), "wait": edges.get("device_wait", 0.0),
            "frame": j["time_s"]["frame"], "rays": j["rays"]}


def traversal_rates(bench, scenes, threads, workdir):
    """Mrays/s of our 4-ray packets per scene stem and ray kind at `threads` threads."""
    out = os.path.join(workdir, "traversal.json")
    subprocess.run([bench, "--benchmark_filter=/ours4/", "--benchmark_out=" + out, "--benchmark_out_format=json"] +
                   scenes, check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        runs = json.load(f)["benchmarks"]
    rates = {}
    for r in runs:
        if r.get("threads") != threads:
            continue
        scene, kind = r["run_name"].split("/")[:2]
        rates[(scene, kind)] = r["Mrays/s"]
    return rates


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--no-traversal", action="store_true")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    scenes = a.scenes or [os.path.join(ROOT, "scenes", s + ".json") for s in ("room", "glass")]
    if not a.scenes and os.path.isdir(os.path.join(ROOT, "..", "shared", "scenes")):
        scenes.append(os.path.join(ROOT, "scenes", "car.json"))
    zigzag = os.path.join(a.build, "zigzag")
    names = [os.path.splitext(os.path.basename(s))[0] for s in scenes]
    runs = {(n, c): [] for n in names for c in CONFIGS}
    one_core = min(os.sched_getaffinity(0))
    with tempfile.TemporaryDirectory() as work:
        configs = list(CONFIGS.items())
        for rep in range(a.reps):
            for scene, name in zip(scenes, names):
                # Each repetition starts at another configuration, so none always runs first
                # (a cold cache) or right after the same neighbour.
                for config, options in configs[rep % len(configs):] + configs[:rep % len(configs)]:
                    threads = 1 if config in ("adaptive_1t", "adaptive_1core") else a.threads
                    cpus = {one_core} if config == "adaptive_1core" else None
                    runs[(name, config)].append(render(zigzag, scene, a.size, threads, options, work, cpus))
            print(f"repetition {rep + 1}/{a.reps} done", file=sys.stderr)
        rates = {}
        if not a.no_traversal:
            rates = traversal_rates(os.path.join(a.build, "tools", "bench_traversal", "bench_traversal"), scenes,
                                    a.threads, work)

    def med(name, config, key):
        return statistics.median(r[key] for r in runs[(name, config)])

    print(f"\nframe benchmark: {a.size}x{a.size}, {a.threads} threads (adaptive_1t: 1 thread; adaptive_1core: 1 thread"
          f" on 1 core, map and lavapipe included), medians of {a.reps}, seconds")
    head = ("scene", "1 ray/px", "serial: render", "serial: map", "map share", "adaptive frame",
            "lattice", "lattice/frame", "frame 1t", "2t speed-up", "frame 1 core", "vs 1 core",
            "device wait", "share with wait", "lattice/(frame + wait)")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for n in names:
        adaptive, one = med(n, "adaptive", "frame"), med(n, "adaptive_1t", "frame")
        core = med(n, "adaptive_1core", "frame")
        lattice = med(n, "lattice", "frame")  # frame against frame: the same clock as the adaptive's
        share = statistics.median(r["map"] / (r["render"] + r["map"]) for r in runs[(n, "serial")])
        wait = med(n, "adaptive", "wait")
        share_wait = statistics.median((r["map"] + r["wait"]) / (r["render"] + r["map"] + r["wait"])
                                       for r in runs[(n, "serial")])
        single = statistics.median(r["frame"] + r["wait"] for r in runs[(n, "adaptive")])
        print(f"| {n} | {med(n, '1rpp', 'render'):.3f} | {med(n, 'serial', 'render'):.3f} | "
              f"{med(n, 'serial', 'map'):.3f} | {100 * share:.1f} % | {adaptive:.3f} | "
              f"{lattice:.3f} | {lattice / adaptive:.1f}x | {one:.3f} | {one / adaptive:.2f}x | {core:.3f} | "
              f"{core / adaptive:.2f}x | {wait:.3f} | {100 * share_wait:.1f} % | {lattice / single:.1f}x |")
    if not rates:
        return
    print(f"\nray-throughput limit ({a.threads} threads): rays by type / bench_traversal ours4 Mrays/s;"
          " frame render time / time at that limit")
    print("| scene | config | primary | shadow | secondary | limit s | render s | render / limit |")
    print("|---|---|---|---|---|---|---|---|")
    for n in names:
        for config in ("1rpp", "serial", "lattice"):
            rays = runs[(n, config)][0]["rays"]  # deterministic: the same in every run
            counts = {"primary": rays["primary"], "shadow": rays["shadow"],
                      "secondary": rays["reflection"] + rays["refraction"] + rays.get("continuation", 0)}
            if any((n, k) not in rates for k in counts):
                print(f"| {n} | {config} | (no traversal rates for this scene) |")
                continue
            limit = sum(counts[k] / (rates[(n, k)] * 1e6) for k in counts)
            render_s = med(n, config, "render")
            print(f"| {n} | {config} | {counts['primary']} | {counts['shadow']} | {counts['secondary']} | "
                  f"{limit:.3f} | {render_s:.3f} | {render_s / limit:.1f}x |")


if __name__ == "__main__":
    main()
