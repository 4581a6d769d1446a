"""Checks of the quick report's outputs: every expected row and file, sane numbers, and the
report's tone map reproducing zigzag's own PNG (FLIP is computed on that display image)."""
import csv
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

build, root, out = map(Path, sys.argv[1:4])
sys.path.insert(0, str(root / "tools" / "report"))
import metrics  # noqa: E402

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)


rows = list(csv.DictReader(open(out / "accuracy_vs_time.csv")))
by = {(r["scene"], r["setting"]): r for r in rows}
for scene in ("room", "glass"):
    none = by.get((scene, "none"))
    lat = by.get((scene, "uniform-lattice-25"))
    ada = by.get((scene, "adaptive-eps0.1-vulkan-box-paper-geopaper"))
    check(none and lat and ada, f"{scene}: missing none/lattice/adaptive rows")
    if not (none and lat and ada):
        continue
    f = {k: float(v) for k, v in ada.items()
         if k in ("rmse", "rmse_display", "flip", "rays_per_px", "image_s", "maxrss_mb")}
    check(len(f) == 6 and all(math.isfinite(v) and v > 0 for v in f.values()), f"{scene}: non-finite adaptive metrics {f}")
    # The frame's time lies within the run's total (load + BVH + frame + write): the map and
    # level 1 overlap, so adding their times would count the overlap twice.
    for r in (none, lat, ada):
        check(float(r["image_s"]) <= float(r["total_s"]), f"{scene}: {r['setting']} frame {r['image_s']} s "
              f"longer than the whole run {r['total_s']} s")
    check(float(lat["rmse_display"]) < float(none["rmse_display"]), f"{scene}: lattice display RMSE not below 1 ray/px")
    # Antialiasing must pay off: 25 rays/px beats 1 ray/px against the reference, adaptive in between.
    check(float(lat["rmse"]) < float(none["rmse"]), f"{scene}: lattice RMSE not below 1 ray/px")
    check(float(ada["flip"]) < float(none["flip"]), f"{scene}: adaptive FLIP not below 1 ray/px")
    check(1.0 < float(ada["rays_per_px"]) < 25.0, f"{scene}: adaptive rays/px {ada['rays_per_px']}")
    check(abs(float(lat["rays_per_px"]) - 25.0) < 0.1, f"{scene}: lattice rays/px {lat['rays_per_px']}")
    # Signatures only add refinements: never fewer rays than the same setting without them.
    base = by.get((scene, "adaptive-eps0.05-vulkan-box-tuned-geoall"))
    signed = by.get((scene, "adaptive-eps0.05-vulkan-box-tuned-geoall-sigall"))
    check(base and signed, f"{scene}: missing the signature ablation rows")
    if base and signed:
        check(float(signed["rays_per_px"]) >= float(base["rays_per_px"]),
              f"{scene}: --signature all traced fewer rays than none")
    # The highlight flag and the curvature ring only add rays.
    plain = by.get((scene, "adaptive-eps0.05-vulkan-box-tuned-geopaper"))
    both = by.get((scene, "adaptive-eps0.05-vulkan-box-tuned-geopaper-hl-cv"))
    check(plain and both, f"{scene}: missing the beyond-corners ablation rows")
    if plain and both:
        check(float(both["rays_per_px"]) > float(plain["rays_per_px"]),
              f"{scene}: --highlights on --curvature on traced no more rays than without")
star = [r for r in rows if r["scene"] == "star"]
check(any(r["mode"] == "adaptive" for r in star) and any(r["setting"] == "uniform-lattice-25" for r in star),
      "star rows missing")
report = (out / "REPORT.md").read_text()
for needle in ("## Table 2", "## Targets of issue 5", "## Chosen defaults", "Recommended defaults",
               "## Sample signatures: ablation", "## Beyond corner colours: ablation"):
    check(needle in report, f"REPORT.md lacks {needle!r}")
for name in ("error_room.png", "error_star.png", "stages.png", "crops_room.png"):
    check((out / name).exists(), f"missing {name}")

# The report's display values (for the metrics, unrounded) must be the renderer's tone map:
# rounded, they give its PNG to the 8-bit step.
with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    base = [str(build / "zigzag"), "render", str(root / "scenes" / "glass.json"), "-q", "--width", "48",
            "--height", "40", "--aa", "none", "--threads", "1"]
    subprocess.run(base + ["-o", str(tmp / "g.exr")], check=True)
    subprocess.run(base + ["-o", str(tmp / "g.png")], check=True)
    exposure = json.loads((root / "scenes" / "glass.json").read_text()).get("exposure", 1.0)
    display = metrics.display(metrics.read_exr(tmp / "g.exr"), exposure)
    # The metrics see the tone map's own values, not 8-bit steps (rounding both images
    # pulls the error ratios towards 1).
    check(bool(np.any(np.abs(display * 255 - np.round(display * 255)) > 1e-3)), "display values are rounded to 8 bits")
    ours = metrics.eight_bit(display).astype(int)
    theirs = np.asarray(Image.open(tmp / "g.png").convert("RGB")).astype(int)
    diff = int(np.abs(ours - theirs).max()) if ours.shape == theirs.shape else -1
    check(diff in (0, 1), f"tone map differs from zigzag PNG by {diff} steps (-1: shapes differ)")

for f in failures:
    print("FAIL:", f)
print(f"check_quick: {len(rows)} rows, {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
