#!/usr/bin/env python3
"""Writes the small glTF test fixtures used by the scene loader's unit tests.

Standard library only. Run it from anywhere; it writes next to itself:

    python3 make_fixtures.py

Every file is tiny and hand-built so the tests can check exact numbers:

- tri_indexed.gltf      one indexed triangle with normals (embedded base64),
                        a material with `extras` overrides
- tri_unindexed.gltf    two triangles, no index accessor, no material
- hierarchy.gltf        parent (translation + scale) -> child (rotation)
- no_normals.gltf       an indexed tetrahedron without NORMAL
- degenerate.gltf       a quad plus a repeated-index and a collinear triangle
- cube.glb              binary glTF: unit cube centred on the origin, normals
- nan_position.gltf     a NaN in POSITION
- corrupt.glb           truncated garbage with a glb magic
- scene_with_camera_light.gltf
                        a quad, a perspective camera, a point light and a spot
                        light (KHR_lights_punctual), a BLEND material with
                        KHR_materials_ior
- mirrored.gltf         a triangle under a node with scale [-1, 1, 1]
- skewed.gltf           four triangles with normals tilted out of their
                        faces' planes, under a node that scales
                        non-uniformly, rotates and moves, whose children
                        rotate and mirror (scale [1, -1, 1]), one by TRS and
                        one by a matrix: where the normal matrix (inverse
                        transpose) and the model matrix disagree

and, for the hard-case suite, into ../../assets/hard/models/:

- slivers.gltf          a square in y = 0 tiled by six triangles, two of them
                        slivers (aspect ratio 1e6 and 2e6), plus three
                        zero-area ones (a repeated index, three collinear
                        vertices, three distinct vertices at one point); no
                        NORMAL, so normals are computed from faces
- bad-normals.gltf      three squares in y = 0: zero-length normals,
                        non-unit normals (lengths 1e-3 to 100), and normals
                        +Y on one side and -Y on the other, so that the
                        interpolated normal passes through zero mid-square

and, for assets/vertex-colors.toml, into ../../assets/models/:

- vertex-colors.gltf    COLOR_0 in the three encodings glTF allows: a cube
                        whose corners are coloured by position (normalised
                        unsigned bytes, RGBA, alpha 255), a floor square
                        (normalised unsigned shorts, RGB) and an upright
                        triangle (floats, RGB); TEXCOORD_0 likewise after
                        them (floats for the cube, 0 to 1 across each face;
                        shorts for the floor; bytes for the triangle)

and, for the image textures (tests/cpu/texture_import.rs), here:

- checker-2x2.png       a 2x2 RGBA PNG: red, green (top row), blue, sRGB
                        grey 128 (bottom row), all opaque
- textured_file.gltf    a unit quad with TEXCOORD_0 (v down the image: 0 at
                        the quad's top) under a material whose base colour
                        texture is checker-2x2.png beside it, its URI
                        percent-encoded (checker%2D2x2.png), no sampler,
                        baseColorFactor (0.5, 1, 1)
- textured_datauri.gltf the same with the PNG as a base64 data URI, a
                        sampler (NEAREST, NEAREST_MIPMAP_LINEAR,
                        CLAMP_TO_EDGE, MIRRORED_REPEAT) and
                        KHR_texture_transform (offset (0.5, -0.25),
                        rotation 0.5, scale (2, 3); extensionsRequired)
- textured.glb          the same quad as binary glTF, the PNG in a buffer
                        view (image/png), a sampler (LINEAR,
                        NEAREST_MIPMAP_NEAREST, REPEAT, CLAMP_TO_EDGE)
- textured_texcoord1.gltf
                        three quads side by side with TEXCOORD_0 (floats)
                        and TEXCOORD_1 (normalised unsigned bytes, another
                        mapping): material `set1` reads texCoord 1,
                        `transformed` texCoord 0 overridden to 1 by
                        KHR_texture_transform, `set0` texCoord 0
- box-textured.gltf     a unit cube, four corners per face with 0..1
                        coordinates across each face, its base colour an
                        8x8 PNG of two colours (a checkerboard of 2x2-texel
                        cells, orange and cream) as a data URI, like the
                        Khronos BoxTextured sample
"""

