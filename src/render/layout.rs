//! Where the views (one to three) go on the canvas: side by side on wide canvases, stacked on
//! narrow ones.
//!
//! Units are framebuffer pixels (CSS pixels × devicePixelRatio), origin top-left. Every view gets
//! exactly the same size and integer origin, so the same scene drawn in two views is the same
//! picture pixel for pixel (what the fairness test checks).

/// A rectangle in framebuffer pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Rect {
    /// Width over height; 1 for an empty rectangle so projections stay finite.
    pub fn aspect(&self) -> f32 {
        if self.width == 0 || self.height == 0 {
            1.0
        } else {
            self.width as f32 / self.height as f32
        }
    }
}

/// The view rectangles and whether they are stacked. Views past the layout's count are empty.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub views: [Rect; MAX_VIEWS],
    pub stacked: bool,
}

/// Most views one canvas shows: popping, alpha-blending, geomorphing.
pub const MAX_VIEWS: usize = 3;

/// Gap between views in framebuffer pixels: enough to see where one view ends.
pub const GAP: u32 = 4;

/// Splits a `width` × `height` canvas into `count` equal views separated by [`GAP`] (`count` is
/// clamped to 1..=[`MAX_VIEWS`]; the rectangles past it are empty).
///
/// Canvases taller than wide stack the views top to bottom, others put them side by side. A canvas
/// too small for its views gives empty rectangles (nothing is drawn) rather than panicking.
pub fn layout(width: u32, height: u32, count: usize) -> Layout {
    let count = count.clamp(1, MAX_VIEWS) as u32;
    let stacked = height > width;
    let along = if stacked { height } else { width };
    let size = along.saturating_sub((count - 1) * GAP) / count;
    let views = [0u32, 1, 2].map(|i| {
        let offset = i * (size + GAP);
        if i >= count {
            Rect::default()
        } else if stacked {
            Rect { x: 0, y: offset, width, height: size }
        } else {
            Rect { x: offset, y: 0, width: size, height }
        }
    });
    Layout { views, stacked }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn wide_canvas_puts_views_side_by_side() {
        let l = layout(1208, 400, 3);
        assert!(!l.stacked);
        assert_eq!(l.views[0], Rect { x: 0, y: 0, width: 400, height: 400 });
        assert_eq!(l.views[1], Rect { x: 404, y: 0, width: 400, height: 400 });
        assert_eq!(l.views[2], Rect { x: 808, y: 0, width: 400, height: 400 });
    }

    #[test]
    fn narrow_canvas_stacks_equal_views() {
        let l = layout(300, 907, 3);
        assert!(l.stacked);
        assert_eq!(l.views.map(|r| r.y), [0, 303, 606]);
        assert!(l.views.iter().all(|r| r.width == 300 && r.height == 299));
    }

    #[test]
    fn two_views_share_the_width_and_the_third_is_empty() {
        let l = layout(1004, 500, 2);
        assert_eq!(l.views[0], Rect { x: 0, y: 0, width: 500, height: 500 });
        assert_eq!(l.views[1], Rect { x: 504, y: 0, width: 500, height: 500 });
        assert_eq!(l.views[2], Rect::default());
        assert_eq!(layout(640, 320, 1).views[0], Rect { x: 0, y: 0, width: 640, height: 320 });
        assert_eq!(layout(640, 320, 0), layout(640, 320, 1));
    }

    #[test]
    fn tiny_canvas_gives_empty_views() {
        let l = layout(5, 2, 3);
        assert!(l.views.iter().all(|r| r.width == 0));
        assert_eq!(l.views[0].aspect(), 1.0);
    }
}
