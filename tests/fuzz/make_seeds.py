#!/usr/bin/env python3
"""Writes the scene_fuzzer seeds for the glTF (flat, instanced, emissive), GLB, MTL (with and without
emission), PNG, emissive-scene, path-traced-scene and textured-scene parsers into
tests/fuzz/corpus/ (run from anywhere: python3 tests/fuzz/make_seeds.py). Each seed is one fuzzer
input: the selector byte of scene_fuzzer.cpp, then the parser's bytes. Standard library only (no
PIL): PNGs are written with zlib by hand.

The JPEG and EXR seeds (image_jpeg_baseline, image_exr_zip, image_exr_none) are not written here:
they were made once with libjpeg-turbo (8x8 RGB, quality 50, baseline, optimized Huffman) and
OpenEXR's RgbaOutputFile (4x4 half RGBA, ZIP and no compression), and are kept as they are, with
their magic bytes dropped as described in scene_fuzzer.cpp. The spline-patch seed (patches_two:
selector 8, then tests/data/patches/two_patches.inc) and the sphere-file seeds (spheres_plain,
spheres_scalar: selector 9, then a 32-byte FLSPHERE header and 16- or 20-byte records) and the
instancing scene (scene_instances: selector 0, a JSON scene with "meshes" and "instance" objects)
were written once by hand from those formats, as were the volume seeds (volume_nrrd_raw,
volume_nrrd_gzip: selector 11 and an attached NRRD file; volume_raw_u16: selector 12, the 16-byte
header and 48 bytes of voxels; scene_volumes: selector 0, a JSON scene with all three volume modes;
volume_vdb_*: selector 13, then a fixture of tests/data/volumes written by OpenVDB 10), and the
lightfield seed (lightfield_slab: selector 14, then `frameless bake-lightfield default --uv 2x2
--st 4x4 --spp 1`'s file).
"""
import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")

