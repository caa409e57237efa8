//! The checks a value gets after it parses, each error carrying the line
//! of the key it came from (`Spanned`): numbers >= 0 or > 0, colours,
//! integers in a range. [`Ctx`] is the file being read.

use std::path::Path;

use glam::DVec3;
use toml::Spanned;

use super::located_errors::line_col;
use super::schema::Finite;
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;

/// Semantic checks after parsing: errors carry the line of a `Spanned`.
/// `base_dir` resolves the files the scene names (meshes, textures).
pub(super) struct Ctx<'a> {
    pub(super) label: &'a str,
    pub(super) text: &'a str,
    pub(super) base_dir: &'a Path,
    pub(super) limits: &'a LoadLimits,
}

impl Ctx<'_> {
    pub(super) fn line<T>(&self, s: &Spanned<T>) -> usize {
        line_col(self.text, s.span().start).0
    }

    pub(super) fn err<T>(&self, at: &Spanned<T>, message: impl Into<String>) -> SceneError {
        SceneError::invalid(self.label, self.line(at), message)
    }

    pub(super) fn non_negative(&self, s: &Spanned<Finite>, what: &str) -> Result<f64, SceneError> {
        let v = s.get_ref().0;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(s, format!("`{what}` is {v}; expected a number >= 0")))
        }
    }

    pub(super) fn positive(&self, s: &Spanned<Finite>, what: &str) -> Result<f64, SceneError> {
        let v = s.get_ref().0;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(s, format!("`{what}` is {v}; expected a number > 0")))
        }
    }

    pub(super) fn non_negative3(
        &self,
        s: &Spanned<DVec3>,
        what: &str,
    ) -> Result<DVec3, SceneError> {
        let v = *s.get_ref();
        if v.min_element() >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                s,
                format!(
                    "`{what}` is [{}, {}, {}]; expected values >= 0",
                    v.x, v.y, v.z
                ),
            ))
        }
    }

    pub(super) fn int_in(
        &self,
        s: &Spanned<i64>,
        what: &str,
        lo: i64,
        hi: i64,
        why: &str,
    ) -> Result<u32, SceneError> {
        let v = *s.get_ref();
        if (lo..=hi).contains(&v) {
            u32::try_from(v).map_err(|_| self.err(s, format!("`{what}` is {v}; out of range")))
        } else {
            Err(self.err(
                s,
                format!("`{what}` is {v}{why}; expected an integer from {lo} to {hi}"),
            ))
        }
    }
}

/// `s`'s value mapped by `f`, keeping its place in the file.
pub(super) fn spanned_map<T, U>(s: &Spanned<T>, f: impl FnOnce(&T) -> U) -> Spanned<U> {
    Spanned::new(s.span(), f(s.get_ref()))
}
