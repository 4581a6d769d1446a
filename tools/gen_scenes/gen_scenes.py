#!/usr/bin/env python3
"""Writes the project's own scenes (scenes/*.gltf + .bin + .json rigs).

Python 3 standard library only, deterministic: the same script writes the same bytes.
Usage: tools/gen_scenes/gen_scenes.py [output_dir]   (default: <repo>/scenes)

Every scene is a glTF 2.0 file with one external .bin buffer. Objects are separate
nodes with their own translation / rotation / scale, and repeated furniture shares one
mesh between several nodes, so the loader's node-transform and instancing paths are
exercised by the project's own scenes too. The .json rig next to each .gltf adds the
camera, the lights and the render settings (format: scenes/README.md).
"""
import json
import math
import os
import struct
import sys

# ---------------------------------------------------------------------------------------
# Geometry: a Part is one material's triangles (indexed), in the object's local frame.


class Part:
    def __init__(self, material):
        self.material = material
        self.pos, self.nrm, self.uv, self.idx = [], [], [], []

    def vertex(self, p, n, uv):
        self.pos.append(tuple(p))
        self.nrm.append(tuple(n))
        self.uv.append(tuple(uv))
        return len(self.pos) - 1

    def tri(self, a, b, c):
        self.idx += [a, b, c]

    def triangles(self):
        return len(self.idx) // 3


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    length = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    return (a[0] / length, a[1] / length, a[2] / length)


def grid(part, origin, du, dv, nu, nv, uv_scale=1.0):
    """A flat nu x nv grid spanning origin + [0,1]du + [0,1]dv; front face along du x dv."""
    n = normalize(cross(du, dv))
    base = len(part.pos)
    for j in range(nv + 1):
        for i in range(nu + 1):
            s, t = i / nu, j / nv
            p = add(origin, add(scale(du, s), scale(dv, t)))
            part.vertex(p, n, (s * uv_scale, t * uv_scale))
    for j in range(nv):
        for i in range(nu):
            a = base + j * (nu + 1) + i
            part.tri(a, a + 1, a + nu + 2)
            part.tri(a, a + nu + 2, a + nu + 1)


