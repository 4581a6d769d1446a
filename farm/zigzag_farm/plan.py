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
from dataclasses import dataclass, field

from .job import plain_name
from .regions import Region, split_frame

_FRAMES = re.compile(r"^\s*(-?\d+)\s*(?:-\s*(-?\d+)\s*(?:x\s*(\d+)\s*)?)?$")
# More jobs than this is a typo (--frames 0-99999999), not a batch: refuse it before the plan
# (a few hundred bytes per job) takes gigabytes.
MAX_JOBS = 1_000_000


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
    count = (last - first) // step + 1
    if count > MAX_JOBS:
        raise ValueError(f"--frames {text!r}: {count} frames, more than a batch may have ({MAX_JOBS})")
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
    camera_names: tuple[str, ...] = ()  # as `zigzag info` lists them, for --camera NAME
    fps: float = 24.0
    frame_range: tuple[int, int] | None = None
    # Each camera's (width, height) as `zigzag render` sizes its frame with the batch's
    # --width/--height (a side left out follows the camera's aspect); empty: (width, height).
    camera_sizes: tuple[tuple[int, int], ...] = ()
    files: tuple[str, ...] = ()  # every file the scene is read from (rig, glTF, buffers, images)
    content: str = ""  # a digest of those files' contents: an edit to any of them re-renders

    def size(self, camera: int) -> tuple[int, int]:
        if camera < len(self.camera_sizes):
            return self.camera_sizes[camera]
        return self.width, self.height


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
class PartNames:
    """How the region parts of one frame's output are named in the work folder, for any
    region count: a run tells apart, and removes, the parts that an interrupted run with
    another --regions left (gigabytes for a large frame, in a hidden folder)."""

    folder: str
    prefix: str  # "{scene}-{frame}-c{camera}"
    width: int
    height: int
    identity: str  # what decides the bytes, the output too: canonical JSON

    def path(self, index: int, count: int, region: Region) -> str:
        digest = _digest({**json.loads(self.identity), "region": region.bounds})
        return os.path.join(self.folder, f"{self.prefix}-{part_tag(index, count)}-{digest}.exr")

    def index_and_count(self, name: str) -> tuple[int, int] | None:
        """(index, count) of a file name this frame's parts could have, for a count a batch
        may split it into; None for any other name."""
        if not name.startswith(self.prefix + "-r"):  # most names: no regex
            return None
        m = re.fullmatch(re.escape(self.prefix) + r"-r([0-9]+)of([0-9]+)-[0-9a-f]{12}\.exr", name)
        if not m or len(m[2]) > 7:
            return None
        index, count = int(m[1]), int(m[2])
        return (index, count) if index < count <= min(self.width * self.height, MAX_JOBS) else None


def part_tag(index: int, count: int) -> str:
    return f"r{index}of{count}"


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
    part_names: PartNames | None = None


def _file_identity(path: str) -> tuple[int, int] | None:
    """(device, inode): the same file under any name, links included; None if missing."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_dev, st.st_ino


@dataclass
class Plan:
    frames: list[FrameJob] = field(default_factory=list)
    # Every file the batch writes -> what it is ("the image of room camera 0 f3"): no two
    # outputs of any kind (images, stats, region parts, summary, manifest) may share a path.
    claims: dict[str, str] = field(default_factory=dict)
    # The files the batch's scenes are read from (rigs, glTFs, buffers, images), by identity
    # (device, inode) -> "scene room": no output may replace one, whichever scene it is.
    inputs: dict[tuple[int, int], str] = field(default_factory=dict)

    def add_inputs(self, info) -> None:
        for f in info.files:
            if (identity := _file_identity(f)) is not None:
                self.inputs.setdefault(identity, f"{f}, a file of scene {info.name}")

    @property
    def render_jobs(self) -> list[RenderJob]:
        return [p for f in self.frames for p in f.parts]

    def claim(self, path: str, what: str, hint: str = "") -> None:
        """Reserve path for one output; a second claim is a usage error naming both."""
        name = plain_name(os.path.basename(path))  # as in the temporaries' names
        if len(os.fsencode(name)) > MAX_OUTPUT_NAME:
            escaped = " (each '{', '}' or '%' counts 3)" if name != os.path.basename(path) else ""
            raise ValueError(f"{path} ({what}): its name is {len(os.fsencode(name))} bytes; the farm takes at most "
                             f"{MAX_OUTPUT_NAME}, as its temporaries (and zigzag's) add a host tag to it within the "
                             f"file system's 255{escaped}")
        if path in self.claims:
            raise ValueError(f"{path} would be written as both {self.claims[path]} and {what}"
                             + (f": {hint}" if hint else ""))
        source = self.inputs.get(_file_identity(path))  # none yet: no scene is read from it
        if source:
            raise ValueError(f"{path} ({what}) is {source}: writing it would replace the scene")
        self.claims[path] = what


# The longest output file name: a job writes ".NAME.HOST-PID-UUID8.tmp.EXT" (HOST at most
# job.MAX_TAG_HOST bytes) and its stats, ".stats.json" more, and zigzag's temporary of that
# adds "." and ".zz-PID-RANDOM16-N": 87 bytes beside NAME with 7-digit PIDs and a 3-digit N,
# 242 in all, so zigzag never cuts the name (a cut loses the extension the farm's cleanup
# tells outputs apart by; tests/farm/test_runner.py).
MAX_OUTPUT_NAME = 155


KNOWN_PLACEHOLDERS = "{scene}, {camera}, {frame}, {frame:04}"


def _placeholder(body: str, scene: str, camera: int, frame: int) -> str | None:
    """One "{...}" body as the renderer expands it (host/app/output_paths.cpp
    expand_placeholder), or None if it is not one it knows: {frame:N} pads with zeros to N,
    one or two digits; no other format spec."""
    if body == "scene":
        return scene
    if body == "camera":
        return str(camera)
    if body == "frame":
        return str(frame)
    if body.startswith("frame:"):
        width = body[len("frame:"):]
        if 1 <= len(width) <= 2 and all(c in "0123456789" for c in width):
            digits = str(frame)
            return "0" * max(0, int(width) - len(digits)) + digits
    return None


def expand(pattern: str, scene: str, camera: int, frame: int | None, option: str = "-o") -> str:
    """An output pattern expanded exactly as `zigzag render` expands it (expand_output_pattern):
    a '{' starts a placeholder up to the next '}' (no escape); {scene}, {camera}, {frame} and
    {frame:N}; anything else is refused with the renderer's message. A still is frame 0."""
    out, i = [], 0
    while i < len(pattern):
        if pattern[i] != "{":
            out.append(pattern[i])
            i += 1
            continue
        close = pattern.find("}", i)
        value = None if close < 0 else _placeholder(pattern[i + 1:close], scene, camera,
                                                    frame if frame is not None else 0)
        if value is None:
            bad = pattern[i:] if close < 0 else pattern[i:close + 1]
            raise ValueError(f"{option} {pattern}: unknown placeholder '{bad}' (known: {KNOWN_PLACEHOLDERS})")
        out.append(value)
        i = close + 1
    return "".join(out)


