"""The measured points: which modes and adaptive settings the report renders.

The full cross product eps x edges x filter x tables x geo-policy (7 x 2 x 2 x 3 x 2 = 168
adaptive points per scene) is too slow for a 2-core machine, so the grid is pruned:
  * an eps sweep (0.02 0.05 0.1 0.2) for the `paper` and the `tuned` table sets
    (edges vulkan, box filter, geo policy paper);
  * around eps 0.05 and 0.1, one factor changed at a time: --edges off, --filter mitchell,
    --tables all, --geo-policy all, tuned + geo all, tuned + edges off;
  * sample signatures (ALGORITHM.md §11) around eps 0.05, tuned tables, geo policy all,
    edges vulkan, box: none, each part alone (object, lights, secondary: the ablation
    table), all, and all at eps 0.1;
  * beyond corner colours (ALGORITHM.md §11 and our curvature correction) around eps 0.05,
    tuned tables, geo policy paper, edges vulkan, box: the highlight flag alone, the
    curvature correction alone, both, both with the texture detail flag, both with the
    `lights`, the `secondary` and all signatures, both with the `secondary` and all
    signatures and the map's material rule (--edge-material on), that with the HDR zone
    rule (--hdr-zones on), all of these with the texture flag too, and both at eps 0.1 (the
    second ablation table), that with the texture footprint correction (--footprint on), and
    that with geo policy split (--geo-policy split: geo pixels also trace the zones between
    samples whose signatures differ), that with the map's edge direction orienting geo pixels
    whose corners leave the orientation open (--geo-orient on), that with the map's zones
    (--geo-zones on: geo pixels trace the zones where the map saw their edge), and that with
    the split zones in refined pixels the map does not flag too (--split-unflagged on), and
    that with the threshold of pixels whose corners all see a mirror's or a glass's image at
    0.02, 0.015 and 0.01 (--eps-specular), and at 0.01 with the gaps between refined pixels
    filled (--fill-gaps on);
  * uniform: 1 ray/px, grid and stratified at 4 9 16 25 rays/px, the 25-point lattice.
Timed runs: --runs of them (the run with the median frame time gives all of a row's times)
for 1 ray/px, the lattice and every adaptive point; one run for the other uniform points
(4-25x longer renders, so their relative noise is smaller). REPORT.md states the count its
rows were timed with (measured_grid).
The Siemens star runs the default and its one-factor variations with the box filter only.
"""
from __future__ import annotations

import dataclasses


def timing_doc(runs: int) -> str:
    """The timing paragraph of the measured grid, for the run count the rows were timed with."""
    if runs <= 1:
        return "Timed runs: one per point (--runs 1), so every time is a single run.\n"
    return (f"Timed runs: {runs} for 1 ray/px, the lattice and every adaptive point, whose row takes all its\n"
            "times from the run with the median frame time; one run for the other uniform points (4-25x\n"
            "longer renders, so their relative noise is smaller).\n")


def measured_grid(runs: int) -> str:
    """This module's description of the grid for REPORT.md, its timing paragraph for `runs`."""
    doc = __doc__
    start, end = doc.find("Timed runs:"), doc.find("The Siemens star")
    if start < 0 or end < start:
        return doc
    return doc[:start] + timing_doc(runs) + doc[end:]


