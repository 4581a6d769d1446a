"""Job planning: which (scene, frame, camera, region) jobs a batch needs, and their keys.

A job's key is derived from everything that decides its output bytes, so the same batch
planned twice (a re-run after the driver died) gets the same keys and Dask deduplicates a
job submitted twice while it is still known to the scheduler.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import string
from dataclasses import dataclass, field

from .regions import Region, split_frame

_FRAMES = re.compile(r"^\s*(-?\d+)\s*(?:-\s*(-?\d+)\s*(?:x\s*(\d+)\s*)?)?$")


def parse_frames(text: str) -> list[int]:
    """`A`, `A-B` or `A-BxS` (inclusive, step S >= 1) -> the frame numbers, ascending."""
    m = _FRAMES.match(text)
    if not m:
        raise ValueError(f"--frames {text!r}: expected A, A-B or A-BxS (e.g. 1-48x2)")
    first = int(m.group(1))
    last = int(m.group(2)) if m.group(2) is not None else first
    step = int(m.group(3)) if m.group(3) is not None else 1
    if step < 1:
        raise ValueError(f"--frames {text!r}: the step must be at least 1")
    if last < first:
        raise ValueError(f"--frames {text!r}: the last frame comes before the first")
    return list(range(first, last + 1, step))


@dataclass(frozen=True)
class SceneInfo:
    """What `zigzag info SCENE --json` says about a scene (only what planning needs)."""

    path: str
    name: str
    width: int
    height: int
    cameras: int
    animated: bool = False
    fps: float = 24.0
    frame_range: tuple[int, int] | None = None


@dataclass(frozen=True)
class RenderJob:
    """One `zigzag render` call: a whole frame, or one region of it (a part to merge)."""

    key: str
    scene: str
    scene_name: str
    frame: int | None
    camera: int
    region: Region | None
    output: str  # the final path of this job's image (a part in the work folder for regions)
    args: tuple[str, ...] = ()


@dataclass(frozen=True)
class FrameJob:
    """One output image: either a single render job, or region parts and their merge."""

    key: str
    output: str
    stats: str | None
    scene_name: str
    frame: int | None
    camera: int
    parts: tuple[RenderJob, ...]
    merged: bool  # True: the parts are merged into `output` by `zigzag merge`


@dataclass
class Plan:
    frames: list[FrameJob] = field(default_factory=list)

    @property
    def render_jobs(self) -> list[RenderJob]:
        return [p for f in self.frames for p in f.parts]


def pattern_fields(pattern: str) -> set[str]:
    return {name for _, name, _, _ in string.Formatter().parse(pattern) if name}


def expand(pattern: str, scene: str, camera: int, frame: int | None) -> str:
    """Replace {scene}, {camera}, {frame} and {frame:04}-style widths in an output pattern."""
    unknown = pattern_fields(pattern) - {"scene", "camera", "frame"}
    if unknown:
        raise ValueError(f"output pattern {pattern!r}: unknown field(s) {sorted(unknown)}; "
                         "use {scene}, {camera}, {frame} or {frame:04}")
    return pattern.format(scene=scene, camera=camera, frame=frame if frame is not None else 0)


def _digest(payload: dict) -> str:
    blob = json.dumps(payload, sort_keys=True, separators=(",", ":")).encode()
    return hashlib.sha256(blob).hexdigest()[:12]


def _frame_tag(frame: int | None) -> str:
    return "still" if frame is None else f"f{frame}"


def plan_batch(scenes: list[SceneInfo], output: str, *, frames: list[int] | None, camera: str,
               regions: int, work_dir: str, stats: str | None = None,
               args: tuple[str, ...] = (), fingerprint: str = "") -> Plan:
    """Every output image of the batch and the render jobs that make it.

    frames=None: each animated scene's own frame range, a still for the others.
    camera: an index or "all". regions > 1 splits each image into parts merged afterwards.
    fingerprint: whatever else decides the bytes (the renderer binary, scene contents).
    """
    plan = Plan()
    seen: dict[str, str] = {}
    for info in scenes:
        if camera == "all":
            cameras = list(range(info.cameras))
        else:
            index = int(camera)
            if not 0 <= index < info.cameras:
                raise ValueError(f"{info.path}: --camera {camera} does not exist "
                                 f"(the scene has {info.cameras} camera(s))")
            cameras = [index]
        if frames is not None:
            scene_frames: list[int | None] = list(frames)
        elif info.animated and info.frame_range is not None:
            scene_frames = list(range(info.frame_range[0], info.frame_range[1] + 1))
        else:
            scene_frames = [None]
        for frame in scene_frames:
            for cam in cameras:
                out = os.path.abspath(expand(output, info.name, cam, frame))
                what = f"{info.name} camera {cam} {_frame_tag(frame)}"
                if out in seen:
                    raise ValueError(f"output pattern {output!r} writes {out} for both {seen[out]} "
                                     f"and {what}: add {{scene}}, {{camera}} or {{frame}}")
                seen[out] = what
                stats_out = os.path.abspath(expand(stats, info.name, cam, frame)) if stats else None
                identity = {"scene": os.path.abspath(info.path), "frame": frame, "camera": cam,
                            "args": list(args), "fingerprint": fingerprint,
                            "size": [info.width, info.height]}
                frame_key = f"zz-frame-{info.name}-{_frame_tag(frame)}-c{cam}-{_digest({**identity, 'output': out})}"
                parts = []
                split = split_frame(info.width, info.height, regions) if regions > 1 else [None]
                for i, region in enumerate(split):
                    if region is None:
                        part_out = out
                        tag = "full"
                    else:
                        tag = f"r{i}of{len(split)}"
                        part_out = os.path.join(
                            work_dir, f"{info.name}-{_frame_tag(frame)}-c{cam}-{tag}-"
                                      f"{_digest({**identity, 'region': region.bounds})}.exr")
                    payload = {**identity, "output": part_out,
                               "region": region.bounds if region else None}
                    parts.append(RenderJob(
                        key=f"zz-render-{info.name}-{_frame_tag(frame)}-c{cam}-{tag}-{_digest(payload)}",
                        scene=os.path.abspath(info.path), scene_name=info.name, frame=frame,
                        camera=cam, region=region, output=part_out, args=tuple(args)))
                plan.frames.append(FrameJob(key=frame_key, output=out, stats=stats_out,
                                            scene_name=info.name, frame=frame, camera=cam,
                                            parts=tuple(parts), merged=regions > 1))
    return plan
