"""Checks of the report's logic on made-up rows (no rendering): equal-error speed-ups with the
lattice as a candidate, the reference-noise fit, one run's times per row, the header listing
mixed binaries and references, NaN ratios, crop windows by the adaptive image's excess error."""
import math
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools" / "report"))
import crops  # noqa: E402
import markdown  # noqa: E402
import measure  # noqa: E402
import settings  # noqa: E402

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)


# One run gives every time of a row: the run with the median frame time.
runs = [{"timing": {"image_s": t, "edges_s": e}, "maxrss_mb": 1, "stats": {}} for t, e in ((1, 0.9), (3, 0.1), (2, 0.5))]
check(measure.median_run(runs)["timing"] == {"image_s": 2, "edges_s": 0.5}, "median_run: not the median frame's run")
check(measure.median_run(runs[:2])["timing"]["image_s"] == 1, "median_run: two runs, not the lower middle")


# Equal error: grid and stratified curves from 1 ray/px, the lattice at 25 rays/px.
def row(mode, pattern, spp, t, e):
    label = f"uniform-{pattern}-{spp}" if mode == "uniform" else mode
    return {"scene": "s", "mode": mode, "pattern": pattern, "spp": spp, "image_s": t, "rmse": e, "setting": label}


rows = [row("none", "", 1, 1.0, 0.1)]
for pattern, k in (("grid", 1.0), ("stratified", 1.1)):
    rows += [row("uniform", pattern, n, n * k, 0.1 / n ** 0.5 * k) for n in (4, 9, 16, 25)]
rows.append(row("uniform", "lattice", 25, 20.0, 0.005))
for err, want_note, want in ((0.01, "≤lattice", 10.0),   # below grid/stratified, above the lattice
                             (0.001, "≥lattice", 10.0),  # below every point: the smallest lower bound
                             (0.5, "≤1 ray/px", 0.5)):   # worse than 1 ray/px
    v, note = markdown.equal_error_speedup(rows, "s", {"image_s": 2.0, "rmse": err})
    check(note == want_note and abs(v - want) < 1e-9, f"equal error at {err}: {v} {note!r}, want {want} {want_note!r}")
v, note = markdown.equal_error_speedup(rows, "s", {"image_s": 2.0, "rmse": 0.03})
check(note == "grid" and 4.5 < v < 8, f"equal error interpolated: {v} {note!r}")
check("≤10.0×" in markdown.equal_error_phrase(10.0, "≤lattice", "linear RMSE"), "≤ missing from the phrase")

# Reference noise: the fit recovers s² from exact points; fewer than 3 points is n/a.
R, A, q = 256, 1e-4, 0.7
strat = [{"scene": "x", "mode": "uniform", "pattern": "stratified", "spp": n, "ref_spp": R,
          "rmse_display": math.sqrt(A * (n ** (-2 * q) + R ** (-2 * q)))} for n in (4, 9, 16, 25)]
noise = markdown.reference_noise(strat, "x")
check("s2" in noise and abs(noise["s2"] / (A * R ** (-2 * q)) - 1) < 0.02, f"reference noise fit: {noise}")
check("s2" not in markdown.reference_noise(strat[:2], "x"), "reference noise from 2 points")
check(math.isnan(markdown.noise_removed_ratio({"rmse_display": 0.011}, {"rmse_display": 0.01}, {"s2": 2e-4})),
      "noise-removed ratio with the lattice's MSE below s²")

# The header lists every binary and reference rays/px of the rows.
env = {"binary_digest": "E", "ref_spp": 256}
binary, ref = markdown.provenance([{"scene": "a", "binary": "B1", "ref_spp": 256},
                                   {"scene": "b", "binary": "B2", "ref_spp": 1024}], env)
check("B1 (a)" in binary and "B2 (b)" in binary, f"mixed binaries: {binary}")
check("256 rays/px (a)" in ref and "1024 rays/px (b)" in ref, f"mixed references: {ref}")

# A NaN ratio in any scene makes the worst ratio NaN (max() kept it only when first).
lat = {"mode": "uniform", "setting": settings.LATTICE25.label, "rmse": 1, "rmse_display": 1, "flip": 1,
       "image_s": 5, "rays_per_px": 25}


def ada(scene, label, d):
    return {"scene": scene, "mode": "adaptive", "setting": label, "rmse": 1, "rmse_display": d, "flip": 1,
            "image_s": 1, "rays_per_px": 1.5}


rows = [dict(lat, scene="a"), dict(lat, scene="b"), ada("a", "X", 1.05), ada("b", "X", math.nan),
        ada("a", "Y", 1.2), ada("b", "Y", 1.2)]
choice = markdown.choose_defaults(rows, ["a", "b"])
check(choice["label"] == "Y", f"a setting with an unmeasured scene was chosen: {choice['label']}")

# Crops: the window where the adaptive image's error exceeds the lattice's most.
img = np.zeros((64, 64, 3), np.uint8)
ref, lattice, adaptive, none = img.copy(), img.copy(), img.copy(), img.copy()
none[0:16, 0:16] = 255        # where 1 ray/px errs most
adaptive[40:56, 40:56] = 60   # adaptive errs, the lattice nearly as much
lattice[40:56, 40:56] = 50
adaptive[8:24, 40:56] = 40    # adaptive errs, the lattice does not: the largest excess
excess = crops.squared_error(adaptive, ref) - crops.squared_error(lattice, ref)
check(crops.worst_windows(excess, 16, 1) == [(8, 40)], "crop window not at the adaptive image's excess error")
with tempfile.TemporaryDirectory() as tmp:
    scene = Path(tmp) / "sc"
    scene.mkdir()
    for name, im in (("none", none), (settings.LATTICE25.label, lattice), ("A", adaptive), ("reference", ref)):
        Image.fromarray(im).save(scene / f"{name}.png")
    check(crops.scene_crops(scene, "A", Path(tmp)) is not None, "crops not written")
    (scene / f"{settings.LATTICE25.label}.png").unlink()
    check(crops.scene_crops(scene, "A", Path(tmp)) is not None, "crops not written without the lattice image")

check("one per point" in settings.measured_grid(1) and "Timed runs: 3" in settings.measured_grid(3),
      "the measured grid's timing text does not follow the run count")

for f in failures:
    print("FAIL:", f)
print(f"check_logic: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
