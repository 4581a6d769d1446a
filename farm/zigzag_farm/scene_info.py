"""Asking the renderer about a scene: `zigzag info SCENE --json` -> SceneInfo."""
from __future__ import annotations

import json
import os
import subprocess
from concurrent.futures import ThreadPoolExecutor

from .plan import SceneInfo


class SceneError(RuntimeError):
    pass


class InfoUsageError(SceneError):
    """zigzag info refused the options it was given (the render's --width, --fps, ...)."""


def _frame_range(d: dict) -> tuple[int, int] | None:
    for key in ("frame_range", "frames"):
        v = d.get(key)
        if isinstance(v, (list, tuple)) and len(v) == 2:
            return int(v[0]), int(v[1])
        if isinstance(v, dict) and "first" in v and "last" in v:
            return int(v["first"]), int(v["last"])
    if "frame_start" in d and "frame_end" in d:
        return int(d["frame_start"]), int(d["frame_end"])
    return None


def _camera_sizes(d: dict, cameras: int) -> tuple[tuple[int, int], ...]:
    sizes = d.get("camera_sizes")
    if not isinstance(sizes, list):
        return ()
    if len(sizes) != cameras:
        raise ValueError(f"{len(sizes)} camera_sizes for {cameras} camera(s)")
    return tuple((int(w), int(h)) for w, h in sizes)


def parse_info(path: str, d: dict) -> SceneInfo:
    """A scene's info as `zigzag info --json` gives it, asked with the batch's --width/--height
    (so its sizes are the ones `zigzag render` will use)."""
    cameras = d.get("camera_count", d.get("cameras", 1))
    listed = d.get("cameras")
    names = tuple(str(n) for n in listed) if isinstance(listed, list) else ()
    if isinstance(cameras, list):
        cameras = len(cameras)
    if names and len(names) != int(cameras):
        raise ValueError(f"{len(names)} camera names for {cameras} camera(s)")
    # Relative paths in "files" are relative to where info ran: this process's folder.
    files = tuple(os.path.abspath(f) for f in d.get("files", ()) or ())
    return SceneInfo(path=path, name=os.path.splitext(os.path.basename(path))[0],
                     width=int(d["width"]), height=int(d["height"]), cameras=int(cameras),
                     camera_names=names, animated=bool(d.get("animated", False)), fps=float(d.get("fps") or 24.0),
                     frame_range=_frame_range(d), camera_sizes=_camera_sizes(d, int(cameras)),
                     files=files or (os.path.abspath(path),))


def scene_info(zigzag: str, path: str, info_args: list[str] = (), timeout: float = 300.0) -> SceneInfo:
    """One scene's info. info_args: the render options `zigzag info` takes too (--width,
    --height, --fps, --assets), so the sizes and files are those of the render."""
    try:
        p = subprocess.run([zigzag, "info", path, "--json", *info_args], capture_output=True,
                           text=True, timeout=timeout, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise SceneError(f"{path}: zigzag info failed: {e}") from None
    if p.returncode != 0:
        # The error lines (not the warnings before them), else what there is without CLI11's
        # "Run with --help" line that follows an option's error.
        lines = [line for line in p.stderr.strip().splitlines()
                 if line.strip() and not line.startswith("Run with --help")]
        errors = [line for line in lines if line.startswith("zigzag: error:")]
        msg = " ".join(errors or lines) or f"{path}: zigzag info exit code {p.returncode}"
        # 100-127: the options were refused (CLI11's codes; zigzag's usage exit is 105), for
        # every scene alike: bad options, not a scene that fails to load.
        raise (InfoUsageError if 100 <= p.returncode <= 127 else SceneError)(msg)
    try:
        d = json.loads(p.stdout)
        if isinstance(d, list):
            d = d[0]
        if isinstance(d, dict) and d.get("error"):
            raise SceneError(f"{path}: {d['error']}")
        return parse_info(path, d)
    except (ValueError, KeyError, IndexError, TypeError) as e:
        raise SceneError(f"{path}: cannot read zigzag info --json output ({e})") from None


def scene_infos(zigzag: str, paths: list[str], info_args: list[str] = ()):
    """[(path, SceneInfo or SceneError)] in order, asked in parallel."""
    def one(path):
        try:
            return path, scene_info(zigzag, path, info_args)
        except SceneError as e:
            return path, e
    with ThreadPoolExecutor(max_workers=min(8, max(1, len(paths)))) as pool:
        return list(pool.map(one, paths))
