"""Asking the renderer about a scene: `zigzag info SCENE --json` -> SceneInfo."""
from __future__ import annotations

import json
import os
import subprocess
from concurrent.futures import ThreadPoolExecutor

from .plan import SceneInfo


class SceneError(RuntimeError):
    pass


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


def parse_info(path: str, d: dict, width: int | None = None, height: int | None = None) -> SceneInfo:
    cameras = d.get("cameras", 1)
    if isinstance(cameras, list):
        cameras = len(cameras)
    return SceneInfo(path=path, name=os.path.splitext(os.path.basename(path))[0],
                     width=int(width or d["width"]), height=int(height or d["height"]),
                     cameras=int(cameras), animated=bool(d.get("animated", False)),
                     fps=float(d.get("fps") or 24.0), frame_range=_frame_range(d))


def scene_info(zigzag: str, path: str, width: int | None = None, height: int | None = None,
               timeout: float = 300.0) -> SceneInfo:
    """One scene's info; width/height override the scene's (the render's --width/--height)."""
    try:
        p = subprocess.run([zigzag, "info", path, "--json"], capture_output=True, text=True,
                           timeout=timeout, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise SceneError(f"{path}: zigzag info failed: {e}") from None
    if p.returncode != 0:
        msg = p.stderr.strip().splitlines()
        raise SceneError(msg[-1] if msg else f"{path}: zigzag info exit code {p.returncode}")
    try:
        d = json.loads(p.stdout)
        if isinstance(d, list):
            d = d[0]
        return parse_info(path, d, width, height)
    except (ValueError, KeyError, IndexError, TypeError) as e:
        raise SceneError(f"{path}: cannot read zigzag info --json output ({e})") from None


def scene_infos(zigzag: str, paths: list[str], width=None, height=None):
    """[(path, SceneInfo or SceneError)] in order, asked in parallel."""
    def one(path):
        try:
            return path, scene_info(zigzag, path, width, height)
        except SceneError as e:
            return path, e
    with ThreadPoolExecutor(max_workers=min(8, max(1, len(paths)))) as pool:
        return list(pool.map(one, paths))
