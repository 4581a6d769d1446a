"""Job planning: frame ranges, output patterns, jobs and their keys."""
import dataclasses
import hashlib
import json
import os
import re
import time

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
    with pytest.raises(ValueError, match="unknown placeholder"):
        expand("{scene}_{take}.png", "room", 0, 1)


@pytest.mark.parametrize("pattern,expanded", [
    ("{frame:4}.png", "0002.png"), ("{frame:04}.png", "0002.png"), ("{frame:1}.png", "2.png"),
    ("{frame:0}.png", "2.png"), ("{frame:12}.png", "000000000002.png"), ("{frame:00}.png", "2.png"),
    ("a}b{scene}}.png", "a}bro{om}.png"),  # a lone '}' is itself; {scene}'s braces are not expanded again
    ("{camera}_{scene}.png", "3_ro{om.png"),
])
def test_patterns_expand_as_the_renderer_does(pattern, expanded):
    """host/app/output_paths.cpp expand_placeholder: {frame:N} is zero-padding to N, one or two
    digits, and nothing else of Python's format specs (review: {frame:4} gave '   2')."""
    assert expand(pattern, "ro{om", 3, 2) == expanded


@pytest.mark.parametrize("pattern,bad", [
    ("w3/{scene:.3}_{frame}.png", "{scene:.3}"), ("{camera:x}.png", "{camera:x}"),
    ("{frame:4d}.png", "{frame:4d}"), ("{frame:>4}.png", "{frame:>4}"), ("{frame:123}.png", "{frame:123}"),
    ("{frame:}.png", "{frame:}"), ("{frame: 4}.png", "{frame: 4}"), ("{}.png", "{}"), ("{0}.png", "{0}"),
    ("{{frame}}.png", "{{frame}"), ("{scene.png", "{scene.png"), ("{Frame}.png", "{Frame}"),
])
def test_other_placeholders_are_refused_with_the_renderers_message(pattern, bad):
    with pytest.raises(ValueError) as e:
        expand(pattern, "room", 0, 2, "--stats")
    assert str(e.value) == (f"--stats {pattern}: unknown placeholder '{bad}' "
                            "(known: {scene}, {camera}, {frame}, {frame:04})")


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
    # Every key, the frames' too (a re-run with other options must not find its frames done).
    for changed in (plan(regions=4, args=("--eps", "0.1")), plan(regions=4, fingerprint="new renderer"),
                    plan(regions=4, scenes=[dataclasses.replace(s, content="edited") for s in (ANIM, STILL)])):
        other = [j.key for j in changed.render_jobs] + [f.key for f in changed.frames]
        assert len(other) == len(keys) and not set(keys) & set(other)


def test_regions_become_parts_in_the_work_folder():
    p = plan(regions=4, scenes=[STILL], output="/o/{scene}.exr")
    (f,) = p.frames
    assert f.merged and len(f.parts) == 4
    assert all(part.output.startswith("/w/") and part.output.endswith(".exr") for part in f.parts)
    assert len({part.output for part in f.parts}) == 4
    assert sum(part.region.pixels for part in f.parts) == 64 * 64


def test_part_names_keep_their_bytes():
    """A part's name is its frame's identity hashed with its region: the same bytes as every
    earlier run made them (an interrupted run's parts are found again, or removed), written
    out here from the fields, not from the code that names them."""
    p = plan(regions=2, scenes=[STILL], output="/o/{scene}.exr", args=("--eps", "0.1"), fingerprint="fp")
    (f,) = p.frames
    for i, part in enumerate(f.parts):
        payload = {"scene": "/s/still.json", "frame": None, "camera": 0, "args": ["--eps", "0.1"],
                   "fingerprint": "fp", "content": "", "size": [64, 64], "output": "/o/still.exr",
                   "region": list(part.region.bounds)}
        digest = hashlib.sha256(json.dumps(payload, sort_keys=True, separators=(",", ":")).encode()).hexdigest()[:12]
        assert part.output == f"/w/still-still-c0-r{i}of2-{digest}.exr"
        assert f.part_names.index_and_count(os.path.basename(part.output)) == (i, 2)
        assert f.part_names.path(i, 2, part.region) == part.output
    for other in ("still-still-c0-r2of2-0123456789ab.exr", "still-still-c0-r0of99999999-0123456789ab.exr",
                  "still-still-c01-r0of2-0123456789ab.exr", "still-still-c0-r0of2-0123456789ab.png"):
        assert f.part_names.index_and_count(other) is None, other


