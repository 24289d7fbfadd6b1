//! The live meter's GPU side (see [`crate::render::meter`]): each measured frame draws the
//! full-detail reference, every view's plan and every view's control (its plan of the previous
//! measured frame), at the same pose and camera, into small targets cleared to alpha 0, copies them into a mappable buffer and maps it; a later frame reads the
//! pictures once the map has resolved. Nothing waits: a frame whose buffers are all in flight is
//! not measured.

use std::cell::Cell;
use std::rc::Rc;

use super::{flip, frame_targets, FrameInput, Renderer};
use crate::render::flip::{unpack_error, DEFAULT_PPD};
use crate::render::meter::flip_pairs;
use crate::render::overlay::Overlay;
use crate::render::plan::{plan_view, Method, ViewPlan};
use crate::render::schedule::Transition;

/// Height of the meter's pictures, pixels (the width follows the view's aspect). At 128 px the
/// built-in character's last switch changes 9 pixels of area and a geomorph's sub-pixel edge
/// noise reaches a quarter of that in one frame (measured); at 256 px, a twelfth.
pub const METER_HEIGHT: u32 = 256;
/// Readbacks in flight at once: a map resolves a frame or two after its submit.
const IN_FLIGHT: usize = 3;
/// Pictures a frame draws at most: the reference, three views and their three controls.
pub(super) const PICTURES: usize = 7;
/// FLIP error maps a frame computes at most: each view against the reference and its control.
const ERROR_SLOTS: usize = 6;

/// What one meter picture draws: a view's plan, or a crowd view's instanced draws.
enum Picture<'a> {
    Plan(&'a ViewPlan),
    Crowd(&'a [crate::render::crowd::InstancedDraw]),
}

impl Picture<'_> {
    /// Whether two pictures draw the same pixels: equal plans, or the same crowd records (crowd
    /// views with one method hold equal records at different places, so they are drawn apart).
    fn same_pixels(&self, other: &Picture) -> bool {
        match (self, other) {
            (Picture::Plan(a), Picture::Plan(b)) => a.draws == b.draws,
            (Picture::Crowd(a), Picture::Crowd(b)) => a == b,
            _ => false,
        }
    }
}

/// The index of `picture` among `plans`, added if no picture there draws the same pixels.
fn place<'p>(plans: &mut Vec<Picture<'p>>, picture: Picture<'p>) -> usize {
    plans.iter().position(|p| p.same_pixels(&picture)).unwrap_or_else(|| {
        plans.push(picture);
        plans.len() - 1
    })
}

/// The pictures of one measured frame, RGBA8 or BGRA8 (the channel order does not matter to the
/// difference), rows top first: `pictures[0]` is the reference, `pictures[view_picture[i]]` view
/// `i`'s and `pictures[control_picture[i]]` its control's (equal plans share a picture: views
/// with the same plan, views at rest on level 0, a view whose plan held and its control; they are
/// the same pixels, as the fairness test checks).
pub struct MeterFrame {
    pub tag: u64,
    pub width: u32,
    pub height: u32,
    pub pictures: Vec<Vec<u8>>,
    pub view_picture: Vec<usize>,
    pub control_picture: Vec<usize>,
    /// Mean LDR-FLIP error of each compared pair of pictures `(reference, test)` (see
    /// [`crate::render::meter::flip_pairs`]), and the pixels per degree it was computed at; empty
    /// where the GPU has no FLIP.
    pub flip: Vec<((usize, usize), f32)>,
    pub flip_ppd: Option<f32>,
}

/// A measured frame's pictures on their way back: the buffer they were copied into, and what
/// they are.
pub(super) struct Readback {
    buffer: wgpu::Buffer,
    /// `None` while mapping, then whether it mapped.
    mapped: Rc<Cell<Option<bool>>>,
    tag: u64,
    pictures: usize,
    view_picture: Vec<usize>,
    control_picture: Vec<usize>,
    flip_pairs: Vec<(usize, usize)>,
    flip_ppd: Option<f32>,
}

pub(super) struct MeterGpu {
    width: u32,
    height: u32,
    textures: Vec<wgpu::Texture>,
    views: Vec<wgpu::TextureView>,
    /// Each picture's horizontal FLIP filters and the error maps (where the GPU has FLIP).
    filtered: Vec<flip::Filtered>,
    errors: Vec<wgpu::Texture>,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    free: Vec<wgpu::Buffer>,
    in_flight: Vec<Readback>,
}

/// Bytes per padded row of a texture-to-buffer copy (WebGPU pads rows to 256).
fn padded_row(width: u32) -> u32 {
    (4 * width).div_ceil(256) * 256
}

impl MeterGpu {
    /// Picture `i` of the frame being recorded (0: the reference).
    pub(super) fn picture(&self, i: usize) -> Option<&wgpu::TextureView> {
        self.views.get(i)
    }

    fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        sample_count: u32,
        aspect: f32,
        flip: bool,
    ) -> Self {
        let height = METER_HEIGHT;
        let width = ((METER_HEIGHT as f32 * aspect).round() as u32).clamp(16, 4 * METER_HEIGHT);
        let textures: Vec<_> = (0..PICTURES)
            .map(|_| {
                device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("meter picture"),
                    size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    // Sampled by the difference overlay.
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::COPY_SRC
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
            })
            .collect();
        let views = textures.iter().map(|t| t.create_view(&Default::default())).collect();
        let (depth, msaa) = frame_targets::targets(device, format, sample_count, width, height);
        let (filtered, errors) = match flip {
            true => (
                (0..PICTURES).map(|_| flip::Filtered::new(device, width, height)).collect(),
                (0..ERROR_SLOTS).map(|_| flip::target(device, flip::ERROR_FORMAT, width, height)).collect(),
            ),
            false => (Vec::new(), Vec::new()),
        };
        Self {
            width,
            height,
            textures,
            views,
            filtered,
            errors,
            msaa,
            depth,
            free: Vec::new(),
            in_flight: Vec::new(),
        }
    }
}

impl Renderer {
    /// Makes the meter's pictures fit `frame`'s views and, for a measured frame that computes
    /// FLIP, writes FLIP's kernels for its pixels per degree; returns a readback buffer for a
    /// measured frame unless every one is in flight (that frame is then not measured).
    pub(super) fn prepare_meter(&mut self, frame: &FrameInput) -> Option<wgpu::Buffer> {
        let aspect = frame.views[0].0.aspect();
        let fits = |m: &MeterGpu| {
            m.width == ((METER_HEIGHT as f32 * aspect).round() as u32).clamp(16, 4 * METER_HEIGHT)
        };
        let meter = match &mut self.meter {
            Some(meter) if fits(meter) => meter,
            slot => {
                let flip = self.flip.is_some();
                slot.insert(MeterGpu::new(
                    &self.device,
                    self.canvas.color_format,
                    self.canvas.sample_count,
                    aspect,
                    flip,
                ))
            }
        };
        frame.meter?;
        if meter.in_flight.len() >= IN_FLIGHT {
            return None;
        }
        if let Some(flip) = self.flip.as_mut().filter(|_| frame.flip) {
            // The meter's picture at the pixels per degree of the view seen at FLIP's standard.
            let view_height = frame.views[0].0.height.max(1) as f32;
            flip.set_kernels(
                &self.queue,
                DEFAULT_PPD * METER_HEIGHT as f32 / view_height,
                !self.canvas.color_format.is_srgb(),
            );
        }
        let picture_bytes = u64::from(padded_row(meter.width)) * u64::from(meter.height);
        Some(meter.free.pop().unwrap_or_else(|| {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("meter readback"),
                size: (PICTURES + ERROR_SLOTS) as u64 * picture_bytes,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            })
        }))
    }

    /// Records the meter's draws of `frame` into `encoder` (its targets sized by
    /// [`Renderer::prepare_meter`]) and returns the picture of each view (an index; 0 is the
    /// reference), and the readback to start after the submit. With a `buffer` (a measured
    /// frame), the pictures and the views' controls (`frame.controls`) are also copied into it
    /// for reading back; without, the views are drawn for the difference overlay only.
    pub(super) fn encode_meter(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameInput,
        buffer: Option<wgpu::Buffer>,
        slot: &mut u64,
    ) -> (Vec<usize>, Option<Readback>) {
        let Some(meter) = self.meter.as_ref() else { return (Vec::new(), None) };
        let views = frame.views.iter().filter(|(rect, _)| rect.width > 0 && rect.height > 0).count();
        let tag = frame.meter.filter(|_| buffer.is_some());
        let reference_plan = plan_view(Method::Popping, &Transition::at(0));
        let reference = match frame.crowd {
            Some(crowd) => Picture::Crowd(&crowd.reference),
            None => Picture::Plan(&reference_plan),
        };
        // Each distinct picture once: at rest every view draws the same, often level 0 itself.
        let mut plans: Vec<Picture> = vec![reference];
        let view_picture: Vec<usize> = frame.views[..views]
            .iter()
            .enumerate()
            .map(|(i, (_, plan))| match frame.crowd {
                Some(crowd) => {
                    place(&mut plans, Picture::Crowd(crowd.views.get(i).map_or(&[], Vec::as_slice)))
                }
                None => place(&mut plans, Picture::Plan(plan)),
            })
            .collect();
        // Controls only for the single character's measured frames (a crowd's many transitions
        // are measured by their changes, see `TransitionMeter::changes`).
        let control_picture: Vec<usize> = match (frame.controls, frame.crowd, tag) {
            (Some(controls), None, Some(_)) => {
                controls[..views].iter().map(|plan| place(&mut plans, Picture::Plan(plan))).collect()
            }
            _ => view_picture.clone(),
        };
        let clear = wgpu::Color { a: 0.0, ..frame_targets::background_for(self.canvas.color_format) };
        for (i, picture) in plans.iter().enumerate() {
            let (color, resolve) = match &meter.msaa {
                Some(msaa) => (msaa, Some(&meter.views[i])),
                None => (&meter.views[i], None),
            };
            let mut pass = frame_targets::begin_pass(encoder, color, resolve, Some(&meter.depth), clear);
            match picture {
                Picture::Plan(plan) => self.draw_view(&mut pass, plan, Overlay::None, [0.0; 2], slot),
                Picture::Crowd(draws) => self.draw_crowd_view(&mut pass, draws, [0.0; 2], slot),
            }
        }
        let (Some(tag), Some(buffer)) = (tag, buffer) else { return (view_picture, None) };
        // FLIP of each view against the reference and its control, at the pixels per degree of
        // the meter's picture when the view is seen at FLIP's standard 67 ppd.
        let mut flip_pairs = match frame.crowd {
            None => flip_pairs(&view_picture, &control_picture),
            Some(_) => Vec::new(),
        };
        let mut flip_ppd = None;
        match &self.flip {
            Some(flip) if frame.flip && !flip_pairs.is_empty() && !meter.errors.is_empty() => {
                flip_ppd = flip.ppd();
                let mut filtered = vec![false; plans.len()];
                for &(a, b) in &flip_pairs {
                    for p in [a, b] {
                        if !std::mem::replace(&mut filtered[p], true) {
                            flip.encode_horizontal(
                                &self.device,
                                encoder,
                                &meter.views[p],
                                &meter.filtered[p],
                            );
                        }
                    }
                }
                for (slot, &(a, b)) in flip_pairs.iter().enumerate() {
                    let out = meter.errors[slot].create_view(&Default::default());
                    flip.encode_error(&self.device, encoder, &meter.filtered[a], &meter.filtered[b], &out);
                }
            }
            _ => flip_pairs.clear(),
        }
        let row = padded_row(meter.width);
        let picture_bytes = u64::from(row) * u64::from(meter.height);
        let copies = meter.textures.iter().take(plans.len()).enumerate();
        let maps = meter.errors.iter().take(flip_pairs.len()).enumerate().map(|(s, t)| (PICTURES + s, t));
        for (i, texture) in copies.chain(maps) {
            encoder.copy_texture_to_buffer(
                texture.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: i as u64 * picture_bytes,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(meter.height),
                    },
                },
                texture.size(),
            );
        }
        let readback = Readback {
            buffer,
            mapped: Rc::default(),
            tag,
            pictures: plans.len(),
            view_picture: view_picture.clone(),
            control_picture,
            flip_pairs,
            flip_ppd,
        };
        (view_picture, Some(readback))
    }

    /// Starts mapping a measured frame's readback (after its submit); [`Renderer::take_meter_frames`]
    /// collects it once mapped.
    pub(super) fn start_readback(&mut self, readback: Readback) {
        let done = Rc::clone(&readback.mapped);
        readback.buffer.map_async(wgpu::MapMode::Read, .., move |r| done.set(Some(r.is_ok())));
        // A readback comes from the meter's pictures, so the meter is there.
        if let Some(meter) = self.meter.as_mut() {
            meter.in_flight.push(readback);
        }
    }

    /// The measured frames whose readbacks have arrived, oldest first. WebGL2 resolves maps only
    /// when polled, so this polls first; it never waits.
    pub fn take_meter_frames(&mut self) -> Vec<MeterFrame> {
        let _ = self.device.poll(wgpu::PollType::Poll);
        let Some(meter) = self.meter.as_mut() else { return Vec::new() };
        let (width, height) = (meter.width, meter.height);
        let row = padded_row(width) as usize;
        let mut out = Vec::new();
        while meter.in_flight.first().is_some_and(|r| r.mapped.get().is_some()) {
            let readback = meter.in_flight.remove(0);
            if readback.mapped.get() == Some(true) {
                if let Ok(mapped) = readback.buffer.get_mapped_range(..) {
                    let texels = |image: &[u8]| -> Vec<u8> {
                        image
                            .chunks_exact(row)
                            .flat_map(|line| &line[..4 * width as usize])
                            .copied()
                            .collect()
                    };
                    let image =
                        |i: usize| &mapped[i * row * height as usize..(i + 1) * row * height as usize];
                    let flip = readback
                        .flip_pairs
                        .iter()
                        .enumerate()
                        .map(|(slot, &pair)| {
                            let map = texels(image(PICTURES + slot));
                            let sum: f64 =
                                map.chunks_exact(4).map(|t| f64::from(unpack_error(t[0], t[1]))).sum();
                            (pair, (sum / (map.len() / 4).max(1) as f64) as f32)
                        })
                        .collect();
                    let pictures = (0..readback.pictures).map(|i| texels(image(i))).collect();
                    let (view_picture, control_picture) =
                        (readback.view_picture.clone(), readback.control_picture.clone());
                    out.push(MeterFrame {
                        tag: readback.tag,
                        width,
                        height,
                        pictures,
                        view_picture,
                        control_picture,
                        flip,
                        flip_ppd: readback.flip_ppd,
                    });
                }
                readback.buffer.unmap();
            }
            meter.free.push(readback.buffer);
        }
        out
    }
}
