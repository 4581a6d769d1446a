#!/usr/bin/env python3
"""Writes the seed corpus of the loader fuzzers into tools/fuzz/corpus/{gltf,glb,json}.

Seeds are small on purpose (libFuzzer mutates them byte by byte): the repository's own
small scenes/*.gltf and scenes/*.json, plus hand-made self-contained glTF files (data:
URIs) covering the loader's paths: indexed and non-indexed triangles, strips, fans,
points/lines, normals, uvs, materials with the extensions we read, an embedded PNG
texture, cameras, KHR_lights_punctual, node hierarchies. GLB seeds are the same models in
the binary container. Deterministic: re-running gives the same bytes.
"""
import base64, json, os, pathlib, shutil, struct, zlib

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "tools" / "fuzz" / "corpus"


def png_2x2():
    raw = b"".join(b"\x00" + bytes(row) for row in ([255, 0, 0, 0, 255, 0], [0, 0, 255, 255, 255, 255]))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def model(mode=4, indexed=True, extras=True):
    pos = [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0]
    nrm = [0, 0, 1] * 4
    uv = [0, 0, 1, 0, 0, 1, 1, 1]
    idx = [0, 1, 2, 2, 1, 3]
    blob = struct.pack("<12f", *pos) + struct.pack("<12f", *nrm) + struct.pack("<8f", *uv) + struct.pack("<6H", *idx)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
             {"buffer": 0, "byteOffset": 96, "byteLength": 32}, {"buffer": 0, "byteOffset": 128, "byteLength": 12}]
    acc = [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
           {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
           {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
           {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    prim = {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "mode": mode, "material": 0}
    if indexed:
        prim["indices"] = 3
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"name": "root", "children": [1, 2, 3], "rotation": [0, 0.38268343, 0, 0.9238795]},
                     {"mesh": 0, "translation": [0, 0, -1], "scale": [2, 2, 2]},
                     {"camera": 0, "translation": [0.5, 0.5, 3]},
                     {"extensions": {"KHR_lights_punctual": {"light": 0}}, "matrix":
                      [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 2, 2, 1]}],
           "meshes": [{"name": "quad", "primitives": [prim]}],
           "accessors": acc, "bufferViews": views,
           "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01, "zfar": 100}}],
           "materials": [{"name": "m", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1],
                                                                 "metallicFactor": 0, "roughnessFactor": 0.5}}]}
    if extras:
        doc["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior",
                                 "KHR_materials_volume", "KHR_texture_transform", "KHR_materials_emissive_strength"]
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 5, "color": [1, 1, 1],
                                                                 "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}}
        doc["materials"].append({"name": "glass", "emissiveFactor": [0.1, 0, 0],
                                 "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                                                "KHR_materials_ior": {"ior": 1.4},
                                                "KHR_materials_volume": {"attenuationColor": [0.9, 0.5, 0.5],
                                                                         "attenuationDistance": 0.3},
                                                "KHR_materials_emissive_strength": {"emissiveStrength": 2}}})
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
            "index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.1, 0], "scale": [2, 2], "rotation": 0.3}}}
        doc["textures"] = [{"source": 0}]
        doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png_2x2()).decode()}]
    else:
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 5}]}}
        doc["extensionsUsed"] = ["KHR_lights_punctual"]
    return doc, blob


def as_gltf(doc, blob):
    d = json.loads(json.dumps(doc))
    d["buffers"] = [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(blob).decode()}]
    return json.dumps(d, separators=(",", ":")).encode()


def as_glb(doc, blob):
    d = json.loads(json.dumps(doc))
    d["buffers"] = [{"byteLength": len(blob)}]
    js = json.dumps(d, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    bin_ = blob + b"\0" * (-len(blob) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(bin_), 0x004E4942) + bin_
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def main():
    for sub in ("gltf", "glb", "json"):
        shutil.rmtree(OUT / sub, ignore_errors=True)
        (OUT / sub).mkdir(parents=True)
    variants = {"tri_indexed": model(4, True), "tri_plain": model(4, False, False), "strip": model(5, True, False),
                "fan": model(6, False, False), "lines": model(1, True, False)}
    for name, (doc, blob) in variants.items():
        (OUT / "gltf" / f"{name}.gltf").write_bytes(as_gltf(doc, blob))
        (OUT / "glb" / f"{name}.glb").write_bytes(as_glb(doc, blob))
    # The repository's own small glTF scenes (their .bin buffers sit next to the fuzz input).
    for p in sorted((ROOT / "scenes").glob("*.gltf")):
        if p.stat().st_size <= 32 * 1024:
            shutil.copy(p, OUT / "gltf" / p.name)
    # Rigs: the repository's scenes/*.json as they are (the harness provides their models)
    # and one per small model.
    for p in sorted((ROOT / "scenes").glob("*.json")):
        shutil.copy(p, OUT / "json" / p.name)
    rig = {"model": "tiny.gltf", "transform": {"scale": 2, "rotate_y_deg": 30, "translate": [0, 1, 0]},
           "camera": {"eye": [0, 1, 5], "target": [0, 0, 0], "yfov_deg": 40, "aspect": 1.5},
           "cameras": [{"name": "side", "eye": [5, 1, 0], "target": [0, 0, 0], "up": [0, 1, 0]}],
           "default_camera": "side", "use_model_cameras": True, "replace_lights": True,
           "lights": [{"type": "point", "position": [0, 3, 0], "color": [1, 0.9, 0.8], "intensity": 10, "range": 20},
                      {"type": "spot", "position": [0, 3, 3], "direction": [0, -1, -1], "inner_cone_deg": 10,
                       "outer_cone_deg": 30},
                      {"type": "directional", "direction": [1, -1, 0], "intensity": 2}],
           "background": [0.1, 0.2, 0.3], "exposure": 1.5, "max_depth": 4, "width": 64, "height": 48,
           "materials_override": {"m": {"base_color": 0.5, "metallic": 1, "roughness": 0.1, "transmission": 0,
                                        "ior": 1.3, "emissive": [0, 0, 0], "attenuation_color": 0.5,
                                        "attenuation_distance": 2, "double_sided": True}}}
    (OUT / "json" / "tiny_rig.json").write_text(json.dumps(rig, indent=1))
    (OUT / "json" / "matrix_rig.json").write_text(json.dumps(
        {"model": "tiny.glb", "transform": {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}}))
    # The models the harness places next to every fuzzed rig.
    (OUT.parent / "tiny.gltf").write_bytes(as_gltf(*variants["tri_indexed"]))
    (OUT.parent / "tiny.glb").write_bytes(as_glb(*variants["tri_indexed"]))


if __name__ == "__main__":
    main()