def test_two_batches_of_one_frame_into_one_folder_have_their_own_parts():
    """A PNG batch and an EXR batch of the same frame, same work folder (the output's): each
    merge deletes its parts, so sharing them would fail the other batch's merge."""
    (png,) = plan(regions=4, scenes=[STILL], output="/o/{scene}.png").frames
    (exr,) = plan(regions=4, scenes=[STILL], output="/o/{scene}.exr").frames
    assert not {q.output for q in png.parts} & {q.output for q in exr.parts}


def test_no_output_replaces_a_file_of_any_scene(tmp_path):
    """--stats {scene}.json beside room.json would replace the rig with its stats; an image
    named after another scene's texture would replace that. Compared as files (links too)."""
    rig, texture = tmp_path / "still.json", tmp_path / "anim.png"
    rig.write_text("{}")
    texture.write_bytes(b"png")
    (tmp_path / "link.json").symlink_to(rig)
    still = dataclasses.replace(STILL, path=str(rig), files=(str(rig),))
    anim = dataclasses.replace(ANIM, files=(str(texture),))
    with pytest.raises(ValueError, match="still.json, a file of scene still"):
        plan(scenes=[still], output=f"{tmp_path}/{{scene}}.png", stats=f"{tmp_path}/{{scene}}.json")
    with pytest.raises(ValueError, match="a file of scene still"):
        plan(scenes=[still], output=f"{tmp_path}/out.png", stats=f"{tmp_path}/link.json")
    with pytest.raises(ValueError, match="anim.png, a file of scene anim"):  # another scene's file
        plan(scenes=[still, anim], output=f"{tmp_path}/{{scene}}.png", frames=[1], camera="0")
    plan(scenes=[still, anim], output=f"{tmp_path}/out/{{scene}}.png", frames=[1], camera="0")


def test_output_names_leave_room_for_the_temporaries():
    """A 200-byte name is valid, but its job's temporary (a host tag more) is not: refused
    while planning, not after the render."""
    with pytest.raises(ValueError, match=r"its name is 213 bytes; the farm takes at most 155"):
        plan(output="/o/" + "n" * 200 + "_{scene}_{camera}_{frame}.png")
    plan(output="/o/" + "n" * 140 + "_{scene}_{camera}_{frame}.png")


def test_colliding_outputs_are_refused():
    with pytest.raises(ValueError, match="anim_0.png would be written as both the image of anim "
                                         "camera 0 f1 and the image of anim camera 0 f2: add {frame} to -o"):
        plan(output="/o/{scene}_{camera}.png")
    with pytest.raises(ValueError, match="add {scene} to -o"):
        plan(output="/o/{camera}_{frame}.png", frames=[1])