import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

FLOAT = 5126
USHORT = 5123
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963


class Builder:
    """Accumulates one binary buffer plus the views and accessors into it."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def _align(self):
        while len(self.data) % 4:
            self.data.append(0)

    def vec3(self, values, with_bounds=True):
        """Adds a VEC3 float accessor; returns its index."""
        self._align()
        offset = len(self.data)
        for v in values:
            self.data += struct.pack("<3f", *v)
        self.views.append({"buffer": 0, "byteOffset": offset,
                           "byteLength": len(values) * 12,
                           "target": ARRAY_BUFFER})
        acc = {"bufferView": len(self.views) - 1, "componentType": FLOAT,
               "count": len(values), "type": "VEC3"}
        if with_bounds:
            finite = [v for v in values if all(c == c for c in v)]
            acc["min"] = [min(v[i] for v in finite) for i in range(3)]
            acc["max"] = [max(v[i] for v in finite) for i in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def colors(self, values, component_type, kind):
        """Adds a normalised integer accessor (UNSIGNED_BYTE 5121 or
        UNSIGNED_SHORT 5123; VEC2, VEC3 or VEC4): colours, or texture
        coordinates; returns its index."""
        self._align()
        offset = len(self.data)
        code = {5121: "B", 5123: "H"}[component_type]
        width = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        for v in values:
            self.data += struct.pack("<%d%s" % (width, code), *v)
            self._align()
        stride = len(self.data) - offset
        stride //= max(1, len(values))
        self.views.append({"buffer": 0, "byteOffset": offset,
                           "byteLength": len(self.data) - offset,
                           "byteStride": stride,
                           "target": ARRAY_BUFFER})
        self.accessors.append({"bufferView": len(self.views) - 1,
                               "componentType": component_type,
                               "normalized": True,
                               "count": len(values), "type": kind})
        return len(self.accessors) - 1

    def vec2(self, values):
        """Adds a VEC2 float accessor; returns its index."""
        self._align()
        offset = len(self.data)
        for v in values:
            self.data += struct.pack("<2f", *v)
        self.views.append({"buffer": 0, "byteOffset": offset,
                           "byteLength": len(values) * 8,
                           "target": ARRAY_BUFFER})
        self.accessors.append({"bufferView": len(self.views) - 1,
                               "componentType": FLOAT,
                               "count": len(values), "type": "VEC2"})
        return len(self.accessors) - 1

    def indices(self, idx):
        """Adds an unsigned-short SCALAR index accessor; returns its index."""
        self._align()
        offset = len(self.data)
        for i in idx:
            self.data += struct.pack("<H", i)
        self.views.append({"buffer": 0, "byteOffset": offset,
                           "byteLength": len(idx) * 2,
                           "target": ELEMENT_ARRAY_BUFFER})
        self.accessors.append({"bufferView": len(self.views) - 1,
                               "componentType": USHORT, "count": len(idx),
                               "type": "SCALAR"})
        return len(self.accessors) - 1

    def blob(self, data):
        """Adds raw bytes (an image) in a buffer view of their own; returns
        the view's index."""
        self._align()
        offset = len(self.data)
        self.data += data
        self.views.append({"buffer": 0, "byteOffset": offset,
                           "byteLength": len(data)})
        return len(self.views) - 1

    def finish(self, doc, embed=True):
        """Completes `doc` with buffers/views/accessors."""
        self._align()
        buf = {"byteLength": len(self.data)}
        if embed:
            buf["uri"] = ("data:application/octet-stream;base64,"
                          + base64.b64encode(bytes(self.data)).decode("ascii"))
        doc["asset"] = {"version": "2.0", "generator": "make_fixtures.py"}
        doc["buffers"] = [buf]
        doc["bufferViews"] = self.views
        doc["accessors"] = self.accessors
        return doc