@dataclasses.dataclass(frozen=True)
class Setting:
    mode: str                  # none | uniform | adaptive
    spp: int = 1
    pattern: str = ""
    eps: float | None = None
    edges: str = "vulkan"
    filter: str = "box"
    tables: str = "paper"
    geo: str = "paper"
    signature: str = "none"    # --signature: none | all | comma list of object, lights, secondary
    highlights: str = "off"    # --highlights on | off: the analytic highlight flag
    textures: str = "off"      # --textures on | off: the texture detail flag
    curvature: str = "off"     # --curvature on | off: unrefined pixels to second order
    material: str = "off"      # --edge-material on | off: the visibility map flags material boundaries
    hdr: str = "off"           # --hdr-zones on | off: zones interpolated across more than the display shows are traced
    footprint: str = "off"     # --footprint on | off: unrefined textured pixels take the texture's mean over the pixel
    orient: str = "off"        # --geo-orient on | off: geo pixels with an open case take the map's edge direction
    zones: str = "off"         # --geo-zones on | off: geo pixels trace the zones where the map saw their edge
    split: str = "off"         # --split-unflagged on | off: refined pixels the map does not flag trace their split zones
    eps_spec: str = "off"      # --eps-specular off | E: the threshold of pixels whose corners all see a mirror's or glass's image
    gaps: str = "off"          # --fill-gaps on | off: image pixels between two refined ones refine

    @property
    def label(self) -> str:
        if self.mode == "none":
            return "none"
        if self.mode == "uniform":
            return f"uniform-{self.pattern}-{self.spp}"
        return (f"adaptive-eps{self.eps:g}-{self.edges}-{self.filter}"
                f"-{self.tables}-geo{self.geo}{self.extras}")

    @property
    def extras(self) -> str:
        """Label suffix of the options beyond the paper's (empty when all are off)."""
        sig = "" if self.signature == "none" else f"-sig{self.signature.replace(',', '+')}"
        return (sig + ("-hl" if self.highlights == "on" else "") + ("-tx" if self.textures == "on" else "")
                + ("-cv" if self.curvature == "on" else "") + ("-mt" if self.material == "on" else "")
                + ("-hz" if self.hdr == "on" else "") + ("-fp" if self.footprint == "on" else "")
                + ("-go" if self.orient == "on" else "") + ("-gz" if self.zones == "on" else "")
                + ("-su" if self.split == "on" else "")
                + ("" if self.eps_spec == "off" else f"-es{self.eps_spec}")
                + ("-fg" if self.gaps == "on" else ""))

    @property
    def family(self) -> str:
        """The curve a point belongs to in the plots."""
        if self.mode == "uniform":
            return f"uniform {self.pattern}"
        if self.mode == "none":
            return "none"
        sig = "" if self.signature == "none" else f"/sig {self.signature}"
        more = (("/hl" if self.highlights == "on" else "") + ("/tx" if self.textures == "on" else "")
                + ("/cv" if self.curvature == "on" else "") + ("/mt" if self.material == "on" else "")
                + ("/hz" if self.hdr == "on" else "") + ("/fp" if self.footprint == "on" else "")
                + ("/go" if self.orient == "on" else "") + ("/gz" if self.zones == "on" else "")
                + ("/su" if self.split == "on" else "")
                + ("" if self.eps_spec == "off" else f"/es {self.eps_spec}")
                + ("/fg" if self.gaps == "on" else ""))
        return f"adaptive {self.tables}/geo {self.geo}/{self.edges}/{self.filter}{sig}{more}"

    def timed_runs(self, runs: int) -> int:
        """Long uniform renders are timed once; the compared points `runs` times."""
        return 1 if self.mode == "uniform" and self.pattern != "lattice" else runs

    def render_args(self) -> list[str]:
        if self.mode == "none":
            return ["--aa", "none"]
        if self.mode == "uniform":
            return ["--aa", "uniform", "--spp", str(self.spp), "--pattern", self.pattern]
        return ["--aa", "adaptive", "--eps", f"{self.eps:g}", "--edges", self.edges,
                "--filter", self.filter, "--tables", self.tables, "--geo-policy", self.geo,
                "--signature", self.signature, "--highlights", self.highlights, "--textures", self.textures,
                "--curvature", self.curvature, "--edge-material", self.material, "--hdr-zones", self.hdr,
                "--footprint", self.footprint, "--geo-orient", self.orient, "--geo-zones", self.zones,
                "--split-unflagged", self.split, "--eps-specular", self.eps_spec, "--fill-gaps", self.gaps]

    def analytic_args(self, geo_ss: int) -> list[str]:
        """The same adaptive setting in the analytic harness (`edges off` = no geo map)."""
        ss = geo_ss if self.edges == "vulkan" else 0
        return ["--eps", f"{self.eps:g}", "--tables", self.tables, "--geo-policy", self.geo,
                "--geo-ss", str(ss), "--filter", self.filter, "--signature", self.signature,
                "--curvature", self.curvature, "--hdr-zones", self.hdr, "--geo-orient", self.orient,
                "--geo-zones", self.zones, "--split-unflagged", self.split]


# The paper's operating point (eps 0.1, its tables): the baseline of the variations and of the
# star. The CLI's defaults are picked from the whole grid by markdown.choose_defaults.
PAPER_POINT = Setting("adaptive", eps=0.1, edges="vulkan", filter="box", tables="paper",
                      geo="paper")

LATTICE25 = Setting("uniform", spp=25, pattern="lattice")

# The base of the signature ablation: eps 0.05, tuned tables, every zone for flagged pixels, no signatures.
SIGNATURE_BASE = Setting("adaptive", eps=0.05, edges="vulkan", filter="box", tables="tuned", geo="all")
SIGNATURE_PARTS = ["object", "lights", "secondary"]


