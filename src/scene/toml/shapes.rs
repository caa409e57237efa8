//! `[[objects]]`: spheres, planes, boxes and meshes. Each object is held to
//! the keys of its own shape (a key of another shape is an error, named
//! with its line), its material is looked up by name, and it becomes an
//! [`Object`]; a mesh's file is imported through `gltf`, under the
//! object's transform and with its own materials unless one is named.

use glam::{DMat3, DMat4, DVec3};
use toml::Spanned;

use super::checks::Ctx;
use super::schema::{v3, NumOr3, ObjectRaw};
use crate::scene::error::SceneError;
use crate::scene::gltf;
use crate::scene::image_file::TextureStore;
use crate::scene::model::{Material, Object, Shape};

/// `R = Rz * Ry * Rx` for `[x, y, z]` in degrees.
pub fn rotation_from_deg(deg: DVec3) -> DMat3 {
    DMat3::from_rotation_z(deg.z.to_radians())
        * DMat3::from_rotation_y(deg.y.to_radians())
        * DMat3::from_rotation_x(deg.x.to_radians())
}

/// Every object in file order. `names` are the file's materials (the
/// first entries of `materials`); mesh files add theirs to `materials`,
/// their warnings to `warnings` and their images to `textures`. A sphere
/// that `f32` cannot trace from `eye` is refused (`huge_sphere`).
pub(super) fn objects(
    cx: &Ctx,
    raw: &[Spanned<ObjectRaw>],
    names: &[String],
    eye: DVec3,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    textures: &mut TextureStore,
) -> Result<Vec<Object>, SceneError> {
    let mut objects = Vec::new();
    for (i, obj) in raw.iter().enumerate() {
        let at = ObjectAt {
            cx,
            raw: obj.get_ref(),
            index: i + 1,
            shape: obj.get_ref().shape.get_ref().as_str(),
            names,
        };
        let converted = convert_object(&at, materials, warnings, textures)?;
        // A sphere that f32 cannot trace from this eye (huge_sphere).
        if let (Some(Shape::Sphere { center, radius, .. }), Some(r)) = (
            converted.first().map(|o: &Object| o.shape.clone()),
            &obj.get_ref().radius,
        ) {
            if let Some(why) = crate::huge_sphere::refusal(eye, center, radius) {
                return Err(cx.err(r, format!("object {} (sphere): {why}", i + 1)));
            }
        }
        objects.extend(converted);
    }
    Ok(objects)
}

/// The keys each shape accepts (besides `shape`).
fn allowed_keys(shape: &str) -> Option<&'static [&'static str]> {
    Some(match shape {
        "sphere" => &["center", "radius", "segments", "material"],
        "plane" => &["center", "normal", "size", "segments", "material"],
        "box" => &["center", "size", "rotate_deg", "material"],
        "mesh" => &["file", "translate", "rotate_deg", "scale", "material"],
        _ => return None,
    })
}

/// One `[[objects]]` table being converted: what its messages name (its
/// 1-based `index` and `shape`) and the materials it may name.
struct ObjectAt<'a> {
    cx: &'a Ctx<'a>,
    raw: &'a ObjectRaw,
    index: usize,
    shape: &'a str,
    names: &'a [String],
}

impl ObjectAt<'_> {
    /// A required key that is absent, at the line of `shape`.
    fn missing(&self, key: &str) -> SceneError {
        let (index, shape) = (self.index, self.shape);
        SceneError::invalid(
            self.cx.label,
            self.cx.line(&self.raw.shape),
            format!("object {index} ({shape}): missing required key `{key}`"),
        )
    }

    /// The index in `Scene::materials` of the material `m` names.
    fn lookup(&self, m: &Spanned<String>) -> Result<usize, SceneError> {
        let (index, shape, names) = (self.index, self.shape, self.names);
        let name = m.get_ref();
        names.iter().position(|n| n == name).ok_or_else(|| {
            let known = if names.is_empty() {
                "no materials are defined; add a [materials.NAME] table".to_string()
            } else {
                format!("expected one of {}", names.join(", "))
            };
            self.cx.err(
                m,
                format!("object {index} ({shape}): unknown material `{name}`; {known}"),
            )
        })
    }

    fn center(&self) -> Result<DVec3, SceneError> {
        self.raw
            .center
            .as_ref()
            .map(|c| v3(c.get_ref()))
            .ok_or_else(|| self.missing("center"))
    }

    fn segments(&self, default: i64, lo: i64, hi: i64) -> Result<u32, SceneError> {
        let index = self.index;
        match &self.raw.segments {
            Some(s) => self
                .cx
                .int_in(s, &format!("object {index}: segments"), lo, hi, ""),
            None => Ok(default as u32),
        }
    }

    /// `rotate_deg` as a rotation, none where it is absent.
    fn rotation(&self) -> DMat3 {
        rotation_from_deg(
            self.raw
                .rotate_deg
                .as_ref()
                .map_or(DVec3::ZERO, |r| v3(r.get_ref())),
        )
    }
}

