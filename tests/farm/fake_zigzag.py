#!/usr/bin/env python3
"""A stand-in for the zigzag binary that obeys its farm-facing CLI, for the driver's tests.

Scenes are JSON files: {"width", "height", "cameras", "camera_names" (default camera0,
camera1, ...), "animated", "frame_range", "fps",
"sleep" (seconds per render), "fail" (a render error message), "refuse" (a usage error found
once the scene is loaded, exit code 105), "camera_aspects" (width /
height per camera: a side not given by --width/--height follows it, as zigzag's cameras do),
"files" (more files the scene reads, relative to it: their bytes go into the image),
"needs_assets" (a file that must be in --assets DIR)}. An "image" is a header line
`FAKE X0 Y0 X1 Y1 W H` and one byte per pixel derived from (scene, its files, frame, camera,
x, y), so a merge of any split is byte-identical to the full render, and the output is
written slowly in two halves (a reader that does not wait for the rename sees a torn file).
-o and --stats are patterns as zigzag's ({scene}, {camera}, {frame}, {frame:N}; anything else
refused, exit code 105). -o must have an image extension zigzag writes, an `--aov NAME` without a file an .exr -o (exit
105); `render --dry-run` makes those checks and that the scene exists, then exits writing
nothing. Options take `--x v` or `--x=v`; one given twice or out of range is a usage error, exit code
105/114 as zigzag's CLI11. $FAKE_ZIGZAG_LOG: a file each render appends its arguments to;
$FAKE_ZIGZAG_DRY_RUN_LOG: the same for `render --dry-run`.
"""
import hashlib
import json
import os
import sys
import time


def die(msg, code=1):
    print(f"zigzag: error: {msg}", file=sys.stderr)
    sys.exit(code)


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        die(f"{path}: {e}")


VALUED = {"-o", "--stats", "--width", "--height", "--region", "--frame", "--camera", "--fps",
          "--assets", "--threads", "--eps"}


def opt(args, name, default=None):
    values = [args[i + 1] for i, a in enumerate(args[:-1]) if a == name]
    values += [a.split("=", 1)[1] for a in args if a.startswith(name + "=")]
    if len(values) > 1:
        die(f"{name}: At Most 1 required but received {len(values)}", 114)
    return values[0] if values else default


def int_opt(args, name, default, least=1):
    text = opt(args, name)
    if text is None:
        return default
    if not text.isdigit() or int(text) < least:
        die(f"{name}: Value {text} not in range {least} to 16384", 105)
    return int(text)


def positionals(args):
    out, skip = [], False
    for a in args:
        if skip:
            skip = False
        elif a in VALUED:
            skip = True
        elif not a.startswith("-"):
            out.append(a)
    return out


def extra_files(path, s):
    folder = os.path.dirname(path)
    return [os.path.join(folder, f) for f in s.get("files", [])]


def check_assets(path, s, args):
    need = s.get("needs_assets")
    if need and not os.path.exists(os.path.join(opt(args, "--assets", "/nonexistent"), need)):
        die(f"{path}: {need} not found (no --assets DIR with it)")


def camera_size(s, camera, args):
    """zigzag's rule: --width/--height as given, a side left out follows the camera's aspect."""
    w, h = int_opt(args, "--width", None), int_opt(args, "--height", None)
    aspects = s.get("camera_aspects")
    if aspects is None:
        return w or s["width"], h or s["height"]
    aspect = aspects[camera]
    if w and h:
        return w, h
    if h:
        return max(1, round(h * aspect)), h
    w = w or s["width"]
    return w, max(1, round(w / aspect))


def info(args):
    out = []
    for path in positionals(args):
        s = load(path)
        check_assets(path, s, args)
        cameras = s.get("cameras", 1)
        sizes = [camera_size(s, c, args) for c in range(cameras)]
        names = s.get("camera_names", [f"camera{c}" for c in range(cameras)])
        fps = float(opt(args, "--fps", s.get("fps", 24)))
        out.append({"name": os.path.splitext(os.path.basename(path))[0], "width": sizes[0][0],
                    "height": sizes[0][1], "camera_sizes": sizes, "cameras": names,
                    "camera_count": cameras, "fps": fps,
                    "frame_range": s.get("frame_range"), "animated": s.get("animated", False),
                    "files": [path] + extra_files(path, s), "triangles": 12, "lights": 1})
    print(json.dumps(out if len(out) > 1 else out[0]))


