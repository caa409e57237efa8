//! Where the plot's point labels go so that no two overlap: each label
//! tries positions on rings around its point, nearest first, and takes the
//! first that stays inside the plotting area and clears every label placed
//! before it and every point marker. Pure geometry in pixels; the plot
//! draws what this returns.

/// A box in pixels: left, top, right, bottom (right and bottom exclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    pub left: i32,
    pub top: i32,
    pub right: i32,
    pub bottom: i32,
}

impl Rect {
    pub fn at(left: i32, top: i32, (w, h): (u32, u32)) -> Rect {
        Rect {
            left,
            top,
            right: left + w as i32,
            bottom: top + h as i32,
        }
    }

    /// Whether the two boxes share any pixel.
    pub fn intersects(&self, other: &Rect) -> bool {
        self.left < other.right
            && other.left < self.right
            && self.top < other.bottom
            && other.top < self.bottom
    }

    fn inside(&self, bounds: &Rect) -> bool {
        self.left >= bounds.left
            && self.top >= bounds.top
            && self.right <= bounds.right
            && self.bottom <= bounds.bottom
    }
}

/// Pixels between a point and the nearest edge of its label, ring by ring.
const RING_STEP: i32 = 7;
const MAX_RINGS: i32 = 40;

/// One box per label, in order: label `i` of size `sizes[i]` near
/// `points[i]`, all inside `bounds`, none overlapping another or any point
/// marker (a square of `marker` pixels around each point). `None` for a
/// label that found no free place (then the plot leaves it out; its number
/// is still listed beside the plot).
pub fn place_labels(
    points: &[(i32, i32)],
    sizes: &[(u32, u32)],
    bounds: Rect,
    marker: i32,
) -> Vec<Option<Rect>> {
    let markers: Vec<Rect> = points
        .iter()
        .map(|&(x, y)| Rect {
            left: x - marker,
            top: y - marker,
            right: x + marker + 1,
            bottom: y + marker + 1,
        })
        .collect();
    let mut placed: Vec<Rect> = Vec::with_capacity(points.len());
    let mut out = Vec::with_capacity(points.len());
    for (&(x, y), &(w, h)) in points.iter().zip(sizes) {
        let (w, h) = (w as i32, h as i32);
        let free = |r: &Rect| {
            r.inside(&bounds)
                && !placed.iter().any(|p| p.intersects(r))
                && !markers.iter().any(|m| m.intersects(r))
        };
        let found = (1..=MAX_RINGS).find_map(|ring| {
            let gap = marker + ring * RING_STEP - RING_STEP / 2;
            // Right, left, above, below, then the four corners.
            let candidates = [
                (x + gap, y - h / 2),
                (x - gap - w, y - h / 2),
                (x - w / 2, y - gap - h),
                (x - w / 2, y + gap),
                (x + gap, y - gap - h),
                (x - gap - w, y - gap - h),
                (x + gap, y + gap),
                (x - gap - w, y + gap),
            ];
            candidates
                .into_iter()
                .map(|(left, top)| Rect::at(left, top, (w as u32, h as u32)))
                .find(|r| free(r))
        });
        if let Some(r) = found {
            placed.push(r);
        }
        out.push(found);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crowded_points_get_labels_that_do_not_overlap() {
        // Twelve points on top of one another and a row of near neighbours.
        let mut points = vec![(200, 150); 12];
        points.extend((0..10).map(|i| (100 + 4 * i, 80)));
        let sizes = vec![(18, 14); points.len()];
        let bounds = Rect {
            left: 0,
            top: 0,
            right: 400,
            bottom: 300,
        };
        let boxes = place_labels(&points, &sizes, bounds, 5);
        let placed: Vec<Rect> = boxes.iter().flatten().copied().collect();
        assert_eq!(placed.len(), points.len(), "every label found a place");
        for (i, a) in placed.iter().enumerate() {
            assert!(a.inside(&bounds));
            for b in &placed[i + 1..] {
                assert!(!a.intersects(b), "{a:?} overlaps {b:?}");
            }
            for &(x, y) in &points {
                assert!(
                    !(a.left <= x && x < a.right && a.top <= y && y < a.bottom),
                    "{a:?} covers the point ({x}, {y})"
                );
            }
        }
    }

    #[test]
    fn rectangles_that_only_touch_do_not_intersect() {
        let a = Rect::at(0, 0, (10, 10));
        assert!(!a.intersects(&Rect::at(10, 0, (5, 5))));
        assert!(a.intersects(&Rect::at(9, 9, (5, 5))));
    }
}
