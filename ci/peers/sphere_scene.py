#!/usr/bin/env python3
"""The peers' UV sphere, written for shadelab and for Mitsuba (standard library only).

    sphere_scene.py SEG OUTDIR

writes OUTDIR/sphere-SEG.glb and OUTDIR/sphere-SEG.toml (a shadelab scene) and
OUTDIR/sphere-SEG.ply (binary PLY, for mitsuba_peer.py). The sphere is the one
embree_caster.cpp and wgpu_raster_peer.py build in memory: a unit sphere with
rings = SEG, sectors = 2 SEG, so 4 SEG^2 triangles (SEG 100: 40,000; SEG 316:
399,424), zero-area pole triangles included (shadelab drops them on load).
Scene: eye (0, 0.5, 3) looking at the origin, fov_y 40, light (4, 6, 5) with
intensity 8, k = 1, ambient 0.2, material ka 0.3, kd 0.7, ks 0.4, p 40,
colour (0.9, 0.85, 0.8). Prints the triangle count on stderr.
"""
import json
import math
import os
import struct
import sys
from array import array


def uv_sphere(seg):
    """Vertices (flat xyz list, also the normals) and triangle indices, CCW seen from outside."""
    rings, sectors = seg, 2 * seg
    verts = array("f")
    for r in range(rings + 1):
        t = math.pi * r / rings
        st, ct = math.sin(t), math.cos(t)
        for s in range(sectors + 1):
            p = 2 * math.pi * s / sectors
            verts.extend((st * math.cos(p), ct, st * math.sin(p)))
    idx = array("I")
    for r in range(rings):
        for s in range(sectors):
            a = r * (sectors + 1) + s
            b = a + sectors + 1
            # Embree/wgpu order is (a, b, a+1); glTF wants counter-clockwise from outside.
            idx.extend((a, a + 1, b, a + 1, b + 1, b))
    return verts, idx


def le(arr):
    if sys.byteorder != "little":
        arr = array(arr.typecode, arr)
        arr.byteswap()
    return arr.tobytes()


def write_glb(path, verts, idx):
    pos = le(verts)
    ind = le(idx)
    blob = pos + pos + ind  # unit sphere: the normal is the position
    blob += b"\0" * (-len(blob) % 4)
    n = len(verts) // 3
    lo = [min(verts[i::3]) for i in range(3)]
    hi = [max(verts[i::3]) for i in range(3)]
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": 2 * len(pos), "byteLength": len(ind), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
    }
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    head = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(blob))
    with open(path, "wb") as f:
        f.write(head + struct.pack("<II", len(js), 0x4E4F534A) + js)
        f.write(struct.pack("<II", len(blob), 0x004E4942) + blob)


def write_ply(path, verts, idx):
    n, m = len(verts) // 3, len(idx) // 3
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {n}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        f"element face {m}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    vn = array("f")
    for i in range(n):
        xyz = verts[3 * i:3 * i + 3]
        vn.extend(xyz)
        vn.extend(xyz)
    face = struct.Struct("<B3i")
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(le(vn))
        f.write(b"".join(face.pack(3, idx[3 * k], idx[3 * k + 1], idx[3 * k + 2]) for k in range(m)))


SCENE = """# The peers' UV sphere (ci/peers/sphere_scene.py {seg}): {tris} triangles
[camera]
position = [0.0, 0.5, 3.0]
look_at  = [0.0, 0.0, 0.0]
fov_y    = 40.0

[image]
width = 1024
height = 1024
background = [0.0, 0.0, 0.0]

[lighting]
ambient = 0.2
k = 1.0

[[lights]]
position  = [4.0, 6.0, 5.0]
intensity = 8.0

[materials.m]
color = [0.9, 0.85, 0.8]
ka = 0.3
kd = 0.7
ks = 0.4
p  = 40

[[objects]]
shape    = "mesh"
file     = "sphere-{seg}.glb"
material = "m"
"""


def main():
    if len(sys.argv) != 3 or not sys.argv[1].isdigit() or int(sys.argv[1]) < 2:
        sys.exit("usage: sphere_scene.py SEG OUTDIR   (SEG >= 2)")
    seg, out = int(sys.argv[1]), sys.argv[2]
    os.makedirs(out, exist_ok=True)
    verts, idx = uv_sphere(seg)
    base = os.path.join(out, f"sphere-{seg}")
    write_glb(base + ".glb", verts, idx)
    write_ply(base + ".ply", verts, idx)
    with open(base + ".toml", "w") as f:
        f.write(SCENE.format(seg=seg, tris=len(idx) // 3))
    print(f"sphere-{seg}: {len(idx) // 3} triangles", file=sys.stderr)


if __name__ == "__main__":
    main()