def write_gltf(name, doc):
    with open(os.path.join(HERE, name), "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def write_glb(name, doc, binary):
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    while len(js) % 4:
        js += b" "
    binary = bytes(binary)
    while len(binary) % 4:
        binary += b"\0"
    total = 12 + 8 + len(js) + 8 + len(binary)
    out = struct.pack("<4sII", b"glTF", 2, total)
    out += struct.pack("<I4s", len(js), b"JSON") + js
    out += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(out)


def tri_indexed():
    b = Builder()
    pos = b.vec3([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    nrm = b.vec3([(0, 0, 1)] * 3)
    idx = b.indices([0, 1, 2])
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "tri", "mesh": 0}],
        "meshes": [{"name": "tri", "primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm},
            "indices": idx, "material": 0}]}],
        "materials": [{
            "name": "red",
            "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 0.5},
            "extras": {"p": 64, "ka": 0.1, "note": "not a material key"}}],
    }
    write_gltf("tri_indexed.gltf", b.finish(doc))


def tri_unindexed():
    b = Builder()
    pos = b.vec3([(0, 0, 0), (1, 0, 0), (0, 1, 0),
                  (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    nrm = b.vec3([(0, 0, 1)] * 6)
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm}}]}],
    }
    write_gltf("tri_unindexed.gltf", b.finish(doc))


def hierarchy():
    # parent: T = (1, 2, 3), S = 2; child: 90 degrees about +Z.
    # (1,0,0) -> (1,4,3); (0,1,0) -> (-1,2,3); (0,0,1) -> (1,2,5)
    b = Builder()
    pos = b.vec3([(1, 0, 0), (0, 1, 0), (0, 0, 1)])
    idx = b.indices([0, 1, 2])
    h = 0.7071067811865476
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "parent", "translation": [1, 2, 3], "scale": [2, 2, 2],
             "children": [1]},
            {"name": "child", "rotation": [0, 0, h, h], "mesh": 0},
        ],
        "meshes": [{"name": "tri", "primitives": [{
            "attributes": {"POSITION": pos}, "indices": idx}]}],
    }
    write_gltf("hierarchy.gltf", b.finish(doc))


def no_normals():
    b = Builder()
    pos = b.vec3([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)])
    idx = b.indices([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3])
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "tetra", "primitives": [{
            "attributes": {"POSITION": pos}, "indices": idx}]}],
    }
    write_gltf("no_normals.gltf", b.finish(doc))


def degenerate():
    b = Builder()
    # 0..3: unit quad in z = 0; 4: midpoint of edge 0-1 (collinear with 0, 1)
    pos = b.vec3([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0, 0)])
    idx = b.indices([0, 1, 2, 0, 2, 3,   # the quad
                     0, 0, 1,            # repeated index
                     0, 4, 1])           # collinear
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": pos}, "indices": idx}]}],
    }
    write_gltf("degenerate.gltf", b.finish(doc))


def unit_cube():
    """The unit cube centred on the origin, four corners per face with the
    face's normal: (positions, normals, indices)."""
    positions, normals, idx = [], [], []
    # (normal, u, v) with u x v = normal, so (-,-),(+,-),(+,+),(-,+) is CCW
    faces = [((1, 0, 0), (0, 1, 0), (0, 0, 1)),
             ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, 1, 0), (0, 0, 1), (1, 0, 0)),
             ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
             ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
             ((0, 0, -1), (0, 1, 0), (1, 0, 0))]
    for n, u, v in faces:
        base = len(positions)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            positions.append(tuple(0.5 * n[i] + 0.5 * su * u[i] + 0.5 * sv * v[i]
                                   for i in range(3)))
            normals.append(n)
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, idx