def _check_folder_has_no_braces(path: str, what: str) -> None:
    """A file the renderer writes is passed to it in a folder zigzag takes as a pattern: a
    brace there (a scene named shot{camera} in {scene}/, a --work-dir) would be expanded."""
    folder = os.path.dirname(path)
    if "{" in folder or "}" in folder:
        raise ValueError(f"{path} ({what}): its folder {folder} has '{{' or '}}', which zigzag expands "
                         "as placeholders (with no escape): use a folder without braces")


def _digest(payload: dict) -> str:
    blob = json.dumps(payload, sort_keys=True, separators=(",", ":")).encode()
    return hashlib.sha256(blob).hexdigest()[:12]


def _frame_tag(frame: int | None) -> str:
    return "still" if frame is None else f"f{frame}"


@dataclass(frozen=True)
class _Image:
    """Which image of the batch an output belongs to (for collision messages)."""

    scene: SceneInfo
    camera: int
    frame: int | None

    def __str__(self) -> str:
        return f"{self.scene.name} camera {self.camera} {_frame_tag(self.frame)}"


def _tell_apart(a: _Image, b: _Image, option: str) -> str:
    """What the pattern of `option` lacks to give images a and b different paths."""
    if a.scene.name == b.scene.name and a.scene.path != b.scene.path:
        return (f"the scenes {a.scene.path} and {b.scene.path} are both named "
                f"{a.scene.name!r}, so {{scene}} cannot tell them apart: render them in separate "
                f"runs with different {option} folders, or rename one")
    missing = [f"{{{name}}}" for name, differs in (("scene", a.scene.name != b.scene.name),
                                                  ("camera", a.camera != b.camera),
                                                  ("frame", a.frame != b.frame)) if differs]
    return f"add {' or '.join(missing)} to {option}"


def _scene_frames(info: SceneInfo, frames: list[int] | None):
    """The frames to render of a scene (a range, so that counting a long one costs nothing)."""
    if frames is not None:
        return frames
    if info.animated and info.frame_range is not None:
        return range(info.frame_range[0], info.frame_range[1] + 1)
    return [None]


def _scene_cameras(info: SceneInfo, camera: str) -> list[int]:
    """The cameras `--camera` picks in this scene, by zigzag render's rule (find_camera in
    host/scene/camera_select.cpp): all, an index when it is all digits, else a unique name."""
    if camera == "all":
        return list(range(info.cameras))
    if camera.isascii() and camera.isdigit():
        index = int(camera) if len(camera) <= 9 else info.cameras  # as find_camera reads it
        if not 0 <= index < info.cameras:
            raise ValueError(f"{info.path}: --camera {camera} does not exist "
                             f"(the scene has {info.cameras} camera(s))")
        return [index]
    named = [i for i, name in enumerate(info.camera_names) if name == camera]
    if len(named) == 1:
        return named
    if named:  # the renderer refuses it too: the batch must not pick one of them for the user
        raise ValueError(f"{info.path}: camera name '{camera}' is ambiguous: cameras "
                         f"{', '.join(map(str, named))} have it (give an index, --camera {named[0]})")
    names = ", ".join(f"{i} '{name}'" for i, name in enumerate(info.camera_names))
    raise ValueError(f"{info.path}: no camera named '{camera}' (cameras: {names or 'no names known'})")


