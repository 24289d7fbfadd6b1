//! Materials (glTF 2.0 §3.9): the base colour factor and texture, alpha mode and sidedness of
//! every material, in file order so [`crate::mesh::PrimitiveRange::material`] indexes them.
//!
//! Images stay encoded (PNG, JPEG, …) for the browser to decode. An image in a format we cannot
//! name is dropped with a warning and the material keeps its factor.

use super::document::AlphaMode as JsonAlphaMode;
use glam::Vec4;

use super::accessor::Source;
use super::container::load_image;
use super::{ImportError, TEXTURE_FORMAT_EXTENSIONS};
use crate::character::{AlphaMode, Material, TextureImage};

/// Every material of the file.
///
/// # Errors
/// Non-finite factors, a missing texture or image, an image URI the resolver cannot serve.
pub(crate) fn read_materials(
    src: Source,
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Material>, ImportError> {
    let mut materials = Vec::with_capacity(src.root.materials.len());
    for (m, json) in src.root.materials.iter().enumerate() {
        let name = json.name.clone().unwrap_or_else(|| format!("material {m}"));
        let invalid = |problem: &str| ImportError::Invalid(format!("material {m} ('{name}') {problem}"));
        let base_color_factor = Vec4::from_array(json.base_color_factor);
        if !base_color_factor.is_finite() {
            return Err(invalid("has a non-finite base colour factor"));
        }
        let base_color_texture = match &json.base_color_texture {
            None => None,
            Some(info) => {
                let texture =
                    src.root.textures.get(info.index).ok_or_else(|| invalid("names a missing texture"))?;
                if let Some(source) = texture.source {
                    match load_image(src.root, src.buffers, source, resolve)? {
                        Ok((bytes, mime_type)) => Some(TextureImage { bytes, mime_type }),
                        Err(reason) => {
                            warnings.push(format!("material '{name}': {reason}; its texture is dropped"));
                            None
                        }
                    }
                } else {
                    // No `source`: the image is only in an extension.
                    let formats: Vec<&str> = (src.root.extensions_used.iter())
                        .map(String::as_str)
                        .filter(|e| TEXTURE_FORMAT_EXTENSIONS.contains(e))
                        .collect();
                    warnings.push(match formats.is_empty() {
                        true => format!(
                            "material '{name}': its texture has no image; the material keeps its colour"
                        ),
                        false => format!(
                            "material '{name}': its texture is only in {}, which the viewer does not decode; \
                             the material keeps its colour",
                            formats.join(" / ")
                        ),
                    });
                    None
                }
            }
        };
        let alpha_mode = match json.alpha_mode {
            JsonAlphaMode::Opaque => AlphaMode::Opaque,
            JsonAlphaMode::Blend => AlphaMode::Blend,
            JsonAlphaMode::Mask => {
                // §3.9.5: the default cutoff is 0.5.
                let cutoff = json.alpha_cutoff.unwrap_or(0.5);
                if !cutoff.is_finite() {
                    return Err(invalid("has a non-finite alpha cutoff"));
                }
                AlphaMode::Mask { cutoff }
            }
        };
        materials.push(Material {
            name,
            base_color_factor,
            base_color_texture,
            alpha_mode,
            double_sided: json.double_sided,
        });
    }
    Ok(materials)
}
