//! glTF materials in the lecture's lighting model: the metallic-roughness
//! mapping and its `extras` overrides, the warning for what the model does
//! not take, the default material, and the scene's material list.

use glam::DVec3;

use super::accessors::f32x3;
use super::document::GltfFile;
use super::locations::material_label;
use super::textures::base_colour_texture;
use crate::scene::defaults::DEFAULT_MATERIAL;
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;
use crate::scene::image_file::TextureStore;
use crate::scene::model::Material;

/// Maps a glTF metallic-roughness material to the lecture's model.
///
/// With `base = baseColorFactor`, `m = metallicFactor`, `r = roughnessFactor`
/// (both clamped to [0, 1]):
///
/// ```text
/// color = base.rgb
/// ka    = 0.2
/// kd    = 0.8 * (1 - m * (1 - r))
/// ks    = (0.04 + 0.96 * m) * (1 - r)
/// p     = clamp(2 / max(r^4, 1e-4) - 2, 1, 500)
/// kr    = m * (1 - r)
/// kt    = 1 - base.alpha   when alphaMode is BLEND, else 0
/// ior   = KHR_materials_ior.ior if present, else 1.5 when kt > 0, else 1.0
/// ```
///
/// Diffuse fades only for smooth metals: a rough metal scatters light
/// broadly, which this model can only show as diffuse. It also keeps a
/// material without a PBR block (glTF defaults m = r = 1) from rendering
/// ambient-only.
///
/// The base colour texture is added by the caller (`base_colour_texture`,
/// the `gltf` module docs); the other textures and emission are not modelled
/// (each announced by a warning, `unmodelled_features`). Then any of `ka`, `kd`, `ks`, `p`, `kr`, `kt`,
/// `ior` present in the material's `extras` object replaces the computed
/// value (it must be a finite number, `>= 0`, and `ior > 0`; other extras
/// keys are ignored). A primitive without a material gets color 0.8 grey,
/// ka 0.2, kd 0.8, ks 0, p 32, kr 0, kt 0, ior 1.
pub fn map_material(
    file_label: &str,
    name: String,
    mat: &gltf::Material,
    raw_materials: &serde_json::Value,
) -> Result<Material, SceneError> {
    let pbr = mat.pbr_metallic_roughness();
    let base = pbr.base_color_factor();
    let m = f64::from(pbr.metallic_factor()).clamp(0.0, 1.0);
    let r = f64::from(pbr.roughness_factor()).clamp(0.0, 1.0);
    let kt = if mat.alpha_mode() == gltf::material::AlphaMode::Blend {
        (1.0 - f64::from(base[3])).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let ior_ext = mat.index().and_then(|i| {
        raw_materials
            .get(i)?
            .get("extensions")?
            .get("KHR_materials_ior")?
            .get("ior")?
            .as_f64()
            .filter(|x| x.is_finite() && *x > 0.0)
    });
    let mut out = Material {
        name,
        color: f32x3([base[0], base[1], base[2]]).max(DVec3::ZERO),
        ka: DEFAULT_MATERIAL.ka,
        kd: 0.8 * (1.0 - m * (1.0 - r)),
        ks: (0.04 + 0.96 * m) * (1.0 - r),
        p: (2.0 / r.powi(4).max(1e-4) - 2.0).clamp(1.0, 500.0),
        kr: m * (1.0 - r),
        kt,
        ior: ior_ext.unwrap_or(if kt > 0.0 { 1.5 } else { 1.0 }),
        pattern: None,
    };
    if let Some(raw) = mat.extras() {
        let value: serde_json::Value = serde_json::from_str(raw.get()).unwrap_or_default();
        if let Some(obj) = value.as_object() {
            let which = mat.name().map_or_else(
                || format!("material {}", mat.index().unwrap_or(0)),
                |n| format!("material `{n}`"),
            );
            for (key, slot) in [
                ("ka", &mut out.ka),
                ("kd", &mut out.kd),
                ("ks", &mut out.ks),
                ("p", &mut out.p),
                ("kr", &mut out.kr),
                ("kt", &mut out.kt),
                ("ior", &mut out.ior),
            ] {
                let Some(v) = obj.get(key) else { continue };
                let x = v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    SceneError::mesh(
                        file_label,
                        format!("{which}: extras key `{key}` is {v}; expected a finite number"),
                    )
                })?;
                let ok = if key == "ior" { x > 0.0 } else { x >= 0.0 };
                if !ok {
                    return Err(SceneError::mesh(
                        file_label,
                        format!(
                            "{which}: extras key `{key}` is {x}; expected a number {}",
                            if key == "ior" { "> 0" } else { ">= 0" }
                        ),
                    ));
                }
                *slot = x;
            }
        }
    }
    Ok(out)
}