def cube():
    b = Builder()
    positions, normals, idx = unit_cube()
    pos = b.vec3(positions)
    nrm = b.vec3(normals)
    ind = b.indices(idx)
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "cube", "mesh": 0}],
        "meshes": [{"name": "cube", "primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm},
            "indices": ind, "material": 0}]}],
        "materials": [{
            "name": "ochre",
            "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.2, 1],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 0.5}}],
    }
    b.finish(doc, embed=False)
    write_glb("cube.glb", doc, b.data)


def nan_position():
    b = Builder()
    pos = b.vec3([(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0)])
    idx = b.indices([0, 1, 2])
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "broken", "primitives": [{
            "attributes": {"POSITION": pos}, "indices": idx}]}],
    }
    write_gltf("nan_position.gltf", b.finish(doc))


def corrupt():
    data = struct.pack("<4sII", b"glTF", 2, 4096) + b"\x13\x37garbage" * 5
    with open(os.path.join(HERE, "corrupt.glb"), "wb") as f:
        f.write(data)


def scene_with_camera_light():
    b = Builder()
    pos = b.vec3([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)])
    nrm = b.vec3([(0, 0, 1)] * 4)
    idx = b.indices([0, 1, 2, 0, 2, 3])
    doc = {
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_ior"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 4.0,
             "range": 10.0},
            {"type": "spot", "intensity": 10.0,
             "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.5}},
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "quad", "mesh": 0},
            {"name": "cam", "camera": 0, "translation": [0, 0, 5]},
            {"name": "lamp", "translation": [2, 3, 4],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "spot", "translation": [0, 5, 0],
             "extensions": {"KHR_lights_punctual": {"light": 1}}},
        ],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.5, "znear": 0.1,
                                     "zfar": 100.0, "aspectRatio": 1.5}}],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm},
            "indices": idx, "material": 0}]}],
        "materials": [{
            "name": "window",
            "alphaMode": "BLEND",
            "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 1.0, 0.25],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 0.0},
            "extensions": {"KHR_materials_ior": {"ior": 1.25}}}],
    }
    write_gltf("scene_with_camera_light.gltf", b.finish(doc))


def mirrored():
    b = Builder()
    pos = b.vec3([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    nrm = b.vec3([(0, 0, 1)] * 3)
    idx = b.indices([0, 1, 2])
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "mirror", "scale": [-1, 1, 1], "mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm},
            "indices": idx}]}],
    }
    write_gltf("mirrored.gltf", b.finish(doc))


def quat(axis, degrees):
    import math
    n = math.sqrt(sum(c * c for c in axis))
    h = math.radians(degrees) / 2
    return [c / n * math.sin(h) for c in axis] + [math.cos(h)]


def skewed():
    b = Builder()
    pos = b.vec3([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0.2, 0.3, 1), (1, 1, 0.5)])
    # Unit normals deliberately not perpendicular to any face.
    raw = [(0.3, 0.4, 0.866), (-0.5, 0.1, 0.86), (0.2, -0.6, 0.77),
           (0.7, 0.7, 0.14), (0.0, 0.6, 0.8)]
    import math
    nrm = b.vec3([tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in raw])
    idx = b.indices([0, 1, 2, 0, 1, 3, 1, 4, 2, 2, 4, 3])
    prim = {"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx}
    # The child by matrix: rotation 70 degrees about z, then scale
    # (0.5, 2, 1), then a move; column-major as glTF stores it.
    c, s_ = math.cos(math.radians(70)), math.sin(math.radians(70))
    sx, sy, sz = 0.5, 2.0, 1.0
    matrix = [c * sx, s_ * sx, 0, 0,
              -s_ * sy, c * sy, 0, 0,
              0, 0, sz, 0,
              0.25, -0.5, 0.75, 1]
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "skew", "translation": [0.5, -1, 2],
             "rotation": quat((1, 2, 3), 40), "scale": [3, 0.5, 1.5],
             "children": [1, 2]},
            {"name": "turn-and-mirror", "rotation": quat((0, 1, 1), 25),
             "scale": [1, -1, 1], "mesh": 0},
            {"name": "by-matrix", "matrix": matrix, "mesh": 0},
        ],
        "meshes": [{"primitives": [prim]}],
    }
    write_gltf("skewed.gltf", b.finish(doc))


