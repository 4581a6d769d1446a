#!/usr/bin/env python3
"""Frame benchmark: 1 ray/px, adaptive (visibility map and render split) and the 25-point
lattice per scene, interleaved (every repetition runs every configuration once, so load
drifts hit all of them alike), medians of --reps runs, through the real `zigzag render`
path (times from its --stats JSON). Prints the ratios of issue 11: the map's share of the
adaptive frame, lattice / adaptive, adaptive 2 threads vs 1, and the frame's distance to
the ray-throughput limit: its rays by type / bench_traversal's 4-ray-packet throughput
for that type at the same thread count.

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
    "adaptive_1t": [],
    "lattice": ["--aa", "uniform", "--spp", "25", "--pattern", "lattice"],
}


def render(zigzag, scene, size, threads, options, workdir):
    stats = os.path.join(workdir, "stats.json")
    cmd = [zigzag, "render", scene, "-q", "--width", str(size), "--height", str(size), "--threads", str(threads),
           "-o", os.path.join(workdir, "frame.png"), "--stats", stats] + options
    env = dict(os.environ, LP_NUM_THREADS=str(threads))  # lavapipe's workers too
    subprocess.run(cmd, check=True, env=env)
    with open(stats) as f:
        j = json.load(f)
    edges = j["time_s"].get("edges", {}).get("total", 0.0)
    return {"render": j["time_s"]["render"], "map": edges, "rays": j["rays"]}


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
    with tempfile.TemporaryDirectory() as work:
        for rep in range(a.reps):
            for scene, name in zip(scenes, names):
                for config, options in CONFIGS.items():
                    threads = 1 if config == "adaptive_1t" else a.threads
                    runs[(name, config)].append(render(zigzag, scene, a.size, threads, options, work))
            print(f"repetition {rep + 1}/{a.reps} done", file=sys.stderr)
        rates = {}
        if not a.no_traversal:
            rates = traversal_rates(os.path.join(a.build, "tools", "bench_traversal", "bench_traversal"), scenes,
                                    a.threads, work)

    def med(name, config, key):
        return statistics.median(r[key] for r in runs[(name, config)])

    print(f"\nframe benchmark: {a.size}x{a.size}, {a.threads} threads (adaptive_1t: 1), medians of {a.reps}, seconds")
    head = ("scene", "1 ray/px", "adaptive", "map", "map share", "lattice", "lattice/adapt", "adapt 1t", "2t speed-up")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for n in names:
        frame = [r["render"] + r["map"] for r in runs[(n, "adaptive")]]
        frame1 = [r["render"] + r["map"] for r in runs[(n, "adaptive_1t")]]
        adaptive, one = statistics.median(frame), statistics.median(frame1)
        lattice = med(n, "lattice", "render")
        print(f"| {n} | {med(n, '1rpp', 'render'):.3f} | {med(n, 'adaptive', 'render'):.3f} | "
              f"{med(n, 'adaptive', 'map'):.3f} | {100 * statistics.median(r['map'] / (r['render'] + r['map']) for r in runs[(n, 'adaptive')]):.0f} % | "
              f"{lattice:.3f} | {lattice / adaptive:.1f}x | {one:.3f} | {one / adaptive:.2f}x |")
    if not rates:
        return
    print(f"\nray-throughput limit ({a.threads} threads): rays by type / bench_traversal ours4 Mrays/s;"
          " frame render time / time at that limit")
    print("| scene | config | primary | shadow | secondary | limit s | render s | render / limit |")
    print("|---|---|---|---|---|---|---|---|")
    for n in names:
        for config in ("1rpp", "adaptive", "lattice"):
            rays = runs[(n, config)][0]["rays"]  # deterministic: the same in every run
            counts = {"primary": rays["primary"], "shadow": rays["shadow"],
                      "secondary": rays["reflection"] + rays["refraction"]}
            if any((n, k) not in rates for k in counts):
                print(f"| {n} | {config} | (no traversal rates for this scene) |")
                continue
            limit = sum(counts[k] / (rates[(n, k)] * 1e6) for k in counts)
            render_s = med(n, config, "render")
            print(f"| {n} | {config} | {counts['primary']} | {counts['shadow']} | {counts['secondary']} | "
                  f"{limit:.3f} | {render_s:.3f} | {render_s / limit:.1f}x |")


if __name__ == "__main__":
    main()
