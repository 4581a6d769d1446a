"""What decides an image's bytes besides the options: the renderer binary and every file its
scene is read from (rig JSON, glTF, .bin buffers, textures: `zigzag info`'s "files").

Files are hashed by content, so an edit to any of them re-renders what uses it and a `touch`
does not. Hashing gigabytes of textures on every run is slow, so a file's SHA-256 is cached
beside the manifest under its identity on disk (size, inode, mtime and ctime in ns): any write
to the file changes its ctime, which no tool can set back. The clock behind those times is
coarse (a kernel tick), so a file changed within RACY_S of being hashed could keep its
identity through a second write of the same size: such a hash is used but not cached (git's
"racy index" rule).
"""
from __future__ import annotations

import hashlib
import json
import os
import time

from .job import sha256_of, write_json_atomically

CACHE_NAME = ".zigzag-farm-hashes.json"
RACY_S = 2.0


def _identity(st: os.stat_result) -> list[int]:
    return [st.st_size, st.st_ino, st.st_mtime_ns, st.st_ctime_ns]


class HashCache:
    def __init__(self, path: str):
        self.path = path
        self.entries: dict[str, list] = {}
        self.used: dict[str, list] = {}  # what this run hashed or confirmed, saved over the old entries
        try:
            with open(path) as f:
                loaded = json.load(f)
            if isinstance(loaded, dict):
                self.entries = loaded
        except (OSError, ValueError):
            pass

    def sha256(self, path: str) -> str | None:
        """The file's SHA-256, or None when it cannot be read."""
        try:
            st = os.stat(path)
            cached = self.entries.get(path)
            if isinstance(cached, list) and cached[:-1] == _identity(st) and isinstance(cached[-1], str):
                digest = cached[-1]
            else:
                digest = sha256_of(path)
                if _identity(os.stat(path)) != _identity(st) or time.time() - st.st_ctime < RACY_S:
                    return digest  # written while or just before hashed: correct now, not cached
        except OSError:
            return None
        self.used[path] = [*_identity(st), digest]
        return digest

    def save(self) -> None:
        """Best effort: without the cache the next run only hashes again."""
        try:
            write_json_atomically(self.path, {**self.entries, **self.used})
        except OSError:
            pass


def digest(paths: list[str], cache: HashCache) -> str:
    """One digest of the files' paths and contents (a missing file counts as missing)."""
    h = hashlib.sha256()
    for path in paths:
        h.update(os.path.abspath(path).encode() + b"\0")
        h.update((cache.sha256(path) or "unreadable").encode() + b"\0")
    return h.hexdigest()[:16]
