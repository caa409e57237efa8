//! An oracle for the glTF importer that shares no code with it: a reader
//! written here from the glTF 2.0 specification (JSON and GLB, data-URI and
//! file buffers, TRS and matrix nodes, the normal matrix as the inverse
//! transpose, winding reversed under a mirroring transform), with its own
//! matrix code on plain arrays. Every fixture and asset glTF is read both
//! ways and every triangle compared: world positions, normals, winding.
//! The GPU and the CPU reference share the importer, so `check` cannot see
//! its errors; this can.

use std::path::{Path, PathBuf};

use base64::Engine as _;
use serde_json::Value;
use shadelab::scene::Shape;

type V3 = [f64; 3];
/// Column-major, as glTF stores it: m[col][row].
type M4 = [[f64; 4]; 4];

const IDENTITY: M4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

fn mul(a: &M4, b: &M4) -> M4 {
    let mut out = [[0.0; 4]; 4];
    for (col, out_col) in out.iter_mut().enumerate() {
        for (row, cell) in out_col.iter_mut().enumerate() {
            *cell = (0..4).map(|k| a[k][row] * b[col][k]).sum();
        }
    }
    out
}

/// translation * rotation * scale, from the spec's TRS properties.
fn trs(node: &Value) -> M4 {
    let get = |key: &str, default: &[f64]| -> Vec<f64> {
        node.get(key)
            .and_then(Value::as_array)
            .map(|a| a.iter().map(|v| v.as_f64().unwrap()).collect())
            .unwrap_or_else(|| default.to_vec())
    };
    let t = get("translation", &[0.0, 0.0, 0.0]);
    let q = get("rotation", &[0.0, 0.0, 0.0, 1.0]);
    let s = get("scale", &[1.0, 1.0, 1.0]);
    let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
    // The rotation matrix of a unit quaternion, by columns.
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y + z * w),
            2.0 * (x * z - y * w),
        ],
        [
            2.0 * (x * y - z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z + x * w),
        ],
        [
            2.0 * (x * z + y * w),
            2.0 * (y * z - x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let mut m = IDENTITY;
    for ((m_col, r_col), scale) in m.iter_mut().zip(r).zip(&s) {
        for (cell, value) in m_col.iter_mut().zip(r_col) {
            *cell = value * scale;
        }
    }
    m[3] = [t[0], t[1], t[2], 1.0];
    m
}

fn local_matrix(node: &Value) -> M4 {
    match node.get("matrix").and_then(Value::as_array) {
        Some(a) => {
            let v: Vec<f64> = a.iter().map(|x| x.as_f64().unwrap()).collect();
            let mut m = [[0.0; 4]; 4];
            for (col, values) in m.iter_mut().zip(v.chunks_exact(4)) {
                col.copy_from_slice(values);
            }
            m
        }
        None => trs(node),
    }
}

fn upper3(m: &M4) -> [[f64; 3]; 3] {
    [
        [m[0][0], m[0][1], m[0][2]],
        [m[1][0], m[1][1], m[1][2]],
        [m[2][0], m[2][1], m[2][2]],
    ]
}

fn det3(a: &[[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[2][1] * a[1][2])
        - a[1][0] * (a[0][1] * a[2][2] - a[2][1] * a[0][2])
        + a[2][0] * (a[0][1] * a[1][2] - a[1][1] * a[0][2])
}

/// The inverse transpose of a 3x3 (columns), by cofactors: the cofactor
/// matrix over the determinant is exactly the inverse transposed.
fn inverse_transpose(a: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let d = det3(a);
    let e = |c: usize, r: usize| a[c][r];
    [0, 1, 2].map(|c| {
        [0, 1, 2].map(|r| {
            let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
            let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
            (e(c1, r1) * e(c2, r2) - e(c2, r1) * e(c1, r2)) / d
        })
    })
}

fn apply3(a: &[[f64; 3]; 3], v: V3) -> V3 {
    [0, 1, 2].map(|r| a[0][r] * v[0] + a[1][r] * v[1] + a[2][r] * v[2])
}

fn point(m: &M4, p: V3) -> V3 {
    [0, 1, 2].map(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(v: V3) -> V3 {
    let l = dot(v, v).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

struct Document {
    json: Value,
    buffers: Vec<Vec<u8>>,
}

fn read_document(path: &Path) -> Document {
    let bytes = std::fs::read(path).unwrap();
    let (json, glb_bin) = if bytes.starts_with(b"glTF") {
        // Header (12 bytes), then chunks: length, type, data.
        let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let json_len = u32_at(12);
        let json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let bin_at = 20 + json_len;
        let bin = (bin_at + 8 <= bytes.len()).then(|| {
            let len = u32_at(bin_at);
            bytes[bin_at + 8..bin_at + 8 + len].to_vec()
        });
        (json, bin)
    } else {
        (serde_json::from_slice(&bytes).unwrap(), None)
    };
    let mut buffers = Vec::new();
    for buffer in json["buffers"].as_array().into_iter().flatten() {
        let data = match buffer.get("uri").and_then(Value::as_str) {
            Some(uri) if uri.starts_with("data:") => {
                let b64 = &uri[uri.find(',').unwrap() + 1..];
                base64::engine::general_purpose::STANDARD
                    .decode(b64)
                    .unwrap()
            }
            Some(uri) => std::fs::read(path.parent().unwrap().join(uri)).unwrap(),
            None => glb_bin.clone().expect("a GLB's BIN chunk"),
        };
        buffers.push(data);
    }
    Document { json, buffers }
}

/// Accessor `index` as rows of f64 (any component type the fixtures use).
fn read_accessor(doc: &Document, index: usize) -> Vec<Vec<f64>> {
    let acc = &doc.json["accessors"][index];
    assert!(
        acc.get("sparse").is_none(),
        "sparse accessors: not in the oracle"
    );
    let count = acc["count"].as_u64().unwrap() as usize;
    let width = match acc["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        other => panic!("accessor type {other}"),
    };
    let (size, read): (usize, fn(&[u8]) -> f64) = match acc["componentType"].as_u64().unwrap() {
        5126 => (4, |b| f64::from(f32::from_le_bytes(b.try_into().unwrap()))),
        5125 => (4, |b| f64::from(u32::from_le_bytes(b.try_into().unwrap()))),
        5123 => (2, |b| f64::from(u16::from_le_bytes(b.try_into().unwrap()))),
        5121 => (1, |b| f64::from(b[0])),
        other => panic!("component type {other}"),
    };
    let view = &doc.json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let data = &doc.buffers[view["buffer"].as_u64().unwrap() as usize];
    let start = view.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize
        + acc.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
    let stride = view
        .get("byteStride")
        .and_then(Value::as_u64)
        .map_or(size * width, |s| s as usize);
    (0..count)
        .map(|i| {
            (0..width)
                .map(|k| {
                    let at = start + i * stride + k * size;
                    read(&data[at..at + size])
                })
                .collect()
        })
        .collect()
}

/// One world-space triangle: positions, and normals where the file has
/// usable ones (finite, non-zero).
struct Triangle {
    positions: [V3; 3],
    normals: [Option<V3>; 3],
}

fn oracle_triangles(path: &Path) -> Vec<Triangle> {
    let doc = read_document(path);
    let scene = doc.json.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
    let mut stack: Vec<(usize, M4)> = doc.json["scenes"][scene]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| (n.as_u64().unwrap() as usize, IDENTITY))
        .collect();
    let mut out = Vec::new();
    while let Some((index, parent)) = stack.pop() {
        let node = &doc.json["nodes"][index];
        let world = mul(&parent, &local_matrix(node));
        for child in node
            .get("children")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            stack.push((child.as_u64().unwrap() as usize, world));
        }
        let Some(mesh) = node.get("mesh").and_then(Value::as_u64) else {
            continue;
        };
        let m3 = upper3(&world);
        let mirrored = det3(&m3) < 0.0;
        let normal_matrix = inverse_transpose(&m3);
        for prim in doc.json["meshes"][mesh as usize]["primitives"]
            .as_array()
            .unwrap()
        {
            assert!(
                prim.get("mode").and_then(Value::as_u64).unwrap_or(4) == 4,
                "triangles only"
            );
            let attrs = &prim["attributes"];
            let positions: Vec<V3> =
                read_accessor(&doc, attrs["POSITION"].as_u64().unwrap() as usize)
                    .into_iter()
                    .map(|p| point(&world, [p[0], p[1], p[2]]))
                    .collect();
            let normals: Vec<Option<V3>> = match attrs.get("NORMAL").and_then(Value::as_u64) {
                Some(a) => read_accessor(&doc, a as usize)
                    .into_iter()
                    .map(|n| {
                        let n = [n[0], n[1], n[2]];
                        let usable = n.iter().all(|c| c.is_finite()) && dot(n, n) > 0.0;
                        usable.then(|| normalize(apply3(&normal_matrix, n)))
                    })
                    .collect(),
                None => vec![None; positions.len()],
            };
            let indices: Vec<usize> = match prim.get("indices").and_then(Value::as_u64) {
                Some(a) => read_accessor(&doc, a as usize)
                    .into_iter()
                    .map(|i| i[0] as usize)
                    .collect(),
                None => (0..positions.len()).collect(),
            };
            for t in indices.chunks_exact(3) {
                // The spec: a negative determinant makes the winding
                // clockwise; front faces stay counter-clockwise in world
                // space by reversing it.
                let t = if mirrored {
                    [t[0], t[2], t[1]]
                } else {
                    [t[0], t[1], t[2]]
                };
                out.push(Triangle {
                    positions: t.map(|i| positions[i]),
                    normals: t.map(|i| normals[i]),
                });
            }
        }
    }
    out
}

fn close(a: V3, b: V3, tol: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tol * (1.0 + a[k].abs()))
}

fn compare_with_the_importer(path: &Path) {
    let scene = shadelab::scene::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut imported: Vec<([V3; 3], [V3; 3])> = Vec::new();
    for object in &scene.objects {
        if let Shape::Mesh(mesh) = &object.shape {
            for t in &mesh.triangles {
                let p = t.map(|i| mesh.positions[i as usize].to_array());
                let n = t.map(|i| mesh.normals[i as usize].to_array());
                imported.push((p, n));
            }
        }
    }
    let name = path.display();
    let oracle: Vec<Triangle> = oracle_triangles(path)
        .into_iter()
        // Zero-area triangles are dropped on import (with a warning).
        .filter(|t| {
            let [a, b, c] = t.positions;
            dot(cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(c, a))) > 0.0
        })
        .collect();
    assert_eq!(imported.len(), oracle.len(), "{name}: triangle count");
    // Node transforms are f32 in the file and composed in f32 by the
    // importer (the oracle composes in f64): they agree to about 1e-8
    // relative; 1e-6 is some 15 f32 ulps. The normal-matrix bug moves
    // normals by degrees, the winding bug swaps whole corners.
    const TOL: f64 = 1e-6;
    for (k, want) in oracle.iter().enumerate() {
        // The same triangle, the same winding: a rotation of its corners.
        let found = imported.iter().find_map(|(p, n)| {
            (0..3).find_map(|r| {
                (0..3)
                    .all(|c| close(p[(r + c) % 3], want.positions[c], TOL))
                    .then(|| [0, 1, 2].map(|c| n[(r + c) % 3]))
            })
        });
        let Some(normals) = found else {
            panic!(
                "{name}: oracle triangle {k} {:?} is not imported with this winding",
                want.positions
            );
        };
        for (c, want_n) in want.normals.iter().enumerate() {
            if let Some(want_n) = want_n {
                assert!(
                    close(normals[c], *want_n, TOL),
                    "{name}: triangle {k} corner {c}: normal {:?}, oracle {want_n:?}",
                    normals[c]
                );
            }
        }
    }
}

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}

#[test]
fn a_skewed_mirrored_hierarchy_imports_as_the_specification_says() {
    compare_with_the_importer(&repo("tests/data/skewed.gltf"));
}

#[test]
fn every_fixture_and_asset_gltf_imports_as_the_specification_says() {
    let mut files = Vec::new();
    for dir in ["tests/data", "assets/models", "assets/hard/models"] {
        for entry in std::fs::read_dir(repo(dir)).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            // nan_position and corrupt are bad input (tests/cli/bad_input.rs).
            let gltf = name.ends_with(".gltf") || name.ends_with(".glb");
            if gltf && !name.starts_with("nan_position") && !name.starts_with("corrupt") {
                files.push(path);
            }
        }
    }
    assert!(files.len() >= 14, "{files:?}");
    for path in files {
        compare_with_the_importer(&path);
    }
}