/// One object: its shape known, its keys that shape's, then converted. A
/// mesh may give many objects, the primitives a shape one.
fn convert_object(
    at: &ObjectAt,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    textures: &mut TextureStore,
) -> Result<Vec<Object>, SceneError> {
    let (o, index, shape) = (at.raw, at.index, at.shape);
    let allowed = allowed_keys(shape).ok_or_else(|| {
        at.cx.err(
            &o.shape,
            format!(
                "object {index}: unknown shape `{shape}`; expected one of sphere, plane, box, mesh"
            ),
        )
    })?;
    refuse_other_shapes_keys(at, allowed)?;
    if shape == "mesh" {
        return mesh(at, materials, warnings, textures);
    }
    let material = at.lookup(o.material.as_ref().ok_or_else(|| at.missing("material"))?)?;
    let shape = match shape {
        "sphere" => sphere(at)?,
        "plane" => plane(at)?,
        _ => cuboid(at)?,
    };
    Ok(vec![Object { shape, material }])
}

/// Refuses, with its line, the first key present that `allowed` lacks.
fn refuse_other_shapes_keys(at: &ObjectAt, allowed: &[&str]) -> Result<(), SceneError> {
    let (o, cx, index, shape) = (at.raw, at.cx, at.index, at.shape);
    // Which keys are present, with their lines.
    let present: [(&str, Option<usize>); 10] = [
        ("center", o.center.as_ref().map(|s| cx.line(s))),
        ("radius", o.radius.as_ref().map(|s| cx.line(s))),
        ("segments", o.segments.as_ref().map(|s| cx.line(s))),
        ("normal", o.normal.as_ref().map(|s| cx.line(s))),
        ("size", o.size.as_ref().map(|s| cx.line(s))),
        ("rotate_deg", o.rotate_deg.as_ref().map(|s| cx.line(s))),
        ("material", o.material.as_ref().map(|s| cx.line(s))),
        ("file", o.file.as_ref().map(|s| cx.line(s))),
        ("translate", o.translate.as_ref().map(|s| cx.line(s))),
        ("scale", o.scale.as_ref().map(|s| cx.line(s))),
    ];
    for (key, line) in present {
        if let Some(line) = line {
            if !allowed.contains(&key) {
                return Err(SceneError::invalid(
                    cx.label,
                    line,
                    format!(
                        "object {index}: key `{key}` does not apply to a {shape}; expected one of shape, {}",
                        allowed.join(", ")
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A `mesh`: every mesh of its glTF file, under `T * R * S`, with the
/// named material or the file's own.
fn mesh(
    at: &ObjectAt,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    textures: &mut TextureStore,
) -> Result<Vec<Object>, SceneError> {
    let (o, cx, index) = (at.raw, at.cx, at.index);
    let file = o.file.as_ref().ok_or_else(|| at.missing("file"))?;
    let material = o.material.as_ref().map(|m| at.lookup(m)).transpose()?;
    let translate = o
        .translate
        .as_ref()
        .map_or(DVec3::ZERO, |t| v3(t.get_ref()));
    let rotation = at.rotation();
    let scale = match &o.scale {
        Some(s) => {
            let v = s.get_ref().splat();
            if v.x == 0.0 || v.y == 0.0 || v.z == 0.0 {
                return Err(cx.err(
                    s,
                    format!("object {index} (mesh): `scale` has a zero component; expected non-zero values"),
                ));
            }
            v
        }
        None => DVec3::ONE,
    };
    let post =
        DMat4::from_translation(translate) * DMat4::from_mat3(rotation) * DMat4::from_scale(scale);
    let path = cx.base_dir.join(file.get_ref());
    let mut loading = gltf::Loading {
        limits: cx.limits,
        textures,
    };
    gltf::load_meshes(&path, post, material, materials, warnings, &mut loading).map_err(|e| {
        SceneError::InObject {
            file: cx.label.to_string(),
            line: cx.line(file),
            object: index,
            source: Box::new(e),
        }
    })
}

fn sphere(at: &ObjectAt) -> Result<Shape, SceneError> {
    let center = at.center()?;
    let r = at.raw.radius.as_ref().ok_or_else(|| at.missing("radius"))?;
    let radius = at.cx.positive(r, &format!("object {}: radius", at.index))?;
    Ok(Shape::Sphere {
        center,
        radius,
        segments: at.segments(32, 3, 4096)?,
    })
}

/// A `plane`: a square of edge `size` (one number) about a non-zero
/// `normal`.
fn plane(at: &ObjectAt) -> Result<Shape, SceneError> {
    let (cx, index) = (at.cx, at.index);
    let center = at.center()?;
    let n = at.raw.normal.as_ref().ok_or_else(|| at.missing("normal"))?;
    let normal = v3(n.get_ref()).normalize_or_zero();
    if normal == DVec3::ZERO || !normal.is_finite() {
        return Err(cx.err(
            n,
            format!("object {index} (plane): `normal` is the zero vector; expected a direction"),
        ));
    }
    let s = at.raw.size.as_ref().ok_or_else(|| at.missing("size"))?;
    let size = match s.get_ref() {
        NumOr3::Num(x) if *x > 0.0 => *x,
        NumOr3::Num(x) => {
            return Err(cx.err(
                s,
                format!("object {index} (plane): `size` is {x}; expected a number > 0"),
            ))
        }
        NumOr3::Vec(_) => {
            return Err(cx.err(
                s,
                format!("object {index} (plane): `size` is an array; expected one number (the edge length of the square)"),
            ))
        }
    };
    Ok(Shape::Plane {
        center,
        normal,
        size,
        segments: at.segments(1, 1, 1024)?,
    })
}

/// A `box`: full edge lengths `size` > 0 along its own axes, turned by
/// `rotate_deg`.
fn cuboid(at: &ObjectAt) -> Result<Shape, SceneError> {
    let center = at.center()?;
    let s = at.raw.size.as_ref().ok_or_else(|| at.missing("size"))?;
    let size = s.get_ref().splat();
    if size.min_element() <= 0.0 {
        return Err(at.cx.err(
            s,
            format!(
                "object {} (box): `size` must be > 0 along every axis; expected edge lengths > 0",
                at.index
            ),
        ));
    }
    Ok(Shape::Box {
        center,
        half_extents: size * 0.5,
        rotation: at.rotation(),
    })
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::super::parse;
    use super::super::test_support::*;
    use super::*;

    #[test]
    fn rotation_order_is_x_then_y_then_z() {
        let r = rotation_from_deg(DVec3::new(90.0, 90.0, 0.0));
        // X first: +Y -> +Z; then Y: +Z -> +X.
        assert!((r * DVec3::Y - DVec3::X).length() < 1e-12);
        let r = rotation_from_deg(DVec3::new(0.0, 90.0, 90.0));
        // Y first: +X -> -Z; then Z leaves -Z alone.
        assert!((r * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
    }

    #[test]
    fn key_of_another_shape_is_rejected() {
        let e = parse_err(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"plane\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nsize = 1\nradius = 2\nmaterial = \"m\"\n",
        ));
        assert_has(&e, &["line 10", "object 1", "`radius`", "plane", "normal"]);
        let e = parse_err(&with_camera("[[objects]]\nshape = \"cone\"\n"));
        assert_has(&e, &["line 5", "`cone`", "sphere, plane, box, mesh"]);
    }

    #[test]
    fn unknown_material_names_object_line_and_choices() {
        let e = parse_err(&with_camera(
            "[materials.plaster]\n[materials.glass]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"marble\"\n",
        ));
        assert_has(&e, &["line 10", "object 1", "`marble`", "glass, plaster"]);
        let e = parse_err(&with_camera(
            "[[objects]]\nshape = \"box\"\ncenter = [0, 0, 0]\nsize = 1\nmaterial = \"x\"\n",
        ));
        assert_has(&e, &["line 8", "no materials are defined"]);
    }

    /// A mesh under a patterned material needs texture coordinates; the
    /// test cube has none, and the message names the primitive and the
    /// material.
    #[test]
    fn a_pattern_on_a_mesh_without_texture_coordinates_is_refused() {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let text = with_camera(
            "[materials.m]\npattern = { kind = \"checker\" }\n[[objects]]\nshape = \"mesh\"\nfile = \"cube.glb\"\nmaterial = \"m\"\n",
        );
        let e = parse(&text, &dir, "t.toml").unwrap_err().to_string();
        assert_has(
            &e,
            &[
                "cube.glb",
                "has no texture coordinates (TEXCOORD_0)",
                "material `m`",
            ],
        );
    }

    #[test]
    fn mesh_errors_name_scene_and_mesh_file() {
        let dir = tempfile::tempdir().unwrap();
        let e = parse(
            &with_camera("[[objects]]\nshape = \"mesh\"\nfile = \"models/missing.glb\"\n"),
            dir.path(),
            "scene.toml",
        )
        .unwrap_err()
        .to_string();
        assert_has(
            &e,
            &[
                "scene.toml line 6",
                "object 1 (mesh)",
                "missing.glb",
                "cannot read",
            ],
        );
        let corrupt = fixture("corrupt.glb");
        let text = with_camera(&format!(
            "[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
            corrupt.display().to_string()
        ));
        let e = parse_err(&text);
        assert_has(&e, &["scene.toml line 6", "corrupt.glb", "not a valid"]);
        let nan = fixture("nan_position.gltf");
        let text = with_camera(&format!(
            "[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
            nan.display().to_string()
        ));
        let e = parse_err(&text);
        assert_has(
            &e,
            &["nan_position.gltf", "POSITION", "accessor 0", "finite"],
        );
    }

    #[test]
    fn mesh_object_uses_file_materials_and_transform() {
        let cube = fixture("cube.glb");
        let text = with_camera(&format!(
            "[[objects]]\nshape = \"mesh\"\nfile = {:?}\nscale = [-2, 1, 1]\ntranslate = [0, 3, 0]\n\
             [[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
            cube.display().to_string(),
            cube.display().to_string()
        ));
        let s = parse_ok(&text);
        assert_eq!(s.objects.len(), 2);
        assert_eq!(
            s.materials.len(),
            1,
            "the same file's material is added once"
        );
        assert_eq!(s.materials[0].name, "cube/ochre");
        assert_eq!(s.objects[0].material, 0);
        assert_eq!(s.objects[1].material, 0);
        let Shape::Mesh(m) = &s.objects[0].shape else {
            panic!()
        };
        assert!(m
            .positions
            .iter()
            .all(|p| (p.x.abs() - 1.0).abs() < 1e-12 && (p.y - 3.0).abs() <= 0.5 + 1e-12));
        // Mirrored by the negative scale: the winding still agrees with the normals.
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let g = (b - a).cross(c - a);
            for &i in t {
                assert!(g.dot(m.normals[i as usize]) > 0.0);
            }
        }
    }

    #[test]
    fn absurd_and_invalid_values() {
        for (rest, parts) in [
            (
                "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0\nmaterial = \"m\"\n",
                &["line 8", "object 1: radius", "> 0"][..],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nsegments = 2\nmaterial = \"m\"\n",
                &["line 9", "segments", "3 to 4096"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"plane\"\ncenter = [0, 0, 0]\nnormal = [0, 0, 0]\nsize = 1\nmaterial = \"m\"\n",
                &["line 8", "`normal`", "zero"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"plane\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nsize = [1, 2, 3]\nmaterial = \"m\"\n",
                &["line 9", "`size`", "one number"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"box\"\ncenter = [0, 0, 0]\nsize = [1, 0, 1]\nmaterial = \"m\"\n",
                &["line 8", "`size`", "> 0"],
            ),
            ("[[objects]]\nshape = \"mesh\"\nfile = \"x.glb\"\nscale = [1, 0, 1]\n", &["line 7", "`scale`", "non-zero"]),
        ] {
            let e = parse_err(&with_camera(rest));
            assert_has(&e, parts);
        }
    }
}
