//! Accessors: checked before the `gltf` crate's reader reads them (type,
//! sparseness, and that they lie inside their buffer view and buffer), and
//! glTF's `f32` values widened to the `f64` of the scene model.

use glam::DVec3;
use gltf::accessor::{DataType, Dimensions};

use super::document::GltfFile;
use crate::scene::error::SceneError;

pub(super) fn f32x3(v: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

/// Checks an accessor so that the `gltf` crate's reader cannot panic on it.
pub(super) fn check_accessor(
    file: &GltfFile,
    what: &str,
    acc: &gltf::Accessor,
    dims: Dimensions,
    types: &[DataType],
) -> Result<(), SceneError> {
    let err = |msg: String| {
        SceneError::mesh(
            &file.label,
            format!("{what} (accessor {}) {msg}", acc.index()),
        )
    };
    if acc.dimensions() != dims || !types.contains(&acc.data_type()) || acc.normalized() {
        return Err(err(format!(
            "has type {:?} {:?}{}; expected {:?} of {:?}",
            acc.dimensions(),
            acc.data_type(),
            if acc.normalized() {
                " (normalized)"
            } else {
                ""
            },
            dims,
            types
        )));
    }
    check_accessor_storage(file, what, acc)
}

/// The part of `check_accessor` that holds for every type: not sparse, not
/// empty, and inside its buffer view and buffer.
pub(super) fn check_accessor_storage(
    file: &GltfFile,
    what: &str,
    acc: &gltf::Accessor,
) -> Result<(), SceneError> {
    let err = |msg: String| {
        SceneError::mesh(
            &file.label,
            format!("{what} (accessor {}) {msg}", acc.index()),
        )
    };
    if acc.sparse().is_some() {
        return Err(err(
            "is a sparse accessor, which is not supported; export without sparse accessors".into(),
        ));
    }
    if acc.count() == 0 {
        return Err(err("is empty".into()));
    }
    let view = acc.view().ok_or_else(|| err("has no buffer view".into()))?;
    let elem = acc.size();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(err(format!(
            "has a byte stride {stride} smaller than its element size {elem}"
        )));
    }
    let end = stride
        .checked_mul(acc.count() - 1)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(acc.offset()));
    if end.is_none_or(|e| e > view.length()) {
        return Err(err(format!(
            "does not fit in its buffer view {} ({} bytes)",
            view.index(),
            view.length()
        )));
    }
    let buffer_len = file
        .buffers
        .get(view.buffer().index())
        .map_or(0, |b| b.len());
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|e| e > buffer_len) {
        return Err(err(format!(
            "uses buffer view {} which runs past the end of buffer {}",
            view.index(),
            view.buffer().index()
        )));
    }
    Ok(())
}
