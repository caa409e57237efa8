//! Which pixels the CPU reference marks as near an edge, from what it
//! knows of each pixel's neighbours: where another renderer's rounding may
//! legitimately show something else.

/// Whether each pixel's 3x3 neighbourhood, clipped to the image, holds more
/// than one signature.
pub(super) fn signature_edges(width: usize, height: usize, signatures: &[u64]) -> Vec<bool> {
    neighbourhood_any(width, height, |own, other| {
        signatures[own] != signatures[other]
    })
}

/// Whether each pixel's 3x3 neighbourhood, clipped to the image, holds a
/// pixel whose `marks` is not 0.
pub(super) fn neighbourhoods(width: usize, height: usize, marks: &[u64]) -> Vec<bool> {
    neighbourhood_any(width, height, |_, other| marks[other] != 0)
}

/// Whether `test(pixel, neighbour)` holds for a pixel of each pixel's 3x3
/// neighbourhood, clipped to the image (indices `y * width + x`).
fn neighbourhood_any(
    width: usize,
    height: usize,
    test: impl Fn(usize, usize) -> bool,
) -> Vec<bool> {
    let mut found = vec![false; width * height];
    for y in 0..height {
        for x in 0..width {
            let own = y * width + x;
            let ys = y.saturating_sub(1)..(y + 2).min(height);
            found[own] = ys.into_iter().any(|ny| {
                (x.saturating_sub(1)..(x + 2).min(width)).any(|nx| test(own, ny * width + nx))
            });
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::signature_edges;

    #[test]
    fn signature_edges_mark_the_3x3_neighbourhood_of_a_change() {
        // 4 x 3, one odd pixel at (3, 0): its neighbours (2, 0), (2, 1),
        // (3, 1) and itself are marked, nothing else.
        let mut sigs = vec![7u64; 12];
        sigs[3] = 9;
        let edges = signature_edges(4, 3, &sigs);
        let marked: Vec<usize> = (0..12).filter(|&i| edges[i]).collect();
        assert_eq!(marked, vec![2, 3, 6, 7]);
        assert!(signature_edges(4, 3, &[1; 12]).iter().all(|e| !e));
    }
}
