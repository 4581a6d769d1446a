#!/usr/bin/env python3
"""A stand-in for the zigzag binary that obeys its farm-facing CLI, for the driver's tests.

Scenes are JSON files: {"width", "height", "cameras", "animated", "frame_range", "fps",
"sleep" (seconds per render), "fail" (a render error message)}. An "image" is a header line
`FAKE X0 Y0 X1 Y1 W H` and one byte per pixel derived from (scene, frame, camera, x, y), so
a merge of any split is byte-identical to the full render, and the output is written slowly
in two halves (a reader that does not wait for the rename sees a torn file).
"""
import hashlib
import json
import os
import sys
import time


def die(msg):
    print(f"zigzag: error: {msg}", file=sys.stderr)
    sys.exit(1)


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        die(f"{path}: {e}")


def opt(args, name, default=None):
    if name in args:
        i = args.index(name)
        return args[i + 1]
    return default


def info(args):
    out = []
    for path in [a for a in args if not a.startswith("-")]:
        s = load(path)
        out.append({"name": os.path.splitext(os.path.basename(path))[0], "width": s["width"],
                    "height": s["height"], "cameras": s.get("cameras", 1), "fps": s.get("fps", 24),
                    "frame_range": s.get("frame_range"), "animated": s.get("animated", False),
                    "triangles": 12, "lights": 1})
    print(json.dumps(out if len(out) > 1 else out[0]))


def pixel(seed, x, y):
    return hashlib.blake2b(f"{seed}:{x}:{y}".encode(), digest_size=1).digest()


def render(args):
    scene = args[0]
    s = load(scene)
    if s.get("fail"):
        die(f"{scene}: {s['fail']}")
    w = int(opt(args, "--width", s["width"]))
    h = int(opt(args, "--height", s["height"]))
    x0, y0, x1, y1 = map(int, opt(args, "--region", f"0,0,{w},{h}").split(","))
    seed = f"{json.dumps(s, sort_keys=True)}:{opt(args, '--frame')}:{opt(args, '--camera', '0')}"
    out = opt(args, "-o")
    body = b"".join(pixel(seed, x, y) for y in range(y0, y1) for x in range(x0, x1))
    data = f"FAKE {x0} {y0} {x1} {y1} {w} {h}\n".encode() + body
    with open(out, "wb") as f:
        f.write(data[: len(data) // 2])
        f.flush()
        time.sleep(float(os.environ.get("FAKE_ZIGZAG_SLEEP", s.get("sleep", 0.0))))
        f.write(data[len(data) // 2:])
    stats = opt(args, "--stats")
    if stats:
        px = (x1 - x0) * (y1 - y0)
        with open(stats, "w") as f:
            json.dump({"scene": os.path.splitext(os.path.basename(scene))[0], "width": w, "height": h,
                       "rays": {"primary": px, "total": 2 * px}, "rays_per_pixel": 1.0 + x0 / w,
                       "time_s": {"render": 0.01, "total": 0.02}}, f)


def merge(args):
    out = opt(args, "-o")
    parts = [a for a in args if a != "-o" and a != out]
    canvas = None
    for p in parts:
        with open(p, "rb") as f:
            header, body = f.read().split(b"\n", 1)
        _, x0, y0, x1, y1, w, h = header.split()
        x0, y0, x1, y1, w, h = map(int, (x0, y0, x1, y1, w, h))
        if canvas is None:
            canvas, size = [None] * (w * h), (w, h)
        for i, b in enumerate(body):
            x, y = x0 + i % (x1 - x0), y0 + i // (x1 - x0)
            if canvas[y * w + x] is not None:
                die(f"{p}: pixel {x},{y} is in two parts")
            canvas[y * w + x] = bytes([b])
    if canvas is None or any(c is None for c in canvas):
        die("the parts do not cover the frame")
    with open(out, "wb") as f:
        f.write(f"FAKE 0 0 {size[0]} {size[1]} {size[0]} {size[1]}\n".encode() + b"".join(canvas))


if __name__ == "__main__":
    cmd, rest = sys.argv[1], sys.argv[2:]
    {"info": info, "render": render, "merge": merge}.get(cmd, lambda a: die(f"unknown command {cmd}"))(rest)
