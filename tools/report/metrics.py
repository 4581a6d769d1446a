"""Images and error metrics: linear EXR in, RMSE/PSNR on HDR values, mean FLIP on display images."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import OpenEXR
import flip_evaluator


def read_exr(path: Path) -> np.ndarray:
    """Linear RGB radiance, H x W x 3 float32."""
    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)[..., :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=-1)


def srgb_encode(x: np.ndarray) -> np.ndarray:
    """IEC 61966-2-1 transfer function on [0, 1]."""
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def display(linear: np.ndarray, exposure: float) -> np.ndarray:
    """The renderer's tone map T(c) = sRGB(1 - exp(-exposure c)), float in [0, 1], not rounded.

    The errors are measured on these values (what FLIP's LDR mode expects, and the space the
    sampler's eps lives in): rounding both images to 8 bits first adds quantisation noise
    that, where the error is a fraction of a step, pulls every ratio towards 1."""
    c = np.nan_to_num(np.maximum(linear, 0.0), nan=0.0, posinf=1e30)
    t = srgb_encode(1.0 - np.exp(-exposure * c))
    return np.clip(t, 0.0, 1.0)


def eight_bit(display01: np.ndarray) -> np.ndarray:
    """A display image as the renderer's PNG stores it."""
    return np.round(display01 * 255.0).astype(np.uint8)


def rmse(test: np.ndarray, ref: np.ndarray) -> float:
    return float(np.sqrt(np.mean((test.astype(np.float64) - ref) ** 2)))


def psnr(rmse_value: float, peak: float = 1.0) -> float:
    """PSNR of linear values against a peak of 1 (the scenes' white)."""
    return math.inf if rmse_value == 0 else 20.0 * math.log10(peak / rmse_value)


def mean_flip(test_display: np.ndarray, ref_display: np.ndarray) -> float:
    """Mean LDR-FLIP (NVIDIA flip-evaluator) of two display images in [0, 1]."""
    _, mean, _ = flip_evaluator.evaluate(ref_display.astype(np.float32),
                                         test_display.astype(np.float32), "LDR",
                                         applyMagma=False)
    return float(mean)
