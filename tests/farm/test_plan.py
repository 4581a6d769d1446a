"""Job planning: frame ranges, output patterns, jobs and their keys."""
import pytest

from zigzag_farm.plan import SceneInfo, expand, parse_frames, plan_batch


@pytest.mark.parametrize("text,frames", [
    ("5", [5]), ("1-8", list(range(1, 9))), ("1-48x2", list(range(1, 49, 2))),
    ("0-10x5", [0, 5, 10]), ("3-4x10", [3]), (" 2 - 6 x 2 ", [2, 4, 6]), ("-2-1", [-2, -1, 0, 1]),
])
def test_frame_ranges(text, frames):
    assert parse_frames(text) == frames


@pytest.mark.parametrize("text", ["", "abc", "8-1", "1-5x0", "1-5x", "1x2", "1-2-3"])
def test_bad_frame_ranges(text):
    with pytest.raises(ValueError):
        parse_frames(text)


def test_patterns():
    assert expand("out/{scene}_{camera}_{frame:04}.png", "room", 2, 7) == "out/room_2_0007.png"
    assert expand("{frame}.exr", "room", 0, 123) == "123.exr"
    assert expand("still.png", "room", 0, None) == "still.png"
    with pytest.raises(ValueError, match="unknown field"):
        expand("{scene}_{take}.png", "room", 0, 1)


ANIM = SceneInfo(path="/s/anim.json", name="anim", width=100, height=60, cameras=2,
                 animated=True, fps=24, frame_range=(1, 6))
STILL = SceneInfo(path="/s/still.json", name="still", width=64, height=64, cameras=1)


def plan(**kw):
    args = dict(frames=None, camera="all", regions=1, work_dir="/w")
    args.update(kw)
    scenes = args.pop("scenes", [ANIM, STILL])
    output = args.pop("output", "/o/{scene}_{camera}_{frame:03}.png")
    return plan_batch(scenes, output, **args)


def test_every_frame_and_camera_once():
    p = plan()
    names = [(f.scene_name, f.frame, f.camera) for f in p.frames]
    assert names == [("anim", fr, c) for fr in range(1, 7) for c in (0, 1)] + [("still", None, 0)]
    assert len({f.output for f in p.frames}) == len(p.frames)
    assert p.frames[0].output == "/o/anim_0_001.png"
    assert all(len(f.parts) == 1 and f.parts[0].output == f.output for f in p.frames)


def test_explicit_frames_with_step_apply_to_every_scene():
    p = plan(frames=parse_frames("2-6x2"), camera="1", scenes=[ANIM])
    assert [(f.frame, f.camera) for f in p.frames] == [(2, 1), (4, 1), (6, 1)]


def test_keys_are_deterministic_unique_and_follow_the_settings():
    a, b = plan(regions=4), plan(regions=4)
    keys = [j.key for j in a.render_jobs] + [f.key for f in a.frames]
    assert keys == [j.key for j in b.render_jobs] + [f.key for f in b.frames]
    assert len(set(keys)) == len(keys)
    other = plan(regions=4, args=("--eps", "0.1"))
    assert not set(keys) & {j.key for j in other.render_jobs}
    rebuilt = plan(regions=4, fingerprint="new renderer")
    assert not set(keys) & {f.key for f in rebuilt.frames}


def test_regions_become_parts_in_the_work_folder():
    p = plan(regions=4, scenes=[STILL], output="/o/{scene}.exr")
    (f,) = p.frames
    assert f.merged and len(f.parts) == 4
    assert all(part.output.startswith("/w/") and part.output.endswith(".exr") for part in f.parts)
    assert len({part.output for part in f.parts}) == 4
    assert sum(part.region.pixels for part in f.parts) == 64 * 64


def test_colliding_outputs_are_refused():
    with pytest.raises(ValueError, match="add {scene}, {camera} or {frame}"):
        plan(output="/o/{scene}_{camera}.png")


def test_missing_camera_is_refused():
    with pytest.raises(ValueError, match="--camera 2 does not exist"):
        plan(camera="2", scenes=[ANIM])