/// The file's material `mat` as [`map_material`] maps it, with its base
/// colour texture (fetched from `store` within `limits`, beside the file's
/// `geometry`), and a warning naming what it has that is not modelled.
pub(super) fn file_material(
    file: &GltfFile,
    mat: &gltf::Material,
    store: &mut TextureStore,
    limits: &LoadLimits,
    geometry: u64,
    warnings: &mut Vec<String>,
) -> Result<Material, SceneError> {
    let label = material_label(mat);
    let unmodelled = unmodelled_features(file, mat);
    if !unmodelled.is_empty() {
        warnings.push(format!(
            "{}: material `{label}` has {}, which shadelab does not model; it renders without {}",
            file.label,
            unmodelled.join(", "),
            if unmodelled.len() == 1 { "it" } else { "them" }
        ));
    }
    let mut m = map_material(
        &file.label,
        format!("{}/{label}", file.stem),
        mat,
        &file.raw.materials,
    )?;
    m.pattern = base_colour_texture(file, mat, store, limits, geometry, warnings)?;
    Ok(m)
}

/// What a glTF material carries that the lighting model does not take:
/// each named for the warning, so that an asset never renders in other
/// colours than its author's without a word. The textures other than the
/// base colour's and emission are not modelled; `KHR_materials_ior` is,
/// through `ior`, and `KHR_texture_transform` on the base colour texture
/// is. Other extensions on the base colour texture (its texture info or
/// its texture) are named too: its PNG or JPEG source is what is drawn.
fn unmodelled_features(file: &GltfFile, mat: &gltf::Material) -> Vec<String> {
    let raw_materials = &file.raw.materials;
    let pbr = mat.pbr_metallic_roughness();
    let mut features = Vec::new();
    let keys = |v: Option<&serde_json::Value>| -> Vec<String> {
        v.and_then(|v| v.get("extensions")?.as_object().cloned())
            .map(|o| o.keys().cloned().collect())
            .unwrap_or_default()
    };
    if let Some(info) = pbr.base_color_texture() {
        let info_json = mat.index().and_then(|i| {
            raw_materials
                .get(i)?
                .get("pbrMetallicRoughness")?
                .get("baseColorTexture")
        });
        let texture_json = file.raw.textures.get(info.texture().index());
        let others = keys(info_json)
            .into_iter()
            .filter(|k| k != "KHR_texture_transform")
            .chain(keys(texture_json));
        for name in others {
            features.push(format!(
                "the extension {name} on its base colour texture (its PNG or JPEG source is drawn)"
            ));
        }
    }
    let mut note = |present: bool, what: &str| {
        if present {
            features.push(what.to_string());
        }
    };
    note(
        pbr.metallic_roughness_texture().is_some(),
        "a metallic-roughness texture",
    );
    note(mat.normal_texture().is_some(), "a normal map");
    note(mat.occlusion_texture().is_some(), "an occlusion texture");
    note(mat.emissive_texture().is_some(), "an emissive texture");
    note(
        mat.emissive_factor() != [0.0; 3],
        "emission (emissiveFactor)",
    );
    note(
        mat.alpha_mode() == gltf::material::AlphaMode::Mask,
        "alpha masking (alphaMode MASK)",
    );
    let extensions = mat
        .index()
        .and_then(|i| {
            raw_materials
                .get(i)?
                .get("extensions")?
                .as_object()
                .cloned()
        })
        .unwrap_or_default();
    for name in extensions.keys().filter(|k| *k != "KHR_materials_ior") {
        features.push(format!("the extension {name}"));
    }
    features
}

/// The material of a primitive without one, as [`map_material`] states it.
pub(super) fn default_material(name: String) -> Material {
    Material {
        name,
        color: DVec3::splat(0.8),
        ..DEFAULT_MATERIAL
    }
}