def box(part, lo, hi, segments=1):
    """Axis-aligned box, outward normals, each face a segments x segments grid."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    dx, dy, dz = (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, z1 - z0)
    neg = lambda v: scale(v, -1.0)
    faces = [
        ((x0, y0, z1), dx, dy),            # +z
        ((x1, y0, z0), neg(dx), dy),       # -z
        ((x1, y0, z1), neg(dz), dy),       # +x
        ((x0, y0, z0), dz, dy),            # -x
        ((x0, y1, z1), dx, neg(dz)),       # +y
        ((x0, y0, z0), dx, dz),            # -y
    ]
    for origin, du, dv in faces:
        grid(part, origin, du, dv, segments, segments)


def sphere(part, centre, radius, slices, stacks, inward=False):
    """UV sphere with smooth normals; inward=True flips normals and winding (a cavity)."""
    base = len(part.pos)
    for j in range(stacks + 1):
        theta = math.pi * j / stacks
        for i in range(slices + 1):
            phi = 2.0 * math.pi * i / slices
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            p = add(centre, scale(n, radius))
            part.vertex(p, scale(n, -1.0) if inward else n, (i / slices, j / stacks))
    for j in range(stacks):
        for i in range(slices):
            a = base + j * (slices + 1) + i
            b, c, d = a + 1, a + slices + 1, a + slices + 2
            quads = [] if j == 0 else [(a, c, b)]
            quads += [] if j == stacks - 1 else [(b, c, d)]
            for t in quads:
                part.tri(*(t if not inward else (t[0], t[2], t[1])))


def lathe(part, profile, slices, cap_bottom=True):
    """Surface of revolution about +y of profile [(r, y), ...] (bottom to top), smooth."""
    base = len(part.pos)
    rings = len(profile)
    for j, (r, y) in enumerate(profile):
        # Profile tangent -> outward normal in the (r, y) plane.
        r0, y0 = profile[max(j - 1, 0)]
        r1, y1 = profile[min(j + 1, rings - 1)]
        tr, ty = r1 - r0, y1 - y0
        nr, ny = ty, -tr
        length = math.hypot(nr, ny)
        nr, ny = nr / length, ny / length
        for i in range(slices + 1):
            phi = 2.0 * math.pi * i / slices
            c, s = math.cos(phi), -math.sin(phi)
            part.vertex((r * c, y, r * s), (nr * c, ny, nr * s), (i / slices, j / (rings - 1)))
    for j in range(rings - 1):
        for i in range(slices):
            a = base + j * (slices + 1) + i
            part.tri(a, a + 1, a + slices + 2)
            part.tri(a, a + slices + 2, a + slices + 1)
    if cap_bottom:
        r, y = profile[0]
        centre = part.vertex((0.0, y, 0.0), (0.0, -1.0, 0.0), (0.5, 0.5))
        first = len(part.pos)
        for i in range(slices + 1):
            phi = 2.0 * math.pi * i / slices
            part.vertex((r * math.cos(phi), y, -r * math.sin(phi)), (0.0, -1.0, 0.0), (0.5, 0.5))
        for i in range(slices):
            part.tri(centre, first + i + 1, first + i)


def cylinder(part, radius, height, slices):
    """Closed cylinder on y in [0, height], flat caps."""
    lathe(part, [(radius, 0.0), (radius, height)], slices, cap_bottom=False)
    for y, ny in ((0.0, -1.0), (height, 1.0)):
        centre = part.vertex((0.0, y, 0.0), (0.0, ny, 0.0), (0.5, 0.5))
        first = len(part.pos)
        for i in range(slices + 1):
            phi = 2.0 * math.pi * i / slices
            part.vertex((radius * math.cos(phi), y, -radius * math.sin(phi)), (0.0, ny, 0.0), (0.5, 0.5))
        for i in range(slices):
            if ny > 0:
                part.tri(centre, first + i, first + i + 1)
            else:
                part.tri(centre, first + i + 1, first + i)


def torus(part, major, minor, slices, sides):
    base = len(part.pos)
    for j in range(sides + 1):
        v = 2.0 * math.pi * j / sides
        for i in range(slices + 1):
            u = 2.0 * math.pi * i / slices
            n = (math.cos(v) * math.cos(u), math.sin(v), -math.cos(v) * math.sin(u))
            ring = (major * math.cos(u), 0.0, -major * math.sin(u))
            part.vertex(add(ring, scale(n, minor)), n, (i / slices, j / sides))
    for j in range(sides):
        for i in range(slices):
            a = base + j * (slices + 1) + i
            part.tri(a, a + 1, a + slices + 2)
            part.tri(a, a + slices + 2, a + slices + 1)


# ---------------------------------------------------------------------------------------
# glTF writer


def material(name, base, metallic=0.0, roughness=0.8, transmission=0.0, ior=None,
             attenuation=None, emissive=None, double_sided=False, thickness=None):
    """thickness: the glass is a solid (KHR_materials_volume); without it a transmissive
    surface is thin-walled by the spec (a sheet: no bending, no absorption)."""
    m = {"name": name,
         "pbrMetallicRoughness": {"baseColorFactor": list(base) + [1.0],
                                  "metallicFactor": metallic, "roughnessFactor": roughness}}
    ext = {}
    if transmission > 0.0:
        ext["KHR_materials_transmission"] = {"transmissionFactor": transmission}
    if ior is not None:
        ext["KHR_materials_ior"] = {"ior": ior}
    if attenuation is not None or thickness is not None:
        ext["KHR_materials_volume"] = {"thicknessFactor": thickness if thickness is not None else 0.5}
    if attenuation is not None:
        colour, distance = attenuation
        ext["KHR_materials_volume"].update({"attenuationColor": list(colour), "attenuationDistance": distance})
    if emissive is not None:
        m["emissiveFactor"] = list(emissive)
    if ext:
        m["extensions"] = ext
    if double_sided:
        m["doubleSided"] = True
    return m


def quat_axis_angle(axis, degrees):
    a = normalize(axis)
    h = math.radians(degrees) * 0.5
    return [a[0] * math.sin(h), a[1] * math.sin(h), a[2] * math.sin(h), math.cos(h)]


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


class GltfWriter:
    def __init__(self, materials):
        self.materials = materials
        self.names = [m["name"] for m in materials]
        self.blob = bytearray()
        self.views, self.accessors, self.meshes, self.nodes = [], [], [], []
        self.animation_channels, self.animation_samplers = [], []
        self.roots = None  # scene root nodes; None = every node
        self.cameras = []
        self.extensions = {}  # document-level extensions (e.g. KHR_lights_punctual)
        self.triangles = 0

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data),
                           "target": target})
        self.blob += data
        return len(self.views) - 1

    def _floats(self, rows, kind):
        data = b"".join(struct.pack("<%df" % len(r), *r) for r in rows)
        view = self._view(data, 34962)
        acc = {"bufferView": view, "componentType": 5126, "count": len(rows), "type": kind}
        if kind in ("VEC3", "SCALAR"):  # POSITION and animation inputs need min/max (spec)
            n = 3 if kind == "VEC3" else 1
            acc["min"] = [min(f32(r[k]) for r in rows) for k in range(n)]
            acc["max"] = [max(f32(r[k]) for r in rows) for k in range(n)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def _indices(self, idx):
        small = max(idx) < 65536
        data = struct.pack("<%d%s" % (len(idx), "H" if small else "I"), *idx)
        view = self._view(data, 34963)
        self.accessors.append({"bufferView": view, "componentType": 5123 if small else 5125,
                               "count": len(idx), "type": "SCALAR"})
        return len(self.accessors) - 1

    def mesh(self, name, parts):
        prims = []
        for part in parts:
            if not part.idx:
                continue
            prims.append({"attributes": {"POSITION": self._floats(part.pos, "VEC3"),
                                         "NORMAL": self._floats(part.nrm, "VEC3"),
                                         "TEXCOORD_0": self._floats(part.uv, "VEC2")},
                          "indices": self._indices(part.idx),
                          "material": self.names.index(part.material), "mode": 4})
        self.meshes.append({"name": name, "primitives": prims,
                            "_tris": sum(p.triangles() for p in parts)})
        return len(self.meshes) - 1

    def node(self, name, mesh, translation=None, rotation=None, scale_=None):
        n = {"name": name, "mesh": mesh}
        if translation:
            n["translation"] = list(translation)
        if rotation:
            n["rotation"] = rotation
        if scale_:
            n["scale"] = list(scale_) if isinstance(scale_, (list, tuple)) else [scale_] * 3
        self.nodes.append(n)
        self.triangles += self.meshes[mesh]["_tris"]

    def add_node(self, node):
        """Any node (camera, light, group); returns its index."""
        self.nodes.append(node)
        return len(self.nodes) - 1

    def animate(self, node, path, interpolation, times, values):
        """One channel; CUBICSPLINE values are (in-tangent, value, out-tangent) per key."""
        kind = "VEC4" if path == "rotation" else "VEC3"
        sampler = {"input": self._floats([(t,) for t in times], "SCALAR"),
                   "output": self._floats([tuple(v) for v in values], kind),
                   "interpolation": interpolation}
        self.animation_samplers.append(sampler)
        self.animation_channels.append({"sampler": len(self.animation_samplers) - 1,
                                        "target": {"node": node, "path": path}})

    def write(self, directory, stem):
        for m in self.meshes:
            del m["_tris"]
        used = sorted({e for m in self.materials for e in m.get("extensions", {})})
        doc = {"asset": {"version": "2.0", "generator": "zigzag tools/gen_scenes/gen_scenes.py"},
               "scene": 0,
               "scenes": [{"name": stem, "nodes": self.roots if self.roots is not None else list(range(len(self.nodes)))}],
               "nodes": self.nodes, "meshes": self.meshes, "materials": self.materials,
               "accessors": self.accessors, "bufferViews": self.views,
               "buffers": [{"uri": stem + ".bin", "byteLength": len(self.blob)}]}
        used = sorted(set(used) | set(self.extensions))
        if used:
            doc["extensionsUsed"] = used
        if self.extensions:
            doc["extensions"] = self.extensions
        if self.animation_channels:
            doc["animations"] = [{"name": "motion", "channels": self.animation_channels,
                                  "samplers": self.animation_samplers}]
        if self.cameras:
            doc["cameras"] = self.cameras
        with open(os.path.join(directory, stem + ".bin"), "wb") as f:
            f.write(bytes(self.blob))
        with open(os.path.join(directory, stem + ".gltf"), "w", newline="\n") as f:
            json.dump(doc, f, indent=1, sort_keys=False)
            f.write("\n")
        return self.triangles


def write_rig(directory, stem, rig):
    with open(os.path.join(directory, stem + ".json"), "w", newline="\n") as f:
        json.dump(rig, f, indent=2)
        f.write("\n")


# ---------------------------------------------------------------------------------------
# Scenes


def room(out):
    """Cornell-style room 6 x 4 x 6 m, open towards +z, with furniture; ~10k triangles."""
    mats = [material("white_wall", (0.75, 0.75, 0.72)),
            material("red_wall", (0.70, 0.12, 0.10)),
            material("green_wall", (0.12, 0.55, 0.15)),
            material("floor", (0.55, 0.45, 0.35), roughness=0.6),
            material("wood", (0.45, 0.28, 0.15), roughness=0.5),
            material("fabric", (0.20, 0.30, 0.60), roughness=1.0),
            material("mirror", (0.95, 0.95, 0.95), metallic=1.0, roughness=0.0),
            material("gold", (1.0, 0.78, 0.34), metallic=1.0, roughness=0.05),
            material("ceramic", (0.85, 0.85, 0.90), roughness=0.1),
            material("plastic", (0.85, 0.65, 0.10), roughness=0.3),
            material("chrome", (0.90, 0.90, 0.92), metallic=1.0, roughness=0.1)]
    w = GltfWriter(mats)
    W, H, D, N = 3.0, 4.0, 3.0, 20   # half width, height, half depth, wall grid

    shell = {m: Part(m) for m in ("white_wall", "red_wall", "green_wall", "floor")}
    grid(shell["floor"], (-W, 0, D), (2 * W, 0, 0), (0, 0, -2 * D), N, N, uv_scale=6)   # floor, up
    grid(shell["white_wall"], (-W, H, -D), (2 * W, 0, 0), (0, 0, 2 * D), N, N)       # ceiling, down
    grid(shell["white_wall"], (-W, 0, -D), (2 * W, 0, 0), (0, H, 0), N, N)           # back, +z
    grid(shell["red_wall"], (-W, 0, D), (0, 0, -2 * D), (0, H, 0), N, N)             # left, +x
    grid(shell["green_wall"], (W, 0, -D), (0, 0, 2 * D), (0, H, 0), N, N)            # right, -x
    w.node("room", w.mesh("room_shell", list(shell.values())))

    # Table: top + 4 legs, 1.6 x 0.9 m, 0.75 m high.
    table = Part("wood")
    box(table, (-0.8, 0.70, -0.45), (0.8, 0.75, 0.45), segments=2)
    for sx in (-0.72, 0.72):
        for sz in (-0.37, 0.37):
            box(table, (sx - 0.04, 0.0, sz - 0.04), (sx + 0.04, 0.70, sz + 0.04))
    w.node("table", w.mesh("table", [table]), translation=(0.2, 0.0, -0.4))

    # Chair (one mesh, three instances): wooden frame, fabric seat and back.
    frame, cushion = Part("wood"), Part("fabric")
    for sx in (-0.2, 0.2):
        for sz in (-0.2, 0.2):
            box(frame, (sx - 0.025, 0.0, sz - 0.025), (sx + 0.025, 0.45, sz + 0.025))
    box(cushion, (-0.23, 0.45, -0.23), (0.23, 0.52, 0.23), segments=2)
    box(frame, (-0.23, 0.52, -0.25), (0.23, 1.0, -0.21))
    chair = w.mesh("chair", [frame, cushion])
    w.node("chair_front", chair, translation=(0.3, 0.0, 0.45), rotation=quat_axis_angle((0, 1, 0), 180))
    w.node("chair_left", chair, translation=(-0.85, 0.0, -0.35), rotation=quat_axis_angle((0, 1, 0), 80))
    w.node("chair_corner", chair, translation=(2.3, 0.0, 1.6), rotation=quat_axis_angle((0, 1, 0), -35),
           scale_=0.9)

    # Shelf against the back wall, with a vase and books (boxes) on it.
    shelf = Part("wood")
    box(shelf, (-0.6, 0.0, -0.15), (-0.57, 1.8, 0.15))
    box(shelf, (0.57, 0.0, -0.15), (0.6, 1.8, 0.15))
    for y in (0.05, 0.6, 1.2, 1.77):
        box(shelf, (-0.57, y - 0.03, -0.15), (0.57, y, 0.15))
    w.node("shelf", w.mesh("shelf", [shelf]), translation=(-1.9, 0.0, -2.8))

    books = Part("plastic")
    for k, (x, h) in enumerate(((-0.5, 0.25), (-0.42, 0.3), (-0.34, 0.22), (-0.26, 0.28))):
        box(books, (x, 0.6, -0.1), (x + 0.07, 0.6 + h, 0.1))
    w.node("books", w.mesh("books", [books]), translation=(-1.9, 0.0, -2.8))

    vase = Part("ceramic")
    profile = [(0.10 + 0.06 * math.sin(math.pi * t / 23.0 * 1.6) + 0.03 * (t / 23.0), 0.5 * t / 23.0)
               for t in range(24)]
    lathe(vase, profile, 48)
    w.node("vase", w.mesh("vase", [vase]), translation=(0.45, 0.75, -0.55))

    ball = Part("gold")
    sphere(ball, (0.0, 0.0, 0.0), 1.0, 48, 24)
    w.node("gold_sphere", w.mesh("sphere", [ball]), translation=(-0.2, 0.93, -0.35), scale_=0.18)

    ring = Part("chrome")
    torus(ring, 0.3, 0.08, 32, 16)
    w.node("torus", w.mesh("torus", [ring]), translation=(1.9, 0.42, -1.2),
           rotation=quat_axis_angle((1, 0, 0.3), 70))

    # Mirror panel on the right wall: a thin framed slab, slightly proud of the wall.
    glass, rim = Part("mirror"), Part("wood")
    box(glass, (-0.01, 0.0, -0.7), (0.0, 1.4, 0.7))
    box(rim, (-0.005, -0.05, -0.75), (0.005, 1.45, 0.75))
    w.node("mirror", w.mesh("mirror", [glass, rim]), translation=(W - 0.02, 1.1, -0.6))

    crates = Part("plastic")
    box(crates, (-0.3, 0.0, -0.3), (0.3, 0.6, 0.3), segments=2)
    crate = w.mesh("crate", [crates])
    w.node("crate_a", crate, translation=(1.8, 0.0, 0.4), rotation=quat_axis_angle((0, 1, 0), 25))
    w.node("crate_b", crate, translation=(1.75, 0.6, 0.45), rotation=quat_axis_angle((0, 1, 0), 50),
           scale_=0.6)
    w.node("crate_c", crate, translation=(-2.2, 0.0, 1.2), scale_=(1.2, 0.5, 0.8))
    tris = w.write(out, "room")

    lights = []
    for i, x in enumerate((-1.8, 0.0, 1.8)):
        for k, z in enumerate((-1.8, 0.0, 1.8)):
            warm = (1.0, 0.92, 0.8) if (i + k) % 2 == 0 else (0.9, 0.95, 1.0)
            lights.append({"type": "point", "name": "ceiling_%d%d" % (i, k),
                           "position": [x, 3.4, z], "color": list(warm), "intensity": 1.6})
    write_rig(out, "room", {
        "name": "room",
        "description": "Cornell-style room with furniture, a mirror and 9 point lights",
        "model": "room.gltf",
        # The open front (z = 3) exactly fills the 40 degree view from z = 8.4: no outside.
        "camera": {"name": "front", "eye": [0.0, 2.0, 8.4], "target": [0.0, 2.0, 0.0], "up": [0, 1, 0],
                   "yfov_deg": 40.0},
        "lights": lights,
        "background": [0.0, 0.0, 0.0],
        "exposure": 1.0, "max_depth": 2, "width": 1024, "height": 1024})
    return tris


def checker_floor(w, half, squares, y=0.0):
    light, dark = Part("checker_light"), Part("checker_dark")
    size = 2.0 * half / squares
    for j in range(squares):
        for i in range(squares):
            part = light if (i + j) % 2 == 0 else dark
            x0, z0 = -half + i * size, -half + j * size
            grid(part, (x0, y, z0 + size), (size, 0, 0), (0, 0, -size), 1, 1)
    return w.mesh("checker_floor", [light, dark])


def glass(out):
    mats = [material("checker_light", (0.85, 0.85, 0.85)),
            material("checker_dark", (0.08, 0.08, 0.10)),
            material("backdrop", (0.60, 0.35, 0.20), roughness=0.9),
            material("glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5, thickness=0.5),
            material("tinted_glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5,
                     attenuation=((0.35, 0.75, 0.9), 0.6))]
    w = GltfWriter(mats)
    w.node("floor", checker_floor(w, 4.0, 16))
    back = Part("backdrop")
    stripe = Part("checker_light")
    for k in range(8):
        grid(back if k % 2 == 0 else stripe, (-4.0 + k, 0.0, 0.0), (1.0, 0, 0), (0, 3.0, 0), 1, 1)
    w.node("backdrop", w.mesh("backdrop", [back, stripe]), translation=(0, 0, -2.5))

    solid = Part("glass")
    sphere(solid, (0, 0, 0), 1.0, 64, 32)
    w.node("solid_sphere", w.mesh("solid_sphere", [solid]), translation=(-1.6, 0.6, 0.2), scale_=0.6)

    # Hollow sphere: outer shell plus an inner shell with inverted normals (a glass wall
    # 0.08 thick enclosing air), as in a soap bubble or a glass Christmas ball.
    hollow = Part("glass")
    sphere(hollow, (0, 0, 0), 0.6, 64, 32)
    sphere(hollow, (0, 0, 0), 0.52, 64, 32, inward=True)
    w.node("hollow_sphere", w.mesh("hollow_sphere", [hollow]), translation=(0.0, 0.6, 0.9))

    # The block and the cylinder stand 1 mm above the floor: a glass bottom face coplanar
    # with the floor makes rays refracted out through it start on the floor's plane, where
    # rounding decides whether they hit the floor or pass under it to the background (a
    # speckle of black in the floor seen through the glass, in every render and reference).
    block = Part("glass")
    box(block, (-0.45, 0.0, -0.3), (0.45, 0.9, 0.3))
    w.node("block", w.mesh("block", [block]), translation=(1.5, 0.001, -0.2),
           rotation=quat_axis_angle((0, 1, 0), -30))

    tube = Part("tinted_glass")
    cylinder(tube, 0.35, 1.3, 64)
    w.node("tinted_cylinder", w.mesh("cylinder", [tube]), translation=(-0.2, 0.001, -1.2))
    tris = w.write(out, "glass")
    write_rig(out, "glass", {
        "name": "glass",
        "description": "solid, hollow and tinted glass over a checker floor, 3 point lights",
        "model": "glass.gltf",
        "camera": {"name": "front", "eye": [0.0, 2.2, 6.3], "target": [0.0, 0.7, 0.0], "yfov_deg": 40.0},
        "lights": [
            {"type": "point", "name": "key", "position": [3.0, 4.0, 3.0], "color": [1.0, 0.95, 0.9], "intensity": 12.0},
            {"type": "point", "name": "fill", "position": [-3.5, 3.0, 2.0], "color": [0.85, 0.9, 1.0], "intensity": 6.0},
            {"type": "point", "name": "back", "position": [0.5, 3.5, -2.0], "intensity": 4.0}],
        "background": [0.05, 0.06, 0.08],
        "exposure": 1.0, "max_depth": 2, "width": 1024, "height": 1024})
    return tris


def default(out):
    mats = [material("checker_light", (0.8, 0.8, 0.8)),
            material("checker_dark", (0.2, 0.2, 0.25)),
            material("red_plastic", (0.8, 0.1, 0.08), roughness=0.4),
            material("steel", (0.9, 0.9, 0.9), metallic=1.0, roughness=0.05),
            material("glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5, thickness=0.5),
            material("blue", (0.15, 0.3, 0.8), roughness=0.7)]
    w = GltfWriter(mats)
    w.node("floor", checker_floor(w, 3.0, 8))
    red = Part("red_plastic")
    sphere(red, (0, 0, 0), 1.0, 24, 12)
    w.node("red_sphere", w.mesh("red_sphere", [red]), translation=(-1.1, 0.5, 0.0), scale_=0.5)
    steel = Part("steel")
    sphere(steel, (0, 0, 0), 1.0, 24, 12)
    w.node("mirror_sphere", w.mesh("mirror_sphere", [steel]), translation=(0.2, 0.6, -0.6), scale_=0.6)
    glass_ball = Part("glass")
    sphere(glass_ball, (0, 0, 0), 0.4, 24, 12)
    w.node("glass_sphere", w.mesh("glass_sphere", [glass_ball]), translation=(0.9, 0.4, 0.7))
    cube = Part("blue")
    box(cube, (-0.3, 0.0, -0.3), (0.3, 0.6, 0.3))
    w.node("cube", w.mesh("cube", [cube]), translation=(-0.2, 0.0, 1.0),
           rotation=quat_axis_angle((0, 1, 0), 30))
    tris = w.write(out, "default")
    write_rig(out, "default", {
        "name": "default",
        "description": "small test scene: diffuse, mirror and glass spheres, a cube, 2 lights",
        "model": "default.gltf",
        "camera": {"name": "front", "eye": [0.0, 1.9, 4.2], "target": [0.0, 0.4, 0.0], "yfov_deg": 40.0},
        "lights": [
            {"type": "point", "name": "key", "position": [2.5, 4.0, 3.0], "intensity": 10.0},
            {"type": "point", "name": "fill", "position": [-3.0, 2.5, 1.0], "color": [0.8, 0.85, 1.0], "intensity": 4.0}],
        "background": [0.1, 0.12, 0.16],
        "exposure": 1.0, "max_depth": 2, "width": 512, "height": 512})
    return tris


def animated(out):
    """2 s at 24 fps: objects moving with each interpolation mode, a light moving with
    its node, and the camera orbiting as the child of a rotating node (a hierarchy)."""
    mats = [material("checker_light", (0.8, 0.8, 0.8)),
            material("checker_dark", (0.2, 0.2, 0.25)),
            material("red_plastic", (0.8, 0.1, 0.08), roughness=0.4),
            material("steel", (0.9, 0.9, 0.9), metallic=1.0, roughness=0.05),
            material("green", (0.2, 0.7, 0.25), roughness=0.6),
            material("blue", (0.15, 0.3, 0.8), roughness=0.7)]
    w = GltfWriter(mats)
    w.node("floor", checker_floor(w, 3.0, 8))
    red = Part("red_plastic")
    sphere(red, (0, 0, 0), 0.4, 20, 10)
    w.node("red_sphere", w.mesh("red_sphere", [red]), translation=(-1.2, 0.4, 0.6))
    # LINEAR translation: across and back.
    w.animate(len(w.nodes) - 1, "translation", "LINEAR", [0.0, 1.0, 2.0],
              [(-1.2, 0.4, 0.6), (1.2, 0.4, 0.6), (-1.2, 0.4, 0.6)])
    cube = Part("blue")
    box(cube, (-0.35, 0.0, -0.35), (0.35, 0.7, 0.35))
    w.node("cube", w.mesh("cube", [cube]), translation=(0.0, 0.0, -0.8))
    # LINEAR rotation (slerp): a full turn about y in 90-degree keys.
    w.animate(len(w.nodes) - 1, "rotation", "LINEAR", [0.0, 0.5, 1.0, 1.5, 2.0],
              [quat_axis_angle((0, 1, 0), a) for a in (0, 90, 180, 270, 360)])
    steel = Part("steel")
    sphere(steel, (0, 0, 0), 0.35, 20, 10)
    w.node("steel_sphere", w.mesh("steel_sphere", [steel]), translation=(1.3, 0.35, -0.2))
    # STEP translation: hops between three heights.
    w.animate(len(w.nodes) - 1, "translation", "STEP", [0.0, 0.5, 1.0, 1.5],
              [(1.3, 0.35, -0.2), (1.3, 0.9, -0.2), (1.3, 0.35, -0.2), (1.3, 0.7, -0.2)])
    green = Part("green")
    box(green, (-0.25, 0.0, -0.25), (0.25, 0.5, 0.25))
    w.node("pulse", w.mesh("pulse", [green]), translation=(-1.4, 0.0, -1.0))
    # CUBICSPLINE scale: grows and shrinks with eased tangents (in, value, out per key).
    w.animate(len(w.nodes) - 1, "scale", "CUBICSPLINE", [0.0, 1.0, 2.0],
              [(0, 0, 0), (1, 1, 1), (0, 1.5, 0),
               (0, 0, 0), (1.3, 1.8, 1.3), (0, 0, 0),
               (0, -1.5, 0), (1, 1, 1), (0, 0, 0)])
    # A point light on its own node, circling above (KHR_lights_punctual).
    w.extensions["KHR_lights_punctual"] = {"lights": [
        {"name": "moving_key", "type": "point", "color": [1.0, 0.95, 0.85], "intensity": 10.0}]}
    light = w.add_node({"name": "moving_key", "translation": [2.5, 4.0, 2.5],
                        "extensions": {"KHR_lights_punctual": {"light": 0}}})
    w.animate(light, "translation", "LINEAR", [0.0, 1.0, 2.0],
              [(2.5, 4.0, 2.5), (-2.5, 4.0, 2.5), (2.5, 4.0, 2.5)])
    # The camera: a child of a pivot rotating 60 degrees about y (keys 15 degrees apart).
    w.cameras.append({"name": "orbit", "type": "perspective",
                      "perspective": {"yfov": math.radians(40.0), "aspectRatio": 1.0, "znear": 0.05, "zfar": 100.0}})
    camera = w.add_node({"name": "orbit_camera", "camera": 0, "translation": [0.0, 1.9, 4.2],
                         "rotation": quat_axis_angle((1, 0, 0), -20.0)})
    pivot = w.add_node({"name": "orbit_pivot", "children": [camera]})
    w.animate(pivot, "rotation", "LINEAR", [0.0, 0.5, 1.0, 1.5, 2.0],
              [quat_axis_angle((0, 1, 0), a) for a in (-30, -15, 0, 15, 30)])
    w.roots = [i for i in range(len(w.nodes)) if i != camera]
    tris = w.write(out, "animated")
    write_rig(out, "animated", {
        "name": "animated",
        "description": "2 s animation: LINEAR/STEP/CUBICSPLINE motion, a moving light, an orbiting camera",
        "model": "animated.gltf",
        "lights": [
            {"type": "point", "name": "fill", "position": [-3.0, 2.5, 1.0], "color": [0.8, 0.85, 1.0], "intensity": 4.0}],
        "background": [0.1, 0.12, 0.16],
        "exposure": 1.0, "max_depth": 2, "width": 256, "height": 256,
        "fps": 24, "frames": [0, 47]})
    return tris


def third_party(out):
    # ToyCar is 7 cm long; its own cameras frame it. Camera002 (the README view) shows
    # the whole car in a square frame.
    write_rig(out, "car", {
        "name": "car",
        "description": "Khronos ToyCar (CC0): transmission glass, textures; model cameras",
        "model": "assets:toycar/glTF/ToyCar.gltf",
        "use_model_cameras": True, "default_camera": "Camera002",
        "lights": [
            {"type": "point", "name": "key", "position": [-0.08, 0.12, 0.12], "color": [1.0, 0.96, 0.9], "intensity": 0.03},
            {"type": "point", "name": "rim", "position": [0.1, 0.08, -0.1], "color": [0.8, 0.9, 1.0], "intensity": 0.015}],
        "background": [0.18, 0.2, 0.24],
        "exposure": 1.0, "max_depth": 3, "width": 1024, "height": 1024})
    # GlassVaseFlowers: two vases 12 cm apart (alpha-blend left, transmission right).
    write_rig(out, "vase", {
        "name": "vase",
        "description": "Khronos GlassVaseFlowers (CC0): transmission + volume glass, textured flowers",
        "model": "assets:glassvaseflowers/glTF/GlassVaseFlowers.gltf",
        "camera": {"name": "front", "eye": [0.055, 0.16, 0.42], "target": [0.055, 0.1, 0.0], "yfov_deg": 34.0},
        "lights": [
            {"type": "point", "name": "key", "position": [0.3, 0.4, 0.3], "color": [1.0, 0.95, 0.9], "intensity": 0.6},
            {"type": "point", "name": "fill", "position": [-0.3, 0.25, 0.25], "color": [0.85, 0.9, 1.0], "intensity": 0.3},
            {"type": "point", "name": "back", "position": [0.05, 0.35, -0.3], "intensity": 0.3}],
        "background": [0.45, 0.5, 0.55],
        "exposure": 1.0, "max_depth": 3, "width": 1024, "height": 1024})
    # LightsPunctualLamp: 1.9 m tall standing lamp with 5 point lights of its own.
    write_rig(out, "lamp", {
        "name": "lamp",
        "description": "Khronos LightsPunctualLamp (CC-BY-4.0, DGG): its 5 punctual lights",
        "model": "assets:lightspunctuallamp/glTF/LightsPunctualLamp.gltf",
        "camera": {"name": "front", "eye": [1.2, 1.3, 2.9], "target": [0.25, 0.92, 0.0], "yfov_deg": 38.0},
        "background": [0.02, 0.02, 0.03],
        # Its lights are 15..180 cd at 1-2 m: exposure 0.1 keeps the lit side in range.
        "exposure": 0.1, "max_depth": 2, "width": 768, "height": 1024})


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(here, "..", "..", "scenes"))
    os.makedirs(out, exist_ok=True)
    for name, fn in (("room", room), ("glass", glass), ("default", default), ("animated", animated)):
        print("%s: %d triangles" % (name, fn(out)))
    third_party(out)
    print("car, vase, lamp: rigs written")


if __name__ == "__main__":
    main()
