"""The renderer options given after `--`: read in both `--x v` and `--x=v` forms, as the
renderer's CLI11 takes them, and split by their role in a batch (what decides an image's
bytes, what only changes how fast it is made, what `zigzag info` needs to plan it)."""
from __future__ import annotations

import os
from dataclasses import dataclass


class UsageError(Exception):
    """Bad options or setup: a one-line error and exit code 2."""


def option_value(args: list[str], name: str) -> str | None:
    """The value of the last `name V` or `name=V` in args, else None."""
    value = None
    for i, a in enumerate(args):
        if a == name and i + 1 < len(args):
            value = args[i + 1]
        elif a.startswith(name + "="):
            value = a.split("=", 1)[1]
    return value


def without_option(args: list[str], name: str) -> list[str]:
    """args without any `name V` or `name=V`."""
    out, skip = [], False
    for i, a in enumerate(args):
        if skip:
            skip = False
        elif a == name:
            skip = i + 1 < len(args)
        elif not a.startswith(name + "="):
            out.append(a)
    return out


# Set by the driver itself for every job: after `--` they would contradict its plan.
DRIVER_OPTIONS = ("-o", "--output", "--camera", "--frame", "--region", "--stats", "--time")
# Options with which `zigzag render` writes no image.
NO_IMAGE_OPTIONS = ("--dry-run", "-h", "--help", "--version")
# `zigzag render`'s options that take no value (`zigzag render --help`).
FLAGS = ("-q", "--quiet", "--vk-validate", "--edges-serial", "--allow-missing-textures", *NO_IMAGE_OPTIONS)
# How a job runs, not what it makes: the images are the same bits whatever these are, so
# they stay out of the job keys (another --workers count or a validation run re-renders
# nothing). Flags, then options with a value.
RUNTIME_FLAGS = ("-q", "--quiet", "--vk-validate", "--edges-serial")
RUNTIME_OPTIONS = ("--threads", "--vk-device")
# What `zigzag info` takes too, so that the plan sees the sizes and files the render will.
INFO_OPTIONS = ("--width", "--height", "--fps", "--assets")


def _whole_number(text: str | None, what: str, least: int = 1) -> int | None:
    if text is None:
        return None
    try:
        value = int(text)
    except ValueError:
        raise UsageError(f"{what} {text!r}: expected a whole number") from None
    if value < least:
        raise UsageError(f"{what} {value}: must be at least {least}")
    return value


def _positive_float(text: str | None, what: str) -> float | None:
    if text is None:
        return None
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{what} {text!r}: expected a number") from None
    if not value > 0:
        raise UsageError(f"{what} {text}: must be more than 0")
    return value


def _size_option(given: int | None, passed: list[str], name: str) -> int | None:
    """--width/--height given to the farm or after `--` (the same value if both)."""
    after = _whole_number(option_value(passed, name), f"{name} (after --)")
    if given is not None and after is not None and given != after:
        raise UsageError(f"{name} {given} and {name} {after} after --: give it once")
    return given if given is not None else after


def _aov_files(args: list[str]) -> list[str]:
    """The FILEs of `--aov NAME FILE` (an AOV image of its own; without one, layers of -o)."""
    files = []
    for i, a in enumerate(args):
        name_given = a.startswith("--aov=")
        if a == "--aov" or name_given:
            at = i + (1 if name_given else 2)
            if at < len(args) and not args[at].startswith("-"):
                files.append(args[at])
    return files


def _positionals(args: list[str]) -> list[str]:
    """What zigzag render would take as scene files: words that are no option's value (every
    option but FLAGS takes one; `--aov NAME FILE`'s FILE is refused by _aov_files first)."""
    found, value_next = [], False
    for a in args:
        if value_next:
            value_next = False
        elif a.startswith("-"):  # `--x=v` is split by now but for flags (`--edges-serial=false`)
            value_next = a not in FLAGS and "=" not in a
        else:
            found.append(a)
    return found


@dataclass
class RenderOptions:
    """The renderer options of a batch, split by their role."""

    key_args: list[str]      # every job's options that decide its bytes: part of the job keys
    runtime_args: list[str]  # options that do not (RUNTIME_FLAGS, RUNTIME_OPTIONS): out of the keys
    info_args: list[str]     # what `zigzag info` needs to size and list the scene as rendered


def render_options(o, passed: list[str]) -> RenderOptions:
    # `--eps=0.03` and `--eps 0.03` are one option to zigzag render, so one job key: written
    # the other way on a re-run, it re-rendered every image (review).
    # Flags stay whole: CLI11 reads --edges-serial=false as the flag off, and split its
    # "false" would be a scene file.
    passed = [part for a in passed
              for part in (a.split("=", 1) if a.startswith("--") and "=" in a and a.split("=", 1)[0] not in FLAGS
                           else [a])]
    if passed and passed[-1] in (*INFO_OPTIONS, *RUNTIME_OPTIONS):
        raise UsageError(f"{passed[-1]} after --: needs a value")
    for name in DRIVER_OPTIONS:
        if option_value(passed, name) is not None or name in passed:
            raise UsageError(f"{name} after --: zigzag-farm sets it for every job "
                             "(use -o, --camera, --frames, --regions, --stats; frames, not times)")
    for name in NO_IMAGE_OPTIONS:
        if name in passed or f"{name}=true" in passed:  # every job would end without its image
            raise UsageError(f"{name} after --: a job that renders nothing cannot be a farm job "
                             "(zigzag render --help lists the options; zigzag-farm render --help the farm's)")
    for file in _aov_files(passed):
        # Written by each job beside the farm's outputs, unclaimed, unrecorded, and by every
        # region for its own part: AOVs go into the -o EXR as layers instead.
        raise UsageError(f"--aov ... {file} after --: an AOV image of its own is not a farm output; "
                         "give --aov NAME without a file and an .exr -o to get it as layers")
    for scene in _positionals(passed):
        # Each job would render it too, into the job's temporaries (every job failed naming
        # one), and the plan, made from the scenes before --, would not know it.
        raise UsageError(f"{scene} after --: scenes go before -- (after it, only options for every render)")
    width = _size_option(o.width, passed, "--width")
    height = _size_option(o.height, passed, "--height")
    _positive_float(option_value(passed, "--fps"), "--fps (after --)")
    threads = _whole_number(option_value(passed, "--threads"), "--threads (after --)", least=0)
    key_args = [a for a in passed if a not in RUNTIME_FLAGS]
    for name in (*RUNTIME_OPTIONS, "--width", "--height"):
        key_args = without_option(key_args, name)
    for name, value in (("--width", width), ("--height", height)):
        if value is not None:
            key_args += [name, str(value)]
    if threads is None and o.scheduler is None and o.slurm is None:
        # Workers of a LocalCluster share this machine's cores.
        threads = max(1, (os.cpu_count() or 1) // o.workers)
    runtime_args = ["--threads", str(threads)] if threads is not None else []
    runtime_args += [a for a in passed if a in RUNTIME_FLAGS]
    if (device := option_value(passed, "--vk-device")) is not None:
        runtime_args += ["--vk-device", device]
    info_args = []
    for name in INFO_OPTIONS:
        value = option_value(key_args, name)
        if value is not None:
            info_args += [name, value]
    return RenderOptions(key_args, runtime_args, info_args)
