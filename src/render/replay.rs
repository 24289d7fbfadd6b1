//! The replay of the last transition: the live meter's pictures of every view across it (the
//! frame before it starts to the first frame after it ends), cropped to the region around its
//! largest change and kept for a film strip, with the frame numbers whose meter samples make each
//! method's per-frame difference curve.
//!
//! The region is the square a third of the meter picture's height (85 of 256 pixels) that holds
//! the most change in the transition's largest step: the pixels where a view differs from its
//! control (the same frame drawn with the view's previous plan, see [`super::meter`]), weighted by
//! how much (`|Δα| + |ΔRGB| / 765`), in the frame and view with the largest silhouette step. The strip
//! keeps at most [`MAX_FRAMES`] frames: when a transition runs longer, every other kept frame is
//! dropped and the stride doubles, so the kept frames stay evenly spread; the first frame after
//! the transition is always kept. Pure data, tested natively; `src/web` feeds it and hands the
//! replay to the page.

use super::schedule::Transition;

/// Frames a replay keeps at most (besides the frame before the transition).
pub const MAX_FRAMES: usize = 12;

/// The side of a replay's crop for a meter picture `height` tall: a third of it.
pub fn replay_side(height: u32) -> u32 {
    (height / 3).max(1)
}

/// One measured frame's pictures (RGBA8, the meter's size), one per view.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedFrame {
    pub frame: u64,
    /// Viewer seconds.
    pub time: f64,
    pub transition: Transition,
    pub views: Vec<Vec<u8>>,
}

/// The last transition's replay: `frames` cropped to `region`.
#[derive(Clone, Debug, PartialEq)]
pub struct Replay {
    /// `(from, to)` of the transition.
    pub levels: (usize, usize),
    /// `[x, y, width, height]` in the meter picture's pixels.
    pub region: [u32; 4],
    /// The frame before the transition, the kept frames and the first frame after it, each view
    /// cropped to `region` (RGBA8, rows top first).
    pub frames: Vec<RecordedFrame>,
    /// The first and last frame numbers the transition's curves span.
    pub span: (u64, u64),
}

/// Where a frame's step changed the picture most: the square of the replay's side holding the
/// most change, and how much change the whole picture holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Change {
    pub region: [u32; 4],
    pub weight: f32,
}

/// The change between two RGBA8 pictures `width` × `height` (see the module docs): the `side` ×
/// `side` square (clamped to the picture) whose pixels changed most, or `None` where the pictures
/// are the same.
pub fn change(a: &[u8], b: &[u8], width: u32, height: u32, side: u32) -> Option<Change> {
    let (w, h) = (width as usize, height as usize);
    // Summed-area table of the per-pixel change, one row and column of zeros in front.
    let mut sums = vec![0.0f64; (w + 1) * (h + 1)];
    for (i, (p, q)) in a.chunks_exact(4).zip(b.chunks_exact(4)).enumerate().take(w * h) {
        let coverage = f64::from(p[3].abs_diff(q[3])) / 255.0;
        let colour = (0..3).map(|c| f64::from(p[c].abs_diff(q[c]))).sum::<f64>() / 765.0;
        let (x, y) = (i % w, i / w);
        sums[(y + 1) * (w + 1) + x + 1] =
            coverage + colour + sums[y * (w + 1) + x + 1] + sums[(y + 1) * (w + 1) + x]
                - sums[y * (w + 1) + x];
    }
    let total = sums[(w + 1) * (h + 1) - 1];
    if total <= 0.0 {
        return None;
    }
    let (sw, sh) = (side.min(width) as usize, side.min(height) as usize);
    let at = |x: usize, y: usize| sums[y * (w + 1) + x];
    let mut best = (f64::MIN, 0, 0);
    for y in 0..=h - sh {
        for x in 0..=w - sw {
            let inside = at(x + sw, y + sh) - at(x, y + sh) - at(x + sw, y) + at(x, y);
            if inside > best.0 {
                best = (inside, x, y);
            }
        }
    }
    Some(Change { region: [best.1 as u32, best.2 as u32, sw as u32, sh as u32], weight: total as f32 })
}

