//! Overlays drawn on all three views alike: the triangle edges of the drawn level (wireframe), or
//! a colour per level (so a change of level is seen even where shading hides it). Pure data: the
//! edge list each level's line-list index buffer holds, and the tint each draw gets.
//!
//! A geomorphing draw shows neither level exactly, so its tint is the two levels' tints mixed by
//! the morph parameter `t`, as its shape is.

/// What is drawn over the shaded views.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Overlay {
    #[default]
    None,
    /// The edges of the drawn triangles, dark lines over the shading.
    Wireframe,
    /// Each level tinted with its own colour.
    Levels,
}

/// Distinct colours for levels 0, 1, 2, … (linear RGB), repeating after the last: blue, orange,
/// green, red, purple, yellow, cyan, pink — hues far apart, so neighbouring levels never look alike.
const LEVEL_COLORS: [[f32; 3]; 8] = [
    [0.10, 0.30, 0.90],
    [0.95, 0.40, 0.05],
    [0.10, 0.70, 0.15],
    [0.85, 0.08, 0.10],
    [0.50, 0.20, 0.80],
    [0.95, 0.85, 0.10],
    [0.05, 0.75, 0.80],
    [0.95, 0.45, 0.70],
];

/// How much of a surface's own colour the level tint replaces: enough to tell the levels apart,
/// little enough that lighting still shows the shape.
pub const TINT_STRENGTH: f32 = 0.7;

/// The tint of a draw of level `level` morphing towards `level + 1` by `morph_t` (`None`: no
/// morph): linear RGB and strength, all zero when the overlay is not [`Overlay::Levels`].
pub fn draw_tint(overlay: Overlay, level: usize, morph_t: Option<f32>) -> [f32; 4] {
    if overlay != Overlay::Levels {
        return [0.0; 4];
    }
    let fine = LEVEL_COLORS[level % LEVEL_COLORS.len()];
    let coarse = LEVEL_COLORS[(level + 1) % LEVEL_COLORS.len()];
    let t = morph_t.unwrap_or(0.0).clamp(0.0, 1.0);
    let mix = |c: usize| fine[c] * (1.0 - t) + coarse[c] * t;
    [mix(0), mix(1), mix(2), TINT_STRENGTH]
}

/// The edges of a triangle list as a line list: each undirected edge once, as `(low, high)` vertex
/// pairs in increasing order. A trailing partial triangle is ignored.
pub fn edge_indices(triangles: &[u32]) -> Vec<u32> {
    let mut edges: Vec<(u32, u32)> = triangles
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .filter(|(a, b)| a != b)
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges.into_iter().flat_map(|(a, b)| [a, b]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_quad_of_two_triangles_has_five_edges() {
        // 0-1-2 and 0-2-3 share the diagonal 0-2; the degenerate 1-1-3 adds only 1-3.
        let edges = edge_indices(&[0, 1, 2, 0, 2, 3, 1, 1, 3, 7]);
        assert_eq!(edges, [0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3]);
        assert!(edge_indices(&[]).is_empty());
    }

    #[test]
    fn level_tints_differ_and_geomorphs_mix_them() {
        assert_eq!(draw_tint(Overlay::None, 2, None), [0.0; 4]);
        assert_eq!(draw_tint(Overlay::Wireframe, 2, Some(0.5)), [0.0; 4]);
        for level in 0..LEVEL_COLORS.len() {
            assert_ne!(draw_tint(Overlay::Levels, level, None), draw_tint(Overlay::Levels, level + 1, None));
        }
        let fine = draw_tint(Overlay::Levels, 1, None);
        let coarse = draw_tint(Overlay::Levels, 2, None);
        assert_eq!(draw_tint(Overlay::Levels, 1, Some(0.0)), fine);
        assert_eq!(draw_tint(Overlay::Levels, 1, Some(1.0)), coarse);
        let half = draw_tint(Overlay::Levels, 1, Some(0.5));
        for c in 0..3 {
            assert!((half[c] - 0.5 * (fine[c] + coarse[c])).abs() < 1e-6);
        }
        assert_eq!(half[3], TINT_STRENGTH);
    }
}