def expand(pattern, option, scene, camera, frame):
    """host/app/output_paths.cpp expand_output_pattern: '{' up to the next '}', no escape."""
    out, i = "", 0
    while i < len(pattern):
        if pattern[i] != "{":
            out, i = out + pattern[i], i + 1
            continue
        close = pattern.find("}", i)
        body = pattern[i + 1:close] if close >= 0 else None
        width = body[6:] if body and body.startswith("frame:") else ""
        if body in ("scene", "camera", "frame"):
            out += {"scene": scene, "camera": camera, "frame": str(frame)}[body]
        elif 1 <= len(width) <= 2 and all(c in "0123456789" for c in width):
            out += str(frame).rjust(int(width), "0")
        else:
            bad = pattern[i:] if close < 0 else pattern[i:close + 1]
            die(f"{option} {pattern}: unknown placeholder '{bad}' (known: {{scene}}, {{camera}}, {{frame}}, "
                "{frame:04})", 105)
        i = close + 1
    return out


FORMATS = (".png", ".exr", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".tga", ".webp", ".hdr")


def check_output(out, args):
    """zigzag's preflight_output and validate(): the format from the extension, AOV layers in .exr."""
    ext = os.path.splitext(out)[1].lower()
    if not ext:
        die(f"-o {out}: no file extension to choose the format (use .png or .exr)", 105)
    if ext not in FORMATS:
        die(f"-o {out}: unsupported image format '{ext}' (use .png or .exr; .jpg, .tif, .bmp, .tga, .webp, .hdr "
            "also work)", 105)
    for i, a in enumerate(args):
        name = a.split("=", 1)[1] if a.startswith("--aov=") else args[i + 1] if a == "--aov" and i + 1 < len(args) else None
        at = i + (1 if a.startswith("--aov=") else 2)
        if name is not None and (at >= len(args) or args[at].startswith("-")) and ext != ".exr":
            die(f"--aov {name} without a file adds channels to the -o image, which must be an .exr (-o {out})", 105)


def pixel(seed, x, y):
    return hashlib.blake2b(f"{seed}:{x}:{y}".encode(), digest_size=1).digest()


def render(args):
    log = os.environ.get("FAKE_ZIGZAG_DRY_RUN_LOG" if "--dry-run" in args else "FAKE_ZIGZAG_LOG")
    if log:
        with open(log, "a") as f:
            f.write(json.dumps(args) + "\n")
    dry_run = "--dry-run" in args
    args = [a for a in args if a != "--dry-run"]
    scene = args[0]
    key = (os.path.splitext(os.path.basename(scene))[0], opt(args, "--camera", "0"), int(opt(args, "--frame", "0")))
    out = expand(opt(args, "-o"), "-o", *key)
    stats = opt(args, "--stats")
    stats = expand(stats, "--stats", *key) if stats else None
    eps = opt(args, "--eps")
    if eps is not None and not 0 <= float(eps) <= 1:
        die(f"--eps: Value {eps} not in range 0 to 1", 105)
    int_opt(args, "--threads", 0, least=0)
    check_output(out, args)
    if dry_run:
        if not os.path.exists(scene):
            die(f"{scene}: no such file")
        return
    s = load(scene)
    if s.get("refuse"):  # options refused once the scene is loaded (--dry-run loads nothing)
        die(s["refuse"], 105)
    if s.get("fail"):
        die(f"{scene}: {s['fail']}")
    check_assets(scene, s, args)
    camera = int(opt(args, "--camera", "0"))
    w, h = camera_size(s, camera, args)
    x0, y0, x1, y1 = map(int, opt(args, "--region", f"0,0,{w},{h}").split(","))
    contents = []
    for path in extra_files(scene, s):
        try:
            with open(path, "rb") as f:
                contents.append(hashlib.sha256(f.read()).hexdigest())
        except OSError as e:
            die(f"{path}: {e}")
    seed = f"{json.dumps(s, sort_keys=True)}:{contents}:{opt(args, '--frame')}:{camera}"
    body = b"".join(pixel(seed, x, y) for y in range(y0, y1) for x in range(x0, x1))
    data = f"FAKE {x0} {y0} {x1} {y1} {w} {h}\n".encode() + body
    with open(out, "wb") as f:
        f.write(data[: len(data) // 2])
        f.flush()
        time.sleep(float(os.environ.get("FAKE_ZIGZAG_SLEEP", s.get("sleep", 0.0))))
        f.write(data[len(data) // 2:])
    if stats:
        px = (x1 - x0) * (y1 - y0)
        with open(stats, "w") as f:
            json.dump({"scene": os.path.splitext(os.path.basename(scene))[0], "width": w, "height": h,
                       "pixels": px, "rays": {"primary": px, "total": 2 * px},
                       "rays_per_pixel": 1.0 + x0 / w, "time_s": {"render": 0.01, "total": 0.02}}, f)


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