# The base of the second ablation: eps 0.05, tuned tables, geo policy paper, nothing beyond.
BEYOND_BASE = Setting("adaptive", eps=0.05, edges="vulkan", filter="box", tables="tuned", geo="paper")
BOTH = {"highlights": "on", "curvature": "on"}
BEYOND_VARIANTS = [("highlights", {"highlights": "on"}), ("curvature", {"curvature": "on"}), ("both", BOTH),
                   ("both + textures", {**BOTH, "textures": "on"}),
                   ("both + sig lights", {**BOTH, "signature": "lights"}),
                   ("both + sig secondary", {**BOTH, "signature": "secondary"}),
                   ("both + sig all", {**BOTH, "signature": "all"}),
                   ("both + sig secondary + material", {**BOTH, "signature": "secondary", "material": "on"}),
                   ("both + sig all + material", {**BOTH, "signature": "all", "material": "on"}),
                   ("both + sig all + material + textures",
                    {**BOTH, "signature": "all", "material": "on", "textures": "on"}),
                   ("both + sig all + material + hdr zones",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on"}),
                   ("both + sig all + material + hdr zones + textures",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on", "textures": "on"}),
                   ("both + sig all + material + hdr zones + footprint",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on", "footprint": "on"}),
                   ("both + sig all + material + hdr zones + footprint + geo split",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on", "footprint": "on", "geo": "split"}),
                   ("both + sig all + material + hdr zones + footprint + geo split + map orientation",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on", "footprint": "on", "geo": "split",
                     "orient": "on"}),
                   ("both + sig all + material + hdr zones + footprint + geo split + map orientation + map zones",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on", "footprint": "on", "geo": "split",
                     "orient": "on", "zones": "on"}),
                   ("both + sig all + material + hdr zones + footprint + geo split + map orientation + map zones"
                    " + unflagged split",
                    {**BOTH, "signature": "all", "material": "on", "hdr": "on", "footprint": "on", "geo": "split",
                     "orient": "on", "zones": "on", "split": "on"})]
# The mirror's threshold on top of every detector (ALL_DETECTORS + --eps-specular E).
ALL_DETECTORS = BEYOND_VARIANTS[-1][1]
EPS_SPECULAR = ["0.02", "0.015", "0.01"]
BEYOND_VARIANTS += [(f"all + eps specular {e}", {**ALL_DETECTORS, "eps_spec": e}) for e in EPS_SPECULAR]
# The gaps between refined pixels on top of the tightest threshold (they need one).
BEYOND_VARIANTS += [("all + eps specular 0.01 + fill gaps", {**ALL_DETECTORS, "eps_spec": "0.01", "gaps": "on"})]


def beyond_settings(quick: bool) -> list[Setting]:
    r = dataclasses.replace
    if quick:
        return [BEYOND_BASE, r(BEYOND_BASE, **BOTH)]
    return ([BEYOND_BASE] + [r(BEYOND_BASE, **v) for _, v in BEYOND_VARIANTS]
            + [r(BEYOND_BASE, eps=0.1, **BOTH)])


def signature_settings(quick: bool) -> list[Setting]:
    r = dataclasses.replace
    if quick:
        return [SIGNATURE_BASE, r(SIGNATURE_BASE, signature="all")]
    return ([SIGNATURE_BASE] + [r(SIGNATURE_BASE, signature=p) for p in SIGNATURE_PARTS]
            + [r(SIGNATURE_BASE, signature="all"), r(SIGNATURE_BASE, eps=0.1, signature="all")])


def uniform_settings(quick: bool) -> list[Setting]:
    spps = [4] if quick else [4, 9, 16, 25]
    patterns = ["grid"] if quick else ["grid", "stratified"]
    points = [Setting("none")]
    points += [Setting("uniform", spp=n, pattern=p) for p in patterns for n in spps]
    points.append(LATTICE25)
    return points


def variations(base: Setting) -> list[Setting]:
    """One factor at a time around base."""
    r = dataclasses.replace
    return [r(base, edges="off"), r(base, filter="mitchell"), r(base, tables="all"),
            r(base, geo="all"), r(base, tables="tuned", geo="all"),
            r(base, tables="tuned", edges="off")]


def adaptive_settings(quick: bool) -> list[Setting]:
    if quick:
        sweep = [0.05, 0.1, 0.2]
        points = [dataclasses.replace(PAPER_POINT, eps=e) for e in sweep]
        return _unique(points + [dataclasses.replace(PAPER_POINT, edges="off")] + signature_settings(True)
                       + beyond_settings(True))
    sweep = [0.02, 0.05, 0.1, 0.2]
    points = [dataclasses.replace(PAPER_POINT, eps=e, tables=t)
              for t in ("paper", "tuned") for e in sweep]
    for eps in (0.05, 0.1):
        points += variations(dataclasses.replace(PAPER_POINT, eps=eps))
    return _unique(points + signature_settings(False) + beyond_settings(False))


def star_settings(quick: bool) -> list[Setting]:
    """The star is two-tone: every eps below 1 flags the same pixels, so no eps sweep there.
    Mitchell is left out: the exact-coverage reference is a box integral."""
    if quick:
        return [PAPER_POINT]
    r = dataclasses.replace
    return ([PAPER_POINT] + [v for v in variations(PAPER_POINT) if v.filter == "box"]
            + [r(PAPER_POINT, orient="on"), r(PAPER_POINT, tables="tuned"), r(PAPER_POINT, tables="tuned", orient="on"),
               r(PAPER_POINT, tables="tuned", orient="on", zones="on"),
               r(PAPER_POINT, tables="tuned", edges="off", split="on")])


def _unique(points: list[Setting]) -> list[Setting]:
    seen, out = set(), []
    for p in points:
        if p not in seen:
            seen.add(p)
            out.append(p)
    return out
