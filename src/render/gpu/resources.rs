//! GPU copies of the character: vertex and index buffers of each level, uniform buffers, and one
//! bind group per material with its base-colour texture decoded by the browser.

use wasm_bindgen::JsCast;
use wgpu::util::DeviceExt;

use super::meshes::{LevelGpu, MaterialGpu};
use super::RenderError;
use crate::character::{AlphaMode, Character};
use crate::render::lod_source::LevelData;
use crate::render::mipmap::mip_level_count;
use crate::render::overlay::edge_indices;
use crate::render::uniforms::MaterialRaw;

/// Vertex and index buffers of a level, and its edges for the wireframe overlay; materials
/// outside the table use the default material.
pub(super) fn upload_level(device: &wgpu::Device, level: &LevelData, default_slot: usize) -> LevelGpu {
    let edges = edge_indices(&level.indices);
    let index_buffer = |label, indices: &[u32]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            // An empty buffer is valid but an empty init slice is not mappable everywhere.
            contents: if indices.is_empty() { &[0; 4] } else { bytemuck::cast_slice(indices) },
            usage: wgpu::BufferUsages::INDEX,
        })
    };
    LevelGpu {
        vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("level vertices"),
            contents: bytemuck::cast_slice(&level.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        }),
        indices: index_buffer("level indices", &level.indices),
        edges: index_buffer("level edges", &edges),
        edge_count: edges.len() as u32,
        ranges: level
            .ranges
            .iter()
            .map(|r| (r.first_index, r.index_count, r.material.unwrap_or(default_slot).min(default_slot)))
            .collect(),
    }
}

/// A `width` × `height` `rgba32float` texture of `texels` (row after row) for `textureLoad`
/// in vertex shaders (the crowd's pose palette, the morph deltas), and its view.
pub(super) fn float_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    width: u32,
    height: u32,
    texels: &[[f32; 4]],
) -> wgpu::TextureView {
    let texture = device.create_texture_with_data(
        queue,
        &float_texture_descriptor(label, width, height),
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(texels),
    );
    texture.create_view(&Default::default())
}

/// An `rgba32float` 2D texture of `width × height` texels, sampled with `textureLoad` and written
/// by copies.
pub(super) fn float_texture_descriptor(label: &str, width: u32, height: u32) -> wgpu::TextureDescriptor<'_> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    }
}

pub(super) fn uniform_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// One bind group per material plus a last one for glTF's default material (white, opaque,
/// single-sided). Textures are decoded by the browser (`createImageBitmap`) and copied in.
pub(super) async fn upload_materials(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layout: &wgpu::BindGroupLayout,
    character: &Character,
) -> Result<Vec<MaterialGpu>, RenderError> {
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("base colour"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    });
    let white = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("white"),
            size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &[255; 4],
    );
    let mut out = Vec::new();
    let default = crate::character::Material {
        name: "default".into(),
        base_color_factor: glam::Vec4::ONE,
        base_color_texture: None,
        alpha_mode: AlphaMode::Opaque,
        double_sided: false,
    };
    for material in character.materials.iter().chain([&default]) {
        let decoded = match &material.base_color_texture {
            Some(image) => Some(
                decode_texture(device, queue, &image.bytes, &image.mime_type)
                    .await
                    .map_err(|reason| RenderError::Texture { material: material.name.clone(), reason })?,
            ),
            None => None,
        };
        let texture = decoded.clone().unwrap_or_else(|| white.clone());
        let raw = MaterialRaw {
            base_color_factor: material.base_color_factor.to_array(),
            alpha_cutoff: match material.alpha_mode {
                AlphaMode::Mask { cutoff } => cutoff,
                _ => 0.0,
            },
            double_sided: u32::from(material.double_sided),
            _pad: [0; 2],
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("material"),
            contents: bytemuck::bytes_of(&raw),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let view = texture.create_view(&Default::default());
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&material.name),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        });
        out.push(MaterialGpu { bind_group, double_sided: material.double_sided, texture: decoded });
    }
    Ok(out)
}

/// Decodes an encoded image with the browser, copies it into level 0 of an sRGB texture and fills
/// its mip levels.
async fn decode_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    bytes: &[u8],
    mime_type: &str,
) -> Result<wgpu::Texture, String> {
    let window = web_sys::window().ok_or("no window")?;
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(mime_type);
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)
        .map_err(|e| format!("{e:?}"))?;
    let bitmap_options = web_sys::ImageBitmapOptions::new();
    // The texture is sRGB and glTF's colours are not premultiplied: take the bytes as they are.
    bitmap_options.set_color_space_conversion(web_sys::ColorSpaceConversion::None);
    bitmap_options.set_premultiply_alpha(web_sys::PremultiplyAlpha::None);
    let promise = window
        .create_image_bitmap_with_blob_and_image_bitmap_options(&blob, &bitmap_options)
        .map_err(|e| format!("{e:?}"))?;
    let bitmap: web_sys::ImageBitmap = wasm_bindgen_futures::JsFuture::from(promise)
        .await
        .map_err(|e| js_sys::Error::from(e).message().as_string().unwrap_or_else(|| "decode failed".into()))?
        .dyn_into()
        .map_err(|_| "createImageBitmap returned something else")?;
    let size = wgpu::Extent3d {
        width: bitmap.width().max(1),
        height: bitmap.height().max(1),
        depth_or_array_layers: 1,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("base colour"),
        size,
        mip_level_count: mip_level_count(size.width, size.height),
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        // copy_external_image_to_texture needs RENDER_ATTACHMENT on WebGPU, and so does drawing
        // the mip levels; COPY_SRC lets the page's tests read the levels back.
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    queue.copy_external_image_to_texture(
        &wgpu::CopyExternalImageSourceInfo {
            source: wgpu::ExternalImageSource::ImageBitmap(bitmap),
            origin: wgpu::Origin2d::ZERO,
            flip_y: false,
        },
        wgpu::CopyExternalImageDestInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
            color_space: wgpu::PredefinedColorSpace::Srgb,
            premultiplied_alpha: false,
        },
        size,
    );
    super::mipmaps::generate_mipmaps(device, queue, &texture);
    Ok(texture)
}