HARD = os.path.join(HERE, "..", "..", "assets", "hard", "models")


def write_hard(name, doc):
    with open(os.path.join(HARD, name), "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def up_facing(pos, tri):
    """Orders a triangle of points in y = 0 counter-clockwise seen from +Y."""
    a, b, c = (pos[i] for i in tri)
    # y component of (b - a) x (c - a)
    cross_y = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2])
    return list(tri) if cross_y > 0 else [tri[0], tri[2], tri[1]]


def slivers():
    b = Builder()
    ez = 1.0 - 2e-6
    # M: the midpoint of E-C moved 1e-6 toward D, across the line E-C.
    mx, mz = 0.5, (-ez + 1.0) / 2
    nx, nz = -2 / 5 ** 0.5, 1 / 5 ** 0.5
    pos = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1),   # A B C D
           (0, 0, -ez),                                      # E, 2e-6 off A-B
           (mx + 1e-6 * nx, 0, mz + 1e-6 * nz),              # M
           (0, 0, -1),                                       # on A-B
           (0.3, 0, 0.3), (0.3, 0, 0.3), (0.3, 0, 0.3)]      # one point, thrice
    A, B, C, D, E, M, N, P, Q, R = range(10)
    kept = [(A, E, B), (A, D, E), (E, D, M), (M, D, C), (E, M, C), (E, C, B)]
    idx = []
    for t in kept:
        idx += up_facing(pos, t)
    idx += [A, A, B,      # a repeated index
            A, N, B,      # collinear
            P, Q, R]      # three vertices at one point
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "slivers", "primitives": [{
            "attributes": {"POSITION": b.vec3(pos)},
            "indices": b.indices(idx)}]}],
    }
    write_hard("slivers.gltf", b.finish(doc))


def bad_normals():
    b = Builder()
    meshes, nodes = [], []
    cases = [
        ("zero-length", [(0, 0, 0)] * 4),
        ("non-unit", [(0, 1e-3, 0), (0, 100, 0), (0, 0.5, 0), (0, 3, 0)]),
        ("opposite", [(0, 1, 0), (0, 1, 0), (0, -1, 0), (0, -1, 0)]),
    ]
    for k, (name, normals) in enumerate(cases):
        x0 = -3.3 + 2.2 * k
        # Corners in the order near-left, near-right, far-right, far-left:
        # the +Y normals of "opposite" are on the near edge (z = 1).
        pos = [(x0, 0, 1), (x0 + 2, 0, 1), (x0 + 2, 0, -1), (x0, 0, -1)]
        idx = up_facing(pos, (0, 1, 2)) + up_facing(pos, (0, 2, 3))
        meshes.append({"name": name, "primitives": [{
            "attributes": {"POSITION": b.vec3(pos), "NORMAL": b.vec3(normals)},
            "indices": b.indices(idx)}]})
        nodes.append({"name": name, "mesh": k})
    doc = {
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
    }
    write_hard("bad-normals.gltf", b.finish(doc))


MODELS = os.path.join(HERE, "..", "..", "assets", "models")