/// `region` of an RGBA8 picture `width` wide.
pub fn crop(picture: &[u8], width: u32, [x, y, w, h]: [u32; 4]) -> Vec<u8> {
    let mut out = Vec::with_capacity(4 * (w * h) as usize);
    for row in y..y + h {
        let start = 4 * (row * width + x) as usize;
        out.extend_from_slice(&picture[start..start + 4 * w as usize]);
    }
    out
}

struct Recording {
    levels: (usize, usize),
    before: RecordedFrame,
    stride: u64,
    frames: Vec<RecordedFrame>,
    latest: Option<RecordedFrame>,
    peak: Option<(f32, [u32; 4])>,
}

/// Records transitions as the meter's frames arrive (see the module docs).
#[derive(Default)]
pub struct ReplayRecorder {
    previous: Option<RecordedFrame>,
    open: Option<Recording>,
    pub last: Option<Replay>,
    /// The meter picture's size.
    size: (u32, u32),
}

impl ReplayRecorder {
    /// The meter picture's size the frames were recorded at.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Adds a measured frame (frames in increasing order) of a `width` × `height` meter picture
    /// per view, with its largest step's silhouette and change (the view whose step was largest);
    /// returns whether a replay was completed with it.
    pub fn push(
        &mut self,
        frame: RecordedFrame,
        width: u32,
        height: u32,
        step: Option<(f32, Change)>,
    ) -> bool {
        if self.size != (width, height)
            || self.previous.as_ref().is_some_and(|p| p.views.len() != frame.views.len())
        {
            // Another picture size or view count: what was recorded no longer fits.
            self.open = None;
            self.previous = None;
            self.size = (width, height);
        }
        let shown = |t: &Transition| t.is_running().then_some((t.from, t.to));
        let now = shown(&frame.transition);
        let mut completed = false;
        if let Some(open) = &mut self.open {
            open.grow(&frame, step);
            if Some(open.levels) != now {
                let open = self.open.take().expect("checked");
                self.last = Some(open.finish(width, height));
                completed = true;
            }
        }
        if let (Some(levels), None) = (now, &self.open) {
            if let Some(before) = self.previous.take() {
                let mut open =
                    Recording { levels, before, stride: 1, frames: Vec::new(), latest: None, peak: None };
                open.grow(&frame, step);
                self.open = Some(open);
            }
        }
        self.previous = Some(frame);
        completed
    }
}

impl Recording {
    fn grow(&mut self, frame: &RecordedFrame, step: Option<(f32, Change)>) {
        if let Some((silhouette, change)) = step {
            if self.peak.is_none_or(|(s, _)| silhouette > s) {
                self.peak = Some((silhouette, change.region));
            }
        }
        let offset = frame.frame.saturating_sub(self.before.frame + 1);
        if offset % self.stride == 0 {
            self.frames.push(frame.clone());
            if self.frames.len() > MAX_FRAMES {
                // Every other kept frame goes; the rest are `2 × stride` apart.
                let mut k = 0;
                self.frames.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
            }
            self.latest = None;
        } else {
            self.latest = Some(frame.clone());
        }
    }

