#!/usr/bin/env python3
"""Writes the images of assets/textured.toml and its crate model, with the
standard library alone, so that they can be made again and checked:

- stone.png (128 x 128): stone tiles, grey with a light mortar grid and
  per-tile shading, noise inside each tile (the floor, minified toward
  the horizon);
- planet.png (256 x 128): an equirectangular map (longitude across,
  colatitude down, as shadelab's sphere coordinates): ocean, continents
  from a sum of sines, ice caps;
- crate.png (64 x 64): wooden planks with a frame, the texture of
  ../models/crate.gltf, a cube whose six faces each show it once;
- orientation.png (32 x 32): a red F on a checked ground with a blue
  top-left corner, which reads wrong when mirrored or turned
  (../texture-orientation.toml shows which way it reads on each shape).
"""
import base64
import json
import math
import os
import random
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(path, width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b) in 0..255."""
    rows = b"".join(
        b"\x00" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height)
    )

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xFFFFFFFF
        )

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(data)
    return data


def clamp(v):
    return max(0, min(255, int(round(v))))


def stone():
    rng = random.Random(7)
    tile_shade = [[0.75 + 0.25 * rng.random() for _ in range(4)] for _ in range(4)]
    noise = [[rng.random() for _ in range(128)] for _ in range(128)]

    def pixel(x, y):
        if x % 32 < 2 or y % 32 < 2:
            return (205, 200, 190)
        s = tile_shade[y // 32][x // 32] * (0.85 + 0.15 * noise[y][x])
        return (clamp(120 * s), clamp(118 * s), clamp(112 * s))

    png(os.path.join(HERE, "stone.png"), 128, 128, pixel)


def planet():
    def pixel(x, y):
        lon = 2 * math.pi * (x + 0.5) / 256
        colat = math.pi * (y + 0.5) / 128
        lat = math.pi / 2 - colat
        if abs(lat) > 1.25:
            return (235, 240, 245)
        land = math.sin(3 * lon) * math.cos(2 * lat) + 0.6 * math.sin(5 * lon + 1.3) * math.sin(3 * lat + 0.4)
        if land > 0.35:
            green = 0.5 + 0.5 * math.cos(lat)
            return (clamp(70 + 90 * (1 - green)), clamp(110 + 60 * green), 50)
        return (20, clamp(60 + 40 * math.cos(lat)), clamp(140 + 50 * math.cos(lat)))

    png(os.path.join(HERE, "planet.png"), 256, 128, pixel)


def crate():
    def pixel(x, y):
        if x < 6 or y < 6 or x >= 58 or y >= 58 or abs(x - y) < 4:
            return (110, 70, 35)
        plank = (y // 13) % 2
        grain = 10 * math.sin(x * 0.9 + y * 0.1 + 3 * plank)
        return (clamp(185 + grain - 20 * plank), clamp(135 + grain - 15 * plank), clamp(75 + grain / 2))

    data = png(os.path.join(HERE, "crate.png"), 64, 64, pixel)
    return data


def crate_model():
    """A unit cube, 24 vertices (a face's own normals and uv 0..1), its
    base colour texture the file crate.png beside the textures folder."""
    faces = [
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
    ]
    positions, normals, uvs, indices = [], [], [], []
    for n, u, v in faces:
        base = len(positions)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            positions.append([0.5 * (n[i] + su * u[i] + sv * v[i]) for i in range(3)])
            normals.append(list(n))
            uvs.append([(su + 1) / 2, (1 - sv) / 2])
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    blob = b"".join(struct.pack("<3f", *p) for p in positions)
    blob += b"".join(struct.pack("<3f", *n) for n in normals)
    blob += b"".join(struct.pack("<2f", *t) for t in uvs)
    blob += b"".join(struct.pack("<H", i) for i in indices)
    doc = {
        "asset": {"version": "2.0", "generator": "assets/textures/make_textures.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "crate", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "materials": [{"name": "crate", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.8}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}],
        "images": [{"uri": "../textures/crate.png"}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 288},
            {"buffer": 0, "byteOffset": 288, "byteLength": 288},
            {"buffer": 0, "byteOffset": 576, "byteLength": 192},
            {"buffer": 0, "byteOffset": 768, "byteLength": 72},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 24, "type": "VEC3", "min": [-0.5] * 3, "max": [0.5] * 3},
            {"bufferView": 1, "componentType": 5126, "count": 24, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 24, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 36, "type": "SCALAR"},
        ],
    }
    with open(os.path.join(HERE, "..", "models", "crate.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def orientation():
    # An F in a 32 x 32 grid: its stem at columns 9-13, rows 5-26; its top
    # bar to column 24, its middle bar to column 20.
    def pixel(x, y):
        stem = 9 <= x <= 13 and 5 <= y <= 26
        top = 9 <= x <= 24 and 5 <= y <= 9
        middle = 9 <= x <= 20 and 14 <= y <= 17
        if stem or top or middle:
            return (200, 30, 30)
        if x < 6 and y < 6:
            return (40, 60, 200)
        return (235, 235, 225) if (x // 4 + y // 4) % 2 == 0 else (190, 190, 180)

    png(os.path.join(HERE, "orientation.png"), 32, 32, pixel)


if __name__ == "__main__":
    orientation()
    stone()
    planet()
    crate()
    crate_model()