def vertex_colors():
    b = Builder()
    positions, normals, idx = unit_cube()
    # The corner (x, y, z) in [-0.5, 0.5]^3 has colour (x, y, z) + 0.5, each
    # 0 or 255.
    colors = [tuple(round(255 * (c + 0.5)) for c in p) + (255,) for p in positions]
    cube = {"name": "rgb-cube", "primitives": [{
        "attributes": {"POSITION": b.vec3(positions),
                       "NORMAL": b.vec3(normals),
                       "COLOR_0": b.colors(colors, 5121, "VEC4")},
        "indices": b.indices(idx), "material": 0}]}
    floor_pos = [(-3, 0, 3), (3, 0, 3), (3, 0, -3), (-3, 0, -3)]
    floor = {"name": "floor", "primitives": [{
        "attributes": {
            "POSITION": b.vec3(floor_pos),
            "NORMAL": b.vec3([(0, 1, 0)] * 4),
            "COLOR_0": b.colors([(65535, 52428, 39321), (13107, 26214, 65535),
                                 (65535, 65535, 65535), (32768, 65535, 13107)],
                                5123, "VEC3")},
        "indices": b.indices(up_facing(floor_pos, (0, 1, 2))
                             + up_facing(floor_pos, (0, 2, 3))),
        "material": 0}]}
    sail = {"name": "sail", "primitives": [{
        "attributes": {
            "POSITION": b.vec3([(-2.5, 0, -1), (-1, 0, -1.5), (-1.8, 2, -1.2)]),
            "COLOR_0": b.vec3([(1.0, 0.2, 0.2), (0.2, 1.0, 0.2),
                               (0.2, 0.2, 1.0)], with_bounds=False)},
        "indices": b.indices([0, 1, 2]), "material": 0}]}
    # Texture coordinates, added after everything above so that the
    # accessors' numbers the loader's tests use stay as they are.
    corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    cube["primitives"][0]["attributes"]["TEXCOORD_0"] = b.vec2(corners * 6)
    floor["primitives"][0]["attributes"]["TEXCOORD_0"] = b.colors(
        [(0, 65535), (65535, 65535), (65535, 0), (0, 0)], 5123, "VEC2")
    sail["primitives"][0]["attributes"]["TEXCOORD_0"] = b.colors(
        [(0, 0), (255, 0), (128, 255)], 5121, "VEC2")
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"name": "rgb-cube", "mesh": 0, "translation": [0, 0.5, 0],
                   "rotation": quat((0, 1, 0), 30)},
                  {"name": "floor", "mesh": 1},
                  {"name": "sail", "mesh": 2}],
        "meshes": [cube, floor, sail],
        "materials": [{
            "name": "white",
            "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 0.6}}],
    }
    with open(os.path.join(MODELS, "vertex-colors.gltf"), "w",
              encoding="utf-8") as f:
        json.dump(b.finish(doc), f, indent=1)
        f.write("\n")


def png_bytes(rows):
    """An 8-bit RGBA PNG of `rows` (lists of (r, g, b, a)), standard
    library only."""
    height, width = len(rows), len(rows[0])
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rows)

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


CHECKER_2X2 = [[(255, 0, 0, 255), (0, 255, 0, 255)],
               [(0, 0, 255, 255), (128, 128, 128, 255)]]


def data_uri(png):
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def textured_quad(b, offset=0.0):
    """A unit quad in z = 0 at x = offset, facing +Z, with TEXCOORD_0 (the
    image's top at the quad's top); returns the primitive (no material)."""
    pos = [(offset, 0, 0), (offset + 1, 0, 0), (offset + 1, 1, 0), (offset, 1, 0)]
    return {"attributes": {"POSITION": b.vec3(pos),
                           "NORMAL": b.vec3([(0, 0, 1)] * 4),
                           "TEXCOORD_0": b.vec2([(0, 1), (1, 1), (1, 0), (0, 0)])},
            "indices": b.indices([0, 1, 2, 0, 2, 3])}


def textured_doc(prims, materials, textures, images, samplers=None):
    doc = {
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "quad", "mesh": 0}],
        "meshes": [{"name": "quad", "primitives": prims}],
        "materials": materials,
        "textures": textures,
        "images": images,
    }
    if samplers is not None:
        doc["samplers"] = samplers
    return doc


def painted(name, texture_info, factor=(0.5, 1, 1, 1)):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": list(factor),
                                     "baseColorTexture": texture_info,
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0}}