    fn finish(self, width: u32, height: u32) -> Replay {
        let side = replay_side(height).min(width);
        let centred = [(width - side) / 2, (height - side) / 2, side, side];
        let region = self.peak.map_or(centred, |(_, r)| r);
        let first = self.before.frame;
        let mut frames: Vec<RecordedFrame> =
            std::iter::once(self.before).chain(self.frames).chain(self.latest).collect();
        let last = frames.last().map_or(first, |f| f.frame);
        for f in &mut frames {
            f.views = f.views.iter().map(|v| crop(v, width, region)).collect();
        }
        Replay { levels: self.levels, region, frames, span: (first, last) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A 12 × 9 picture, background alpha 0, with a lit block at `(x, y)` 2 × 2.
    fn picture(block: Option<(usize, usize)>) -> Vec<u8> {
        let mut p = vec![0u8; 4 * 12 * 9];
        if let Some((x, y)) = block {
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let i = 4 * ((y + dy) * 12 + x + dx);
                p[i..i + 4].copy_from_slice(&[200, 100, 50, 255]);
            }
        }
        p
    }

    fn frame(n: u64, transition: Transition, block: Option<(usize, usize)>) -> RecordedFrame {
        RecordedFrame {
            frame: n,
            time: n as f64 / 10.0,
            transition,
            views: vec![picture(block), picture(None)],
        }
    }

    #[test]
    fn a_change_finds_the_square_that_changed_most() {
        let c = change(&picture(None), &picture(Some((8, 5))), 12, 9, 4).unwrap();
        assert_eq!(c.region, [6, 3, 4, 4], "the first square holding the whole block");
        assert!((c.weight - 4.0 * (1.0 + 350.0 / 765.0)).abs() < 1e-4);
        let two = change(&picture(Some((1, 1))), &picture(Some((8, 5))), 12, 9, 2).unwrap();
        assert!(two.region == [1, 1, 2, 2] || two.region == [8, 5, 2, 2], "{two:?}");
        assert_eq!(change(&picture(None), &picture(None), 12, 9, 4), None);
        assert_eq!(change(&picture(None), &picture(Some((8, 5))), 12, 9, 40).unwrap().region, [0, 0, 12, 9]);
        let cropped = crop(&picture(Some((8, 5))), 12, [8, 5, 2, 2]);
        assert!(cropped.chunks_exact(4).all(|p| p == [200, 100, 50, 255]));
    }

    #[test]
    fn a_long_transition_keeps_evenly_spread_frames_the_one_before_and_the_one_after() {
        let mut r = ReplayRecorder::default();
        let run = |t| Transition { from: 2, to: 3, t };
        assert!(!r.push(frame(1, Transition::at(2), None), 12, 9, None));
        // 40 frames of transition; the largest step at frame 5, where view 0's block appears.
        for n in 2..42 {
            let step =
                (n == 5).then(|| (0.3, change(&picture(None), &picture(Some((8, 5))), 12, 9, 3).unwrap()));
            let small = (n != 5).then_some((0.01, Change { region: [0, 0, 3, 3], weight: 0.1 }));
            assert!(!r.push(frame(n, run((n - 2) as f32 / 40.0), Some((8, 5))), 12, 9, step.or(small)));
        }
        assert!(r.push(frame(42, Transition::at(3), Some((8, 5))), 12, 9, None));
        let replay = r.last.clone().unwrap();
        assert_eq!(replay.levels, (2, 3));
        assert_eq!(replay.span, (1, 42));
        assert_eq!(replay.region, [7, 4, 3, 3], "the largest step's square, a third of the height");
        let numbers: Vec<u64> = replay.frames.iter().map(|f| f.frame).collect();
        assert_eq!(numbers.first(), Some(&1), "the frame before");
        assert_eq!(numbers.last(), Some(&42), "the frame after");
        assert!(numbers.len() <= MAX_FRAMES + 2 && numbers.len() >= MAX_FRAMES / 2, "{numbers:?}");
        let gaps: Vec<u64> = numbers.windows(2).map(|w| w[1] - w[0]).collect();
        // After the frame before: evenly spread up to the frame after.
        assert!(gaps[1..gaps.len() - 1].windows(2).all(|g| g[0] == g[1]), "evenly spread: {numbers:?}");
        assert!(replay.frames.iter().all(|f| f.views.len() == 2 && f.views[0].len() == 4 * 9));
        // Frames at rest afterwards start nothing.
        assert!(!r.push(frame(43, Transition::at(3), None), 12, 9, None));
    }
}
