//! The path signature: a hash of everything discrete along a pixel's ray
//! trees, so that neighbours seeing the same surfaces and shadows can be
//! told from those that do not.

use crate::cpu::intersect::Hit;
use crate::rt_scene::Primitive;

/// What one ray is in the tree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum RayKind {
    Primary = 0,
    Reflected = 1,
    Refracted = 2,
    /// A diffuse bounce (secondary illumination).
    Diffuse = 5,
}

/// FNV-1a 64 over the discrete events of a pixel's ray trees, in the order
/// they happen (`docs/raytracing.md`, "Path signature"):
///
/// - every traced ray: its kind (1 byte: 0 primary, 1 reflected,
///   2 refracted, 5 a diffuse bounce), its depth (u32), the object hit (u32, `u32::MAX` on a
///   miss) and the part of it (u32: a box's face `2 axis + (0 for -, 1 for
///   +)`, else 0; `u32::MAX` on a miss); integers little-endian;
/// - after a hit's ray record, for every light the shading asks about
///   (`lighting::facing`, light not at the point), in light order: the byte 3, the
///   light index (u32) and 1 if it is visible (always, with shadows off) or
///   2 if its shadow ray is blocked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PathSignature(pub u64);

impl Default for PathSignature {
    fn default() -> Self {
        PathSignature(0xcbf2_9ce4_8422_2325)
    }
}

impl PathSignature {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    pub(super) fn ray(&mut self, kind: RayKind, depth: u32, hit: Option<&Hit>) {
        let (object, part) = match hit {
            None => (u32::MAX, u32::MAX),
            Some(h) => (
                h.object,
                match h.primitive {
                    Primitive::Box { face, .. } => face,
                    _ => 0,
                },
            ),
        };
        self.bytes(&[kind as u8]);
        self.bytes(&depth.to_le_bytes());
        self.bytes(&object.to_le_bytes());
        self.bytes(&part.to_le_bytes());
    }

    /// The pattern cell a hit lies in: a pattern's colour changes between
    /// cells as a surface's does at its edge.
    pub(super) fn cell(&mut self, cell: i64) {
        self.bytes(&[4]);
        self.bytes(&cell.to_le_bytes());
    }

    pub(super) fn light(&mut self, index: usize, visible: bool) {
        self.bytes(&[3]);
        self.bytes(&(index as u32).to_le_bytes());
        self.bytes(&[if visible { 1 } else { 2 }]);
    }
}