@pytest.mark.parametrize("stats,message", [
    ("/o/{scene}_{camera}_{frame:03}.png", "both the image of anim camera 0 f1 and the stats of anim camera 0 f1"),
    ("/o/{scene}_{camera}.json", "both the stats of anim camera 0 f1 and the stats of anim camera 0 f2: add {frame} to --stats"),
    ("/o/anim_1_{frame:03}.png", "both the stats of anim camera 0 f1 and the image of anim camera 1 f1: "
                                 "-o and --stats must name different files"),
])
def test_stats_that_collide_with_an_image_or_other_stats_are_refused(stats, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        plan(stats=stats)


def test_every_output_kind_is_claimed_once():
    p = plan(regions=4, scenes=[STILL], output="/o/{scene}.exr", stats="/o/{scene}.json")
    (f,) = p.frames
    assert set(p.claims) == {"/o/still.exr", "/o/still.json", *(q.output for q in f.parts)}
    with pytest.raises(ValueError, match="both the stats of still camera 0 still and the summary"):
        p.claim("/o/still.json", "the summary")
    with pytest.raises(ValueError, match="both region part 2 of still"):
        p.claim(f.parts[2].output, "the manifest")


def test_two_scenes_of_one_name_get_a_hint_that_fits():
    other_room = SceneInfo(path="/t/still.json", name="still", width=64, height=64, cameras=1)
    with pytest.raises(ValueError, match="the scenes /s/still.json and /t/still.json are both named "
                                         "'still', so {scene} cannot tell them apart: render them in "
                                         "separate runs with different -o folders, or rename one"):
        plan(scenes=[STILL, other_room], output="/o/{scene}.png")


def test_one_scene_file_given_twice_is_refused_as_such(tmp_path):
    # It gave "add  to -o" (nothing tells the images apart), or, by two paths, "both named
    # 'still' ... rename one" for what is one file (review).
    with pytest.raises(ValueError, match="/s/still.json: the scene is given twice; give it once"):
        plan(scenes=[STILL, STILL], output="/o/{scene}.png")
    real = tmp_path / "room.json"
    real.write_text("{}")
    (tmp_path / "link.json").symlink_to(real)
    a = SceneInfo(path=str(real), name="room", width=64, height=64, cameras=1)
    b = SceneInfo(path=str(tmp_path / "link.json"), name="link", width=64, height=64, cameras=1)
    with pytest.raises(ValueError, match=f"the scene is given twice \\(also as {real}\\)"):
        plan(scenes=[a, b], output="/o/{scene}.png")


def test_regions_split_each_cameras_own_frame():
    wide_and_tall = SceneInfo(path="/s/two.json", name="two", width=200, height=100, cameras=2,
                              camera_sizes=((200, 100), (50, 100)))
    p = plan(scenes=[wide_and_tall], regions=4, output="/o/{camera}.exr")
    for f, (w, h) in zip(p.frames, [(200, 100), (50, 100)]):
        regions = [q.region for q in f.parts]
        assert max(r.x1 for r in regions) == w and max(r.y1 for r in regions) == h
        assert sum(r.pixels for r in regions) == w * h


def test_keys_follow_the_scenes_files_but_not_their_paths_only():
    before = plan(scenes=[STILL])
    edited = plan(scenes=[dataclasses.replace(STILL, content="texture edited")])
    assert before.frames[0].key != edited.frames[0].key
    assert before.render_jobs[0].key != edited.render_jobs[0].key


@pytest.mark.parametrize("pattern", ["/o/{}.png", "/o/{0}.png", "/o/{frame[0]}.png", "/o/{scene!x}.png",
                                     "/o/{frame:abc}.png", "/o/{scene.png"])
def test_bad_pattern_fields_are_value_errors(pattern):
    with pytest.raises(ValueError, match=f"-o {re.escape(pattern)}: unknown placeholder"):
        plan(output=pattern)


def test_a_batch_of_too_many_jobs_is_refused_before_it_is_planned():
    started = time.monotonic()
    with pytest.raises(ValueError, match="99999999 frames, more than a batch may have"):
        parse_frames("0-99999998")
    with pytest.raises(ValueError, match="jobs, more than a batch may have"):
        plan(frames=list(range(10_000)), regions=128, scenes=[STILL])
    assert time.monotonic() - started < 1.0


def test_missing_camera_is_refused():
    with pytest.raises(ValueError, match="--camera 2 does not exist"):
        plan(camera="2", scenes=[ANIM])


NAMED = SceneInfo(path="/s/named.json", name="named", width=64, height=64, cameras=3,
                  camera_names=("front", "top", "front"))


def test_a_camera_by_name_is_its_index_as_the_renderer_finds_it():
    p = plan(camera="top", scenes=[NAMED], output="/o/{scene}_{camera}.png")
    assert [(f.camera, f.output) for f in p.frames] == [(1, "/o/named_1.png")]
    assert [q.camera for q in p.frames[0].parts] == [1]
    assert [f.camera for f in plan(camera="2", scenes=[NAMED]).frames] == [2]  # digits: an index


def test_a_camera_name_that_is_missing_or_shared_is_refused_with_the_cameras():
    with pytest.raises(ValueError, match=r"/s/named.json: no camera named 'side' "
                                         r"\(cameras: 0 'front', 1 'top', 2 'front'\)"):
        plan(camera="side", scenes=[NAMED])
    with pytest.raises(ValueError, match=r"camera name 'front' is ambiguous: cameras 0, 2 have it "
                                         r"\(give an index, --camera 0\)"):
        plan(camera="front", scenes=[NAMED])
    with pytest.raises(ValueError, match="no camera named 'top'"):  # each scene must have it
        plan(camera="top", scenes=[NAMED, STILL])
    with pytest.raises(ValueError, match="--camera 0000000001 does not exist"):  # as find_camera: 9 digits at most
        plan(camera="0000000001", scenes=[NAMED])
    with pytest.raises(ValueError, match="no camera named '\u0662'"):
        plan(camera="\u0662", scenes=[NAMED])  # an Arabic-Indic two is a name, not an index


def test_folders_with_braces_are_refused_as_the_renderer_would_expand_them():
    """A file name's braces stay out of the temporaries the renderer is given; a folder's
    cannot, and zigzag would write elsewhere."""
    braced = dataclasses.replace(STILL, name="shot{camera}")
    with pytest.raises(ValueError, match=r"its folder /o/shot\{camera\} has '\{' or '\}'"):
        plan(scenes=[braced], output="/o/{scene}/x.png")
    with pytest.raises(ValueError, match=r"/w\{1\}/still-still-c0-r0of2-.*--work-dir.*has '\{' or '\}'"):
        plan(scenes=[STILL], output="/o/x.png", regions=2, work_dir="/w{1}")
    plan(scenes=[braced], output="/o/{scene}.png", regions=2)