/// Adds `m` to `materials` and returns its index; an identical material
/// (same name and values) already there is reused. A different material
/// with the same name gets a `#2`, `#3`, ... suffix.
pub(crate) fn push_material(materials: &mut Vec<Material>, m: Material) -> usize {
    let base = m.name.clone();
    let mut k = 1;
    loop {
        let name = if k == 1 {
            base.clone()
        } else {
            format!("{base}#{k}")
        };
        let candidate = Material {
            name: name.clone(),
            ..m.clone()
        };
        match materials.iter().position(|x| x.name == name) {
            None => {
                materials.push(candidate);
                return materials.len() - 1;
            }
            Some(i) if materials[i] == candidate => return i,
            Some(_) => k += 1,
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{DMat4, DVec3};

    use crate::scene::gltf::test_support::{err_of, fixture, meshes, only_mesh, write_gltf};

    /// What the model does not take is announced, one line per material
    /// naming each feature (issue 31: the Duck rendered white-grey without
    /// a word). Vertex colours and base colour textures are modelled now
    /// and say nothing; a normal map's image is never read.
    #[test]
    fn unmodelled_material_features_are_announced() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = write_gltf(dir.path(), "painted", &tri, None, None, |d| {
            d["images"] = serde_json::json!([{"uri": "duck.png"}]);
            d["textures"] = serde_json::json!([{"source": 0}]);
            d["materials"] = serde_json::json!([{
                "name": "duck",
                "normalTexture": {"index": 0},
                "emissiveFactor": [0.5, 0.0, 0.0],
                "extensions": {"KHR_materials_ior": {"ior": 1.4}, "KHR_materials_clearcoat": {}}
            }]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
            // COLOR_0 reuses the positions' accessor (VEC3 floats).
            d["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 0.into();
        });
        let l = meshes(&p, DMat4::IDENTITY).unwrap();
        let material: Vec<&String> = l
            .warnings
            .iter()
            .filter(|w| w.contains("material `duck`"))
            .collect();
        assert_eq!(material.len(), 1, "{:?}", l.warnings);
        for feature in [
            "a normal map",
            "emission (emissiveFactor)",
            "the extension KHR_materials_clearcoat",
        ] {
            assert!(material[0].contains(feature), "{feature}: {}", material[0]);
        }
        assert!(
            !material[0].contains("KHR_materials_ior") && !material[0].contains("base colour"),
            "{}",
            material[0]
        );
        assert!(
            material[0].ends_with("it renders without them"),
            "{}",
            material[0]
        );
        assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
        let m = only_mesh(&l);
        assert_eq!(m.colors, m.positions, "COLOR_0 read as the floats it is");
        // A plain material says nothing.
        let plain = write_gltf(dir.path(), "plain", &tri, None, None, |d| {
            d["materials"] = serde_json::json!([{"name": "grey"}]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
        });
        assert!(meshes(&plain, DMat4::IDENTITY).unwrap().warnings.is_empty());
    }

    #[test]
    fn indexed_triangle_with_normals_and_mapped_material() {
        let l = meshes(&fixture("tri_indexed.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.positions, vec![DVec3::ZERO, DVec3::X, DVec3::Y]);
        assert_eq!(m.normals, vec![DVec3::Z; 3]);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert!(l.warnings.is_empty(), "{:?}", l.warnings);
        // metallic 0, roughness 0.5, extras p = 64 and ka = 0.1.
        let mat = &l.materials[l.objects[0].material];
        assert_eq!(mat.name, "tri_indexed/red");
        assert_eq!(mat.color, DVec3::X);
        assert_eq!(mat.kd, 0.8);
        assert!((mat.ks - 0.02).abs() < 1e-12);
        assert_eq!(mat.p, 64.0, "extras override the computed 30");
        assert_eq!(mat.ka, 0.1, "extras override");
        assert_eq!((mat.kr, mat.kt, mat.ior), (0.0, 0.0, 1.0));
    }

    #[test]
    fn extras_must_be_numbers() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = write_gltf(dir.path(), "extras", &tri, None, None, |d| {
            d["materials"] =
                serde_json::json!([{"name": "shiny", "extras": {"ks": "very", "kd": 0.1}}]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
        });
        let e = err_of(&p);
        assert!(
            e.contains("extras.gltf") && e.contains("`shiny`") && e.contains("`ks`"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "extras2", &tri, None, None, |d| {
            d["materials"] = serde_json::json!([{"name": "shiny", "extras": {"ks": 0.7, "kr": 0.25, "ior": 1.7, "kt": 0.5}}]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
        });
        let l = meshes(&p, DMat4::IDENTITY).unwrap();
        let m = &l.materials[0];
        // Default glTF material: metallic 1, roughness 1 -> kd 0.8, p 1.
        assert_eq!((m.kd, m.p), (0.8, 1.0));
        assert_eq!((m.ks, m.kr, m.ior, m.kt), (0.7, 0.25, 1.7, 0.5));
    }
}
