"""Side-by-side crops (1 ray/px, uniform 25 lattice, adaptive, reference, rays/px heatmap) at the
windows where the adaptive image's error exceeds the lattice's most: where it misses what 25
rays/px get (the adaptive error alone when the lattice image is missing)."""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from PIL import Image

from settings import LATTICE25


def load(path: Path) -> np.ndarray | None:
    return np.asarray(Image.open(path).convert("RGB")) if path.exists() else None


def squared_error(img: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Per-pixel squared display error (summed over RGB, 8-bit PNG values scaled to [0, 1])."""
    return (((img.astype(np.float64) - ref.astype(np.float64)) / 255.0) ** 2).sum(axis=2)


def worst_windows(diff: np.ndarray, w: int, count: int) -> list[tuple[int, int]]:
    """Top-left corners of `count` non-overlapping w x w windows with the largest sum of `diff`."""
    h_, w_ = diff.shape
    step = max(w // 2, 1)
    scored = []
    for y in range(0, h_ - w + 1, step):
        for x in range(0, w_ - w + 1, step):
            scored.append((diff[y:y + w, x:x + w].sum(), y, x))
    chosen = []
    for _, y, x in sorted(scored, reverse=True):
        if all(abs(y - cy) >= w or abs(x - cx) >= w for cy, cx in chosen):
            chosen.append((y, x))
        if len(chosen) == count:
            break
    return chosen


def scene_crops(scene_dir: Path, adaptive_label: str, out: Path, count: int = 3) -> Path | None:
    columns = [("1 ray/px", scene_dir / "none.png"),
               ("uniform 25 lattice", scene_dir / f"{LATTICE25.label}.png"),
               ("adaptive", scene_dir / f"{adaptive_label}.png"),
               ("reference", scene_dir / "reference.png"),
               ("rays/px (dark 1 → bright 25)", scene_dir / f"{adaptive_label}_rays.png")]
    images = [(name, load(p)) for name, p in columns]
    lattice, adaptive, ref = images[1][1], images[2][1], images[3][1]
    if adaptive is None or ref is None:
        return None
    size = ref.shape[0]
    w = max(size // 8, 16)
    # The adaptive image's excess squared error over the lattice's, window by window.
    excess = squared_error(adaptive, ref)
    if lattice is not None:
        excess = excess - squared_error(lattice, ref)
    windows = worst_windows(excess, w, count)
    fig, axes = plt.subplots(len(windows), len(images), figsize=(1.9 * len(images), 1.9 * len(windows) + 0.3),
                             squeeze=False)
    for i, (y, x) in enumerate(windows):
        for j, (name, img) in enumerate(images):
            ax = axes[i][j]
            ax.set_xticks([])
            ax.set_yticks([])
            if img is not None:
                ax.imshow(img[y:y + w, x:x + w], interpolation="nearest")
            if i == 0:
                ax.set_title(name, fontsize=8)
            if j == 0:
                ax.set_ylabel(f"({x},{y})", fontsize=7)
    where = "adaptive's error exceeds the lattice's most" if lattice is not None else "adaptive errs most (no lattice image)"
    fig.suptitle(f"{scene_dir.name}: {w}x{w} crops where the {where}; adaptive = {adaptive_label}", fontsize=8)
    fig.tight_layout()
    path = out / f"crops_{scene_dir.name}.png"
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def all_crops(rows: list[dict], work: Path, out: Path, choice: dict) -> list[tuple[str, Path]]:
    figs = []
    for scene in dict.fromkeys(r["scene"] for r in rows if r["scene"] != "star"):
        path = scene_crops(work / scene, choice["label"], out)
        if path:
            figs.append((f"crops: {scene} (where the adaptive image's error exceeds the lattice's most)", path))
    return figs
