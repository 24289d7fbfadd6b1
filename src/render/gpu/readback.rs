//! Reading back: an offscreen draw at the canvas size, or one mip level of a texture
//! ([`read_texture_level`]), copied into a mappable buffer; and the fence the frame timer waits
//! on. WebGL2 cannot block on the GPU, so maps are polled with a
//! deadline, yielding to the browser's event loop between tries.

use super::{FrameInput, Pixels, RenderError, Renderer};

impl Renderer {
    /// Draws a frame offscreen at the canvas size and reads it back.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU cannot map the copy.
    pub async fn read_pixels(&mut self, frame: &FrameInput<'_>) -> Result<Pixels, RenderError> {
        let (width, height) = self.canvas.size();
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("readback target"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.canvas.color_format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        // A frame read back is never measured: no readback buffer for the meter.
        let _ = self.prepare(frame);
        let (draw, _) = self.encode(frame, &texture, None);
        let mut rgba = read_texture_level(&self.device, &self.queue, &texture, 0, Some(draw)).await?;
        if matches!(
            self.canvas.color_format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        ) {
            for texel in rgba.chunks_exact_mut(4) {
                texel.swap(0, 2);
            }
        }
        Ok(Pixels { width, height, rgba })
    }

    /// Resolves once the GPU has finished everything submitted so far (for frame timing).
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU cannot map the fence buffer.
    pub async fn finish(&self) -> Result<(), RenderError> {
        let fence = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fence"),
            size: 4,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.uniforms.draws, 0, &fence, 0, 4);
        self.queue.submit([encoder.finish()]);
        map_read(&self.device, &fence).await
    }
}

/// Reads back mip `level` of `texture` (4 bytes per texel), after the command buffer `before` if
/// any (submitted together with the copy): its rows tightly packed, top row first.
///
/// # Errors
/// [`RenderError::Readback`] when the GPU cannot map the copy.
pub(super) async fn read_texture_level(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    level: u32,
    before: Option<wgpu::CommandBuffer>,
) -> Result<Vec<u8>, RenderError> {
    let size = texture.size().mip_level_size(level, wgpu::TextureDimension::D2);
    // Rows of a texture-to-buffer copy are padded to 256 bytes (WebGPU's rule).
    let row = 4 * size.width as usize;
    let padded = row.div_ceil(256) * 256;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (padded * size.height as usize) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded as u32),
                rows_per_image: Some(size.height),
            },
        },
        size,
    );
    queue.submit(before.into_iter().chain([encoder.finish()]));
    map_read(device, &buffer).await?;
    let mapped = buffer.get_mapped_range(..).map_err(|e| RenderError::Readback(e.to_string()))?;
    let mut texels = Vec::with_capacity(row * size.height as usize);
    for line in mapped.chunks_exact(padded) {
        texels.extend_from_slice(&line[..row]);
    }
    drop(mapped);
    buffer.unmap();
    Ok(texels)
}

/// Maps `buffer` for reading and waits for it. WebGPU resolves the map from the browser's event
/// loop; the GL backend only when polled after its fence has signalled, which WebGL cannot block
/// on — so this polls, yielding to the event loop between tries, for at most [`MAP_TIMEOUT_MS`].
async fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<(), RenderError> {
    let result: std::rc::Rc<std::cell::Cell<Option<bool>>> = Default::default();
    let done = std::rc::Rc::clone(&result);
    buffer.map_async(wgpu::MapMode::Read, .., move |r| done.set(Some(r.is_ok())));
    let started = js_sys::Date::now();
    loop {
        let _ = device.poll(wgpu::PollType::Poll);
        match result.get() {
            Some(true) => return Ok(()),
            Some(false) => return Err(RenderError::Readback("the buffer could not be mapped".into())),
            None if js_sys::Date::now() - started > MAP_TIMEOUT_MS => {
                return Err(RenderError::Readback(format!(
                    "the GPU did not finish within {MAP_TIMEOUT_MS} ms"
                )));
            }
            None => yield_to_event_loop().await,
        }
    }
}

/// Longest wait for a readback: SwiftShader draws a large frame in well under a second.
const MAP_TIMEOUT_MS: f64 = 20_000.0;

/// Resolves on the next turn of the event loop (a zero-delay timeout).
async fn yield_to_event_loop() {
    let promise = js_sys::Promise::new(&mut |resolve, _reject| {
        let set_timeout =
            web_sys::window().map(|w| w.set_timeout_with_callback_and_timeout_and_arguments_0(&resolve, 0));
        if !matches!(set_timeout, Some(Ok(_))) {
            // No window (a worker): resolve at once; the loop's deadline still bounds the wait.
            let _ = resolve.call0(&wasm_bindgen::JsValue::NULL);
        }
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}