def textures():
    png = png_bytes(CHECKER_2X2)
    with open(os.path.join(HERE, "checker-2x2.png"), "wb") as f:
        f.write(png)

    b = Builder()
    prim = dict(textured_quad(b), material=0)
    doc = textured_doc([prim], [painted("painted", {"index": 0})],
                       [{"source": 0}], [{"uri": "checker%2D2x2.png"}])
    write_gltf("textured_file.gltf", b.finish(doc))

    b = Builder()
    prim = dict(textured_quad(b), material=0)
    transform = {"offset": [0.5, -0.25], "rotation": 0.5, "scale": [2, 3]}
    doc = textured_doc(
        [prim],
        [painted("painted", {"index": 0, "extensions": {
            "KHR_texture_transform": transform}})],
        [{"source": 0, "sampler": 0}],
        [{"name": "checker", "uri": data_uri(png)}],
        [{"magFilter": 9728, "minFilter": 9986, "wrapS": 33071,
          "wrapT": 33648}])
    doc["extensionsUsed"] = ["KHR_texture_transform"]
    doc["extensionsRequired"] = ["KHR_texture_transform"]
    write_gltf("textured_datauri.gltf", b.finish(doc))

    b = Builder()
    prim = dict(textured_quad(b), material=0)
    view = b.blob(png)
    doc = textured_doc([prim], [painted("painted", {"index": 0})],
                       [{"source": 0, "sampler": 0}],
                       [{"bufferView": view, "mimeType": "image/png"}],
                       [{"magFilter": 9729, "minFilter": 9984, "wrapS": 10497,
                         "wrapT": 33071}])
    b.finish(doc, embed=False)
    write_glb("textured.glb", doc, b.data)

    b = Builder()
    prims = []
    for i in range(3):
        prim = textured_quad(b, offset=1.5 * i)
        # TEXCOORD_1: the quad's corners mirrored left to right, as bytes.
        prim["attributes"]["TEXCOORD_1"] = b.colors(
            [(255, 255), (0, 255), (0, 0), (255, 0)], 5121, "VEC2")
        prim["material"] = i
        prims.append(prim)
    materials = [
        painted("set1", {"index": 0, "texCoord": 1}),
        painted("transformed", {"index": 0, "extensions": {
            "KHR_texture_transform": {"texCoord": 1}}}),
        painted("set0", {"index": 0}),
    ]
    doc = textured_doc(prims, materials, [{"source": 0}],
                       [{"uri": data_uri(png)}])
    doc["extensionsUsed"] = ["KHR_texture_transform"]
    write_gltf("textured_texcoord1.gltf", b.finish(doc))

    orange, cream = (230, 120, 30, 255), (250, 240, 210, 255)
    rows = [[orange if (i // 2 + j // 2) % 2 == 0 else cream for i in range(8)]
            for j in range(8)]
    b = Builder()
    positions, normals, idx = unit_cube()
    corners = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
    prim = {"attributes": {"POSITION": b.vec3(positions),
                           "NORMAL": b.vec3(normals),
                           "TEXCOORD_0": b.vec2(corners * 6)},
            "indices": b.indices(idx), "material": 0}
    doc = textured_doc([prim],
                       [painted("box", {"index": 0}, factor=(1, 1, 1, 1))],
                       [{"source": 0, "sampler": 0}],
                       [{"name": "checker-8x8", "uri": data_uri(png_bytes(rows))}],
                       [{"magFilter": 9729, "minFilter": 9987}])
    doc["nodes"][0]["name"] = "box"
    doc["meshes"][0]["name"] = "box"
    write_gltf("box-textured.gltf", b.finish(doc))


def main():
    tri_indexed()
    tri_unindexed()
    hierarchy()
    no_normals()
    degenerate()
    cube()
    nan_position()
    corrupt()
    scene_with_camera_light()
    mirrored()
    skewed()
    slivers()
    bad_normals()
    vertex_colors()
    textures()


if __name__ == "__main__":
    main()