# Selector bytes (scene_fuzzer.cpp).
SCENE, GLTF, GLB, MTL, IMAGE, SCENE_TEX = 0, 3, 4, 5, 6, 7
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def png(width, height, color_type, depth, rows, chunks=(), interlace=0):
    """A PNG of the given rows (each a bytes of already packed pixels, filter 0 added here)."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    ihdr = struct.pack(">IIBBBBB", width, height, depth, color_type, 0, 0, interlace)
    raw = b"".join(b"\x00" + r for r in rows)
    out = PNG_MAGIC + chunk(b"IHDR", ihdr)
    for kind, data in chunks:
        out += chunk(kind, data)
    return out + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def png_rgba_4x4():
    rows = []
    for y in range(4):
        rows.append(b"".join(bytes([x * 64, y * 64, 200, 255 if (x + y) % 2 else 128])
                             for x in range(4)))
    return png(4, 4, 6, 8, rows)


def png_palette_trns_2x2():
    plte = bytes([255, 0, 0, 0, 255, 0, 0, 0, 255])
    trns = bytes([255, 0])
    return png(2, 2, 3, 8, [bytes([0, 1]), bytes([2, 1])], [(b"PLTE", plte), (b"tRNS", trns)])


def png_gray16_interlaced_3x3():
    rows = [b"".join(struct.pack(">H", (x + 3 * y) * 7000) for x in range(3)) for y in range(3)]
    # Adam7 needs the rows per pass; a 3x3 image has passes 1 (1 px), 4 (1 px: x=2,y=0),
    # 5 (2 px: y=2), 6 (x=1 of rows 0 and 2), 7 (row 1): written out explicitly.
    def px(x, y):
        return rows[y][2 * x:2 * x + 2]
    passes = [[[px(0, 0)]],                              # pass 1: (0,0)
              [], [],                                   # passes 2, 3: empty for 3x3
              [[px(2, 0)]],                              # pass 4: (2,0)... (x=2 step 4, y=0)
              [[px(0, 2), px(2, 2)]],                    # pass 5: y=2, x=0,2
              [[px(1, 0)], [px(1, 2)]],                  # pass 6: x=1, y=0,2
              [[px(0, 1), px(1, 1), px(2, 1)]]]          # pass 7: y=1
    raw = b"".join(b"\x00" + b"".join(r) for p in passes for r in p)
    ihdr = struct.pack(">IIBBBBB", 3, 3, 16, 0, 0, 0, 1)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    return (PNG_MAGIC + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) +
            chunk(b"IEND", b""))


def triangle_buffer():
    """Positions (36 bytes), normals (36), uvs (24), indices (6 + 2 padding): 104 bytes."""
    b = b""
    for v in (0, 0, 0, 1, 0, 0, 0, 1, 0):
        b += struct.pack("<f", v)
    for v in (0, 0, 1) * 3:
        b += struct.pack("<f", v)
    for v in (0, 0, 1, 0, 0.25, 0.2):
        b += struct.pack("<f", v)
    b += struct.pack("<HHH", 0, 1, 2) + b"\x00\x00"
    return b


def gltf_text(instanced=False, emissive=False):
    buf = triangle_buffer()
    tex_png = png_palette_trns_2x2()
    doc = {
        "asset": {"version": "2.0", "generator": "frameless fuzz seed"},
        "scene": 0,
        "scenes": [{"nodes": [0, 3]}],
        "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
        "nodes": [
            {"translation": [1, 2, 3], "children": [1, 2]},
            {"scale": [2, 2, 2], "rotation": [0, 0, 0.38268343, 0.92387953], "mesh": 0},
            {"translation": [0, 0, 5], "camera": 0},
            {"matrix": [1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 4, 0, 1],
             "extensions": {"KHR_lights_punctual": {"light": 0}},
             "children": [4]},
            {"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}},
        ],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.5}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "color": [1, 0.9, 0.8], "intensity": 3},
            {"type": "point", "intensity": 20, "range": 10}]}},
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0, "mode": 4}]}],
        "materials": [{"name": "red",
                       "pbrMetallicRoughness": {
                           "baseColorFactor": [1, 0.5, 0.25, 1], "metallicFactor": 0.2,
                           "roughnessFactor": 0.6,
                           "baseColorTexture": {"index": 0, "extensions": {
                               "KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2]}}}},
                       "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"wrapS": 33071, "wrapT": 10497}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(tex_png).decode()}],
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(buf).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 24},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    }
    if instanced:  # the mesh placed by two more nodes (one mirrored): a shared mesh, 3 instances
        doc["nodes"][0]["children"] = [1, 2, 5, 6]
        doc["nodes"] += [{"translation": [3, 0, 0], "scale": [-1, 1, 1], "mesh": 0},
                         {"rotation": [0, 0.70710678, 0, 0.70710678], "mesh": 0}]
    if emissive:  # emission: factor, strength extension and texture
        doc["materials"][0].update({"emissiveFactor": [1, 0.5, 0.2],
                                    "emissiveTexture": {"index": 0},
                                    "extensions": {"KHR_materials_emissive_strength":
                                                   {"emissiveStrength": 4}}})
    return json.dumps(doc, separators=(",", ":")).encode()


def glb():
    """A triangle strip of 4 vertices with float uvs, a metallic material whose base colour
    texture is a PNG stored in a bufferView, under a mirrored node; no lights, one camera."""
    b = b""
    for v in (0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0):
        b += struct.pack("<f", v)
    for v in (0, 0, 1, 0, 0, 1, 1, 1):
        b += struct.pack("<f", v)
    image_at = len(b)  # 80
    tex_png = png_rgba_4x4()
    b += tex_png
    while len(b) % 4:
        b += b"\x00"
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"scale": [-1, 1, 1], "children": [1]},
                  {"mesh": 0}, ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                    "mode": 5, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                "metallicFactor": 1, "roughnessFactor": 0.1}}],
        "textures": [{"source": 0}],
        "images": [{"bufferView": 2, "mimeType": "image/png"}],
        "buffers": [{"byteLength": len(b)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": image_at, "byteLength": len(tex_png)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}],
    }
    js = json.dumps(doc, separators=(",", ":")).encode()
    while len(js) % 4:
        js += b" "
    body = (struct.pack("<II", len(js), 0x4E4F534A) + js +
            struct.pack("<II", len(b), 0x004E4942) + b)
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


# Materials a, b, c, m: the names the fuzzer's fixed OBJ uses (scene_fuzzer.cpp), in the work
# folder that holds t.png (RGBA) and g.png (grey).
MTL_TEXT = b"""# frameless fuzz seed
newmtl a
Kd 0.8 0.2 0.1
Ks 0.5 0.5 0.5
Ns 64
illum 2
map_Kd -s 2 2 1 -o 0.5 0 0 -clamp on t.png
map_d -imfchan m t.png
newmtl b
Kd 0 0 0
Ks 0.9 0.9 0.9
illum 3
map_Ks -blendu off T.PNG
bump -bm 0.5 g.png
newmtl c
Kd xyz 0.5 0.5 0.5
Tr 0.25
illum 1
norm sub\\..\\g.png
newmtl m
Ni 1.5
Tf 0.9 0.8 0.7
d -halo 0.5
illum 7
"""


def scene_textures():
    doc = {
        "settings": {"width": 8, "height": 8, "seed": 1},
        "textures": {
            "img": {"type": "image", "file": "t.png", "wrap": "clamp", "srgb": True,
                    "uv_scale": [2, 2], "uv_offset": [0.5, 0]},
            "alpha": {"type": "image", "file": "t.png", "srgb": False},
            "bump": {"type": "image", "file": "g.png", "srgb": False},
            "stone": {"type": "marble", "color_a": [0.9, 0.9, 0.85], "color_b": [0.2, 0.2, 0.3],
                      "frequency": 2, "octaves": 4, "amplitude": 6,
                      "transform": {"scale": [1, 2, 1]}},
        },
        "materials": {
            "tex": {"class": "diffuse", "kd": [1, 1, 1], "kd_texture": "img",
                    "alpha_texture": "alpha", "alpha_channel": "alpha", "alpha_cutoff": 0.5,
                    "bump_texture": "bump", "bump_scale": 0.5},
            "rock": {"class": "polished", "kd": [0.5, 0.5, 0.5], "r0": 0.04,
                     "kd_texture": "stone"},
        },
        "objects": [
            {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 4,
             "material": "tex"},
            {"type": "sphere", "center": [0, 1, 0], "radius": 0.5, "material": "rock"},
        ],
    }
    return json.dumps(doc, separators=(",", ":")).encode()


def hdr_rle_8x2():
    """A bottom-up 8x2 Radiance HDR body (after the #?RADIANCE line) with new-style runs and literals."""
    body = b"FORMAT=32-bit_rle_rgbe\nEXPOSURE=2\n\n+Y 2 +X 8\n"
    for row in range(2):
        body += bytes([2, 2, 0, 8])
        for c in range(4):
            body += bytes([128 + 5, 100 + c + row]) + bytes([3, 7, 9, 11])  # a run of 5, 3 literals
    return body


def hdr_flat_repeats_2x3():
    """A 2x3 Radiance HDR body with flat pixels and an old-style repeat."""
    body = b"-Y 3 +X 2\n"
    body += bytes([64, 96, 128, 131, 1, 1, 1, 1])  # a pixel and one repeat
    body += bytes([0, 0, 0, 0, 10, 20, 30, 128]) + bytes([255, 0, 0, 140, 1, 1, 1, 1])
    return b"\n" + body


def main():
    seeds = {
        "gltf_triangle": bytes([GLTF]) + gltf_text(),
        "gltf_instanced": bytes([GLTF]) + gltf_text(instanced=True),
        "glb_strip_texture": bytes([GLB]) + glb(),
        "mtl_materials": bytes([MTL]) + MTL_TEXT,
        "mtl_emission": bytes([MTL]) + b"newmtl lamp\nKd 0 0 0\nKe 2 1.5 1\nmap_Ke t.png\n",
        "gltf_emission": bytes([GLTF]) + gltf_text(emissive=True),
        "scene_emission": bytes([SCENE]) + json.dumps({
            "ambient": {"type": "none"},
            "materials": {"lamp": {"class": "diffuse", "kd": 0, "emission": [4, 3, 2]},
                          "m": {"class": "polished", "kd": 0.5, "emission": 0.5}},
            "objects": [{"type": "plane", "point": [0, 2, 0], "normal": [0, -1, 0], "size": 1,
                         "material": "lamp"},
                        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]},
            separators=(",", ":")).encode(),
        "scene_path": bytes([SCENE]) + json.dumps({
            "settings": {"integrator": "igi", "background": [0.2, 0.3, 0.4], "max_depth": 8,
                         "igi": {"paths": 8, "interleave": 2, "clamp": 0.05},
                         "environment": {"file": "sky.exr", "rotate": 30, "scale": 2}},
            "ambient": {"type": "irradiance_volume", "resolution": 4, "samples": 16},
            "materials": {"lamp": {"class": "diffuse", "kd": 0.8, "emission": [4, 3, 2]}},
            "lights": [{"type": "spherical", "position": [0, 3, 0], "radius": 0.5}],
            "objects": [{"type": "plane", "point": [0, 2, 0], "normal": [0, -1, 0], "size": 1,
                         "material": "lamp"}]}, separators=(",", ":")).encode(),
        # Image seeds: the second byte picks the magic the fuzzer puts back (0: PNG).
        "image_png_rgba": bytes([IMAGE, 0]) + png_rgba_4x4()[len(PNG_MAGIC):],
        "image_png_palette": bytes([IMAGE, 0]) + png_palette_trns_2x2()[len(PNG_MAGIC):],
        "image_png_gray16_adam7": bytes([IMAGE, 0]) + png_gray16_interlaced_3x3()[len(PNG_MAGIC):],
        "image_hdr_rle": bytes([IMAGE, 4]) + hdr_rle_8x2(),
        "image_hdr_flat_repeats": bytes([IMAGE, 4]) + hdr_flat_repeats_2x3(),
        "scene_textures": bytes([SCENE_TEX]) + scene_textures(),
    }
    for name, data in seeds.items():
        assert len(data) < 8192, name
        with open(os.path.join(CORPUS, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
