//! The pop spike: how much a view's picture changes from one frame to the next while the camera
//! moves slowly through one change of level (issue 5's test 3; Giegl & Wimmer 2007 call the
//! visible jump "popping"). Popping changes the picture at once, so its largest frame-to-frame
//! change is large; a geomorph spreads the same change over the transition's frames.
//!
//! Pictures are RGBA8 rows, top row first, `width` pixels wide (what the renderer's readback
//! gives). The change of a view between two frames is the mean over the pixels of its rectangle
//! of `|ΔR| + |ΔG| + |ΔB|` (0..765 per pixel; alpha is ignored: the canvas is opaque).

use super::layout::Rect;

/// Mean `|ΔR| + |ΔG| + |ΔB|` per pixel between two RGBA8 pictures inside `rect`.
///
/// A rectangle that is empty, or not wholly inside both pictures (each `width` pixels wide, as
/// many rows as their length holds), changes by 0: there is nothing to compare.
pub fn mean_rgb_change(previous: &[u8], current: &[u8], width: u32, rect: Rect) -> f32 {
    let rows = |p: &[u8]| if width == 0 { 0 } else { p.len() / (4 * width as usize) };
    let inside = rect.width > 0
        && rect.height > 0
        && rect.x as u64 + rect.width as u64 <= width as u64
        && (rect.y + rect.height) as usize <= rows(previous).min(rows(current));
    if !inside {
        return 0.0;
    }
    let mut sum = 0u64;
    for y in rect.y..rect.y + rect.height {
        let start = 4 * (y as usize * width as usize + rect.x as usize);
        let end = start + 4 * rect.width as usize;
        for (a, b) in previous[start..end].chunks_exact(4).zip(current[start..end].chunks_exact(4)) {
            sum += (0..3).map(|c| u64::from(a[c].abs_diff(b[c]))).sum::<u64>();
        }
    }
    (sum as f64 / (rect.width as f64 * rect.height as f64)) as f32
}

/// Collects the frame-to-frame changes of the three views over a run of frames.
#[derive(Clone, Debug, Default)]
pub struct SpikeMeter {
    previous: Option<Vec<u8>>,
    /// Change of each view between consecutive frames, in frame order (one fewer than frames).
    pub series: [Vec<f32>; 3],
}

impl SpikeMeter {
    /// Adds the next frame (`rgba`, `width` pixels wide) with the views' rectangles.
    pub fn push(&mut self, rgba: Vec<u8>, width: u32, rects: [Rect; 3]) {
        if let Some(previous) = &self.previous {
            for (series, rect) in self.series.iter_mut().zip(rects) {
                series.push(mean_rgb_change(previous, &rgba, width, rect));
            }
        }
        self.previous = Some(rgba);
    }

    /// The largest change of each view (0 before two frames were pushed).
    pub fn largest(&self) -> [f32; 3] {
        self.series.each_ref().map(|s| s.iter().copied().fold(0.0, f32::max))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A `width` × `height` RGBA picture of one grey level.
    fn flat(width: u32, height: u32, grey: u8) -> Vec<u8> {
        [grey, grey, grey, 255].repeat((width * height) as usize)
    }

    fn set(p: &mut [u8], width: u32, x: u32, y: u32, rgba: [u8; 4]) {
        let i = 4 * (y * width + x) as usize;
        p[i..i + 4].copy_from_slice(&rgba);
    }

    #[test]
    fn change_counts_rgb_inside_the_rectangle_only() {
        let (w, h) = (4, 3);
        let a = flat(w, h, 100);
        let mut b = a.clone();
        // Inside the 2×2 rectangle at (1, 1): one pixel +10 red, −20 green, +5 blue, alpha ignored.
        set(&mut b, w, 2, 2, [110, 80, 105, 0]);
        // Outside it: a big change that must not count.
        set(&mut b, w, 0, 0, [255, 255, 255, 255]);
        let rect = Rect { x: 1, y: 1, width: 2, height: 2 };
        assert_eq!(mean_rgb_change(&a, &b, w, rect), 35.0 / 4.0);
        assert_eq!(mean_rgb_change(&b, &a, w, rect), 35.0 / 4.0, "symmetric");
        assert_eq!(mean_rgb_change(&a, &b, w, Rect { x: 0, y: 0, width: 1, height: 1 }), 465.0);
    }

    #[test]
    fn rectangles_outside_the_picture_change_by_nothing() {
        let a = flat(4, 3, 0);
        let b = flat(4, 3, 255);
        assert_eq!(mean_rgb_change(&a, &b, 4, Rect { x: 3, y: 0, width: 2, height: 1 }), 0.0);
        assert_eq!(mean_rgb_change(&a, &b, 4, Rect { x: 0, y: 2, width: 1, height: 2 }), 0.0);
        assert_eq!(mean_rgb_change(&a, &b, 4, Rect::default()), 0.0);
        assert_eq!(mean_rgb_change(&a, &b[..16], 4, Rect { x: 0, y: 1, width: 1, height: 1 }), 0.0);
        assert_eq!(mean_rgb_change(&a, &b, 0, Rect { x: 0, y: 0, width: 1, height: 1 }), 0.0);
    }

    #[test]
    fn meter_keeps_each_views_series_and_largest_change() {
        let (w, h) = (3, 1);
        let rects = [0, 1, 2].map(|x| Rect { x, y: 0, width: 1, height: 1 });
        let mut meter = SpikeMeter::default();
        let mut frame = flat(w, h, 0);
        meter.push(frame.clone(), w, rects);
        assert_eq!(meter.largest(), [0.0; 3]);
        // View 0 pops once by 90; view 1 ramps by 30 per frame; view 2 never changes.
        set(&mut frame, w, 0, 0, [30, 30, 30, 255]);
        set(&mut frame, w, 1, 0, [10, 10, 10, 255]);
        meter.push(frame.clone(), w, rects);
        set(&mut frame, w, 1, 0, [20, 20, 20, 255]);
        meter.push(frame.clone(), w, rects);
        assert_eq!(meter.series, [vec![90.0, 0.0], vec![30.0, 30.0], vec![0.0, 0.0]]);
        assert_eq!(meter.largest(), [90.0, 30.0, 0.0]);
    }
}