def _check_job_count(scenes: list[SceneInfo], frames, camera: str, regions: int) -> None:
    total = 0
    for info in scenes:
        n_cameras = info.cameras if camera == "all" else 1
        total += len(_scene_frames(info, frames)) * n_cameras * (regions + (regions > 1))  # + the merge
    if total > MAX_JOBS:
        raise ValueError(f"the batch would have {total} jobs, more than a batch may have "
                         f"({MAX_JOBS}): fewer frames, cameras or regions")


def plan_batch(scenes: list[SceneInfo], output: str, *, frames: list[int] | None, camera: str,
               regions: int, work_dir: str, stats: str | None = None,
               args: tuple[str, ...] = (), fingerprint: str = "") -> Plan:
    """Every output image of the batch and the render jobs that make it.

    frames=None: each animated scene's own frame range, a still for the others.
    camera: an index, a camera's name or "all". regions > 1 splits each image into parts merged afterwards.
    args: the render options that decide the bytes (not --threads: any thread count renders
    the same bits, so it stays out of the keys). fingerprint: the renderer binary; each
    scene's own files are in its SceneInfo.content.
    """
    _check_job_count(scenes, frames, camera, regions)
    seen: dict[str, str] = {}
    for info in scenes:  # one file twice (as given, or by two paths): every image twice
        real = os.path.realpath(info.path)
        if real in seen:
            raise ValueError(f"{info.path}: the scene is given twice"
                             + (f" (also as {seen[real]})" if seen[real] != info.path else "")
                             + "; give it once")
        seen[real] = info.path
    plan = Plan()
    for info in scenes:
        plan.add_inputs(info)
    first_image: dict[str, tuple] = {}  # output path -> (the image, the option) that claimed it
    for info in scenes:
        cameras = _scene_cameras(info, camera)
        for frame in _scene_frames(info, frames):
            for cam in cameras:
                image = _Image(info, cam, frame)
                out = os.path.abspath(expand(output, info.name, cam, frame, "-o"))
                stats_out = os.path.abspath(expand(stats, info.name, cam, frame, "--stats")) if stats else None
                for path, kind, option in ((out, "the image", "-o"), (stats_out, "the stats", "--stats")):
                    if path is None:
                        continue
                    other = first_image.get(path)
                    if other is None:
                        hint = ""
                    elif other[1] != option:
                        hint = "-o and --stats must name different files"
                    else:
                        hint = _tell_apart(other[0], image, option)
                    _check_folder_has_no_braces(path, f"{kind} of {image}")
                    plan.claim(path, f"{kind} of {image}", hint)
                    first_image[path] = (image, option)
                plan.frames.append(_frame_job(info, cam, frame, out, stats_out, regions, work_dir,
                                              args, fingerprint, plan))
    return plan


def _frame_job(info: SceneInfo, cam: int, frame: int | None, out: str, stats_out: str | None,
               regions: int, work_dir: str, args: tuple[str, ...], fingerprint: str,
               plan: Plan) -> FrameJob:
    width, height = info.size(cam)
    identity = {"scene": os.path.abspath(info.path), "frame": frame, "camera": cam,
                "args": list(args), "fingerprint": fingerprint, "content": info.content,
                "size": [width, height]}
    tag_base = f"{info.name}-{_frame_tag(frame)}-c{cam}"
    frame_key = f"zz-frame-{tag_base}-{_digest({**identity, 'output': out})}"
    # The frame's output in the part names too: two batches of one frame into one folder
    # (a PNG and an EXR) would otherwise share, and delete, each other's parts.
    names = PartNames(work_dir, tag_base, width, height, json.dumps({**identity, "output": out}, sort_keys=True))
    parts = []
    split = split_frame(width, height, regions) if regions > 1 else [None]
    for i, region in enumerate(split):
        if region is None:
            part_out, tag = out, "full"
        else:
            tag = part_tag(i, len(split))
            part_out = names.path(i, len(split), region)
            _check_folder_has_no_braces(part_out, "--work-dir")
            plan.claim(part_out, f"region part {i} of {info.name} camera {cam} {_frame_tag(frame)}")
        payload = {**identity, "output": part_out, "region": region.bounds if region else None}
        parts.append(RenderJob(key=f"zz-render-{tag_base}-{tag}-{_digest(payload)}",
                               scene=os.path.abspath(info.path), scene_name=info.name,
                               frame=frame, camera=cam, region=region, output=part_out,
                               args=tuple(args)))
    return FrameJob(key=frame_key, output=out, stats=stats_out, scene_name=info.name, frame=frame,
                    camera=cam, parts=tuple(parts), merged=regions > 1, part_names=names)
