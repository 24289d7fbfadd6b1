//! The byte-level containers of glTF 2.0 (§4.4 GLB file format, §3.6 buffers, §3.9 images): GLB
//! header and chunks, buffer sources (GLB binary chunk, `data:` URIs, external URIs fetched
//! through the caller's resolver) and image bytes with their MIME type.
//!
//! Nothing here trusts a length field: every slice is checked against the bytes actually present.

use std::borrow::Cow;
use std::collections::HashMap;

use super::document::Root;
use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
use base64::Engine;

use super::ImportError;

/// GLB magic, the ASCII bytes `glTF` (§4.4.3.1).
pub(crate) const GLB_MAGIC: &[u8; 4] = b"glTF";
/// GLB header: magic, version, total length, all `u32` little endian.
const GLB_HEADER_LEN: usize = 12;
/// Chunk header: chunk length and chunk type, both `u32`.
const CHUNK_HEADER_LEN: usize = 8;
/// Chunk type `JSON` read as a little-endian `u32`.
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type `BIN\0` read as a little-endian `u32`.
const CHUNK_BIN: u32 = 0x004E_4942;

/// The two chunks of a GLB file, borrowed from its bytes.
pub(crate) struct Glb<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB file into its JSON chunk and optional BIN chunk, skipping unknown chunks
/// (§4.4.3.3 says readers ignore chunks they do not know).
pub(crate) fn split_glb(bytes: &[u8]) -> Result<Glb<'_>, ImportError> {
    let bad = |reason: String| ImportError::Glb(reason);
    if bytes.len() < GLB_HEADER_LEN || &bytes[..4] != GLB_MAGIC {
        return Err(bad(format!("the file is too short for a GLB header ({} bytes)", bytes.len())));
    }
    let version = read_u32(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(bad(format!("GLB version {version} is not supported (only glTF 2.0)")));
    }
    let declared = read_u32(bytes, 8).unwrap_or(0) as usize;
    if declared > bytes.len() {
        return Err(bad(format!(
            "the header says the file has {declared} bytes but only {} are present (truncated file?)",
            bytes.len()
        )));
    }
    if declared < GLB_HEADER_LEN + CHUNK_HEADER_LEN {
        return Err(bad(format!("the header's total length {declared} leaves no room for the JSON chunk")));
    }
    let bytes = &bytes[..declared];
    let mut at = GLB_HEADER_LEN;
    let mut json = None;
    let mut bin = None;
    let mut chunk_index = 0usize;
    while at + CHUNK_HEADER_LEN <= bytes.len() {
        let len = read_u32(bytes, at).unwrap_or(0) as usize;
        let kind = read_u32(bytes, at + 4).unwrap_or(0);
        let start = at + CHUNK_HEADER_LEN;
        let Some(data) = start.checked_add(len).and_then(|end| bytes.get(start..end)) else {
            return Err(bad(format!(
                "chunk {chunk_index} says it has {len} bytes but only {} remain (truncated file?)",
                bytes.len() - start
            )));
        };
        match (chunk_index, kind) {
            (0, CHUNK_JSON) => json = Some(data),
            (0, _) => return Err(bad("the first chunk is not the JSON chunk".into())),
            (1, CHUNK_BIN) => bin = Some(data),
            _ => {}
        }
        chunk_index += 1;
        // Chunks are padded to 4 bytes, but a sloppy writer may not pad the last one.
        at = start + len.next_multiple_of(4).min(bytes.len() - start);
    }
    let json = json.ok_or_else(|| bad("the file has no JSON chunk".into()))?;
    Ok(Glb { json, bin })
}

/// Decodes `%XX` escapes of a URI (RFC 3986); other bytes are kept.
///
/// # Errors
/// When the decoded bytes are not UTF-8.
pub(crate) fn percent_decode(uri: &str) -> Result<String, ImportError> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8(out)
        .map_err(|_| ImportError::BadUri { uri: uri.to_string(), reason: "not UTF-8".into() })
}

/// The payload and media type of a `data:` URI, or `None` when `uri` is not one.
///
/// # Errors
/// A `data:` URI without `;base64,` or with invalid base64.
fn decode_data_uri(uri: &str) -> Option<Result<(Vec<u8>, String), ImportError>> {
    let rest = uri.strip_prefix("data:")?;
    let bad = |reason: &str| {
        // Data URIs can be megabytes long: name only their start.
        let shown: String = uri.chars().take(40).collect();
        ImportError::BadUri { uri: format!("{shown}…"), reason: reason.into() }
    };
    let Some((header, payload)) = rest.split_once(',') else {
        return Some(Err(bad("data URI has no ',' before its payload")));
    };
    let Some(media_type) = header.strip_suffix(";base64") else {
        return Some(Err(bad("only base64 data URIs are supported")));
    };
    // Some writers omit the `=` padding; the payload is still unambiguous.
    let engine = GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
    );
    Some(
        engine
            .decode(payload)
            .map(|b| (b, media_type.to_string()))
            .map_err(|e| bad(&format!("bad base64: {e}"))),
    )
}

/// Bytes named by a URI: decoded `data:` URIs, or the resolver's answer for anything else.
fn fetch_uri(
    uri: &str,
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<(Vec<u8>, Option<String>), ImportError> {
    if let Some(decoded) = decode_data_uri(uri) {
        let (bytes, media_type) = decoded?;
        return Ok((bytes, Some(media_type).filter(|m| !m.is_empty())));
    }
    let path = percent_decode(uri)?;
    match resolve(&path) {
        Some(bytes) => Ok((bytes, None)),
        None => Err(ImportError::MissingResource(path)),
    }
}

/// The bytes of every buffer of `root`, each cut to its declared `byteLength`.
///
/// Buffer 0 without a URI is the GLB binary chunk (§4.4.3.4).
///
/// # Errors
/// A missing or undecodable source, or one shorter than its `byteLength`.
pub(crate) fn load_buffers<'a>(
    root: &Root,
    bin: Option<&'a [u8]>,
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<Buffers<'a>, ImportError> {
    let mut buffers = Vec::with_capacity(root.buffers.len());
    for (index, buffer) in root.buffers.iter().enumerate() {
        let data: Cow<'a, [u8]> = match (&buffer.uri, bin) {
            (None, Some(bin)) if index == 0 => Cow::Borrowed(bin),
            // Where meshopt-compressed views decode to: nothing to load, even when it names a
            // file (gltfpack -cf writes the uncompressed data beside the .glb as a fallback for
            // loaders without the extension; a user who drops the .glb alone has no such file).
            _ if super::meshopt::is_placeholder(root, index) => {
                buffers.push(Cow::Borrowed(&[][..]));
                continue;
            }
            (Some(uri), _) => Cow::Owned(fetch_uri(uri, resolve)?.0),
            (None, _) => return Err(ImportError::MissingBinChunk(index)),
        };
        let declared = buffer.byte_length;
        if (data.len() as u64) < declared {
            return Err(ImportError::ShortBuffer { buffer: index, declared, actual: data.len() });
        }
        // `declared <= data.len()`, so it fits a usize.
        buffers.push(match data {
            Cow::Borrowed(b) => Cow::Borrowed(&b[..declared as usize]),
            Cow::Owned(mut b) => {
                b.truncate(declared as usize);
                Cow::Owned(b)
            }
        });
    }
    let sources: Vec<&[u8]> = buffers.iter().map(|b| &b[..]).collect();
    let decoded = super::meshopt::decode_views(root, &sources)?;
    Ok(Buffers { buffers, decoded, draco: DecodedAccessors::new() })
}

/// The bytes of accessors decoded from a compressed stream, by accessor index: each accessor's
/// elements tightly packed in its declared type.
pub(crate) type DecodedAccessors = HashMap<usize, Vec<u8>>;

/// Every buffer's bytes, and the decoded bytes of the buffer views stored compressed
/// (`EXT_meshopt_compression`, see `meshopt`), which replace their views' buffer ranges.
pub(crate) struct Buffers<'a> {
    buffers: Vec<Cow<'a, [u8]>>,
    decoded: Vec<Option<Vec<u8>>>,
    /// The accessors of Draco-compressed primitives, decoded (see `draco`; empty until
    /// `set_draco`).
    draco: DecodedAccessors,
}

impl Buffers<'_> {
    /// The bytes the file's buffers hold, all together (each cut to its declared length).
    pub(crate) fn file_bytes(&self) -> usize {
        self.buffers.iter().map(|b| b.len()).sum()
    }

    /// Takes the accessors that Draco-compressed primitives decoded to (see `draco`).
    pub(crate) fn set_draco(&mut self, draco: DecodedAccessors) {
        self.draco = draco;
    }

    /// The decoded bytes of accessor `accessor` when a Draco-compressed primitive defines it:
    /// its elements tightly packed in its declared type.
    pub(crate) fn draco_accessor(&self, accessor: usize) -> Option<&[u8]> {
        self.draco.get(&accessor).map(Vec::as_slice)
    }
}

/// The bytes of buffer view `view`, checked against its buffer (or decoded, when compressed).
pub(crate) fn view_bytes<'b>(root: &Root, data: &'b Buffers, view: usize) -> Result<&'b [u8], ImportError> {
    let v = root
        .buffer_views
        .get(view)
        .ok_or(ImportError::Invalid(format!("buffer view {view} does not exist")))?;
    if let Some(Some(decoded)) = data.decoded.get(view) {
        return Ok(decoded);
    }
    let buffer_index = v.buffer;
    let buffer = data
        .buffers
        .get(buffer_index)
        .ok_or(ImportError::Invalid(format!("buffer view {view} names missing buffer {buffer_index}")))?;
    let offset = v.byte_offset;
    let end = offset.checked_add(v.byte_length);
    match end.filter(|&e| e <= buffer.len() as u64) {
        Some(end) => Ok(&buffer[offset as usize..end as usize]),
        None => Err(ImportError::Invalid(format!(
            "buffer view {view} spans bytes {offset}..{} but buffer {buffer_index} has {} bytes",
            offset as u128 + v.byte_length as u128,
            buffer.len()
        ))),
    }
}

/// MIME type from an image's magic bytes, for images whose file gives none.
fn sniff_mime(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        Some("image/webp")
    } else {
        None
    }
}

/// The encoded bytes and MIME type of image `index`, or `Ok(None)` with a reason when the image is
/// in a format we cannot name.
pub(crate) fn load_image(
    root: &Root,
    buffers: &Buffers,
    index: usize,
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<Result<(Vec<u8>, String), String>, ImportError> {
    let image =
        root.images.get(index).ok_or(ImportError::Invalid(format!("image {index} does not exist")))?;
    let (bytes, uri_mime) = match (&image.buffer_view, &image.uri) {
        (Some(view), _) => (view_bytes(root, buffers, *view)?.to_vec(), None),
        (None, Some(uri)) => fetch_uri(uri, resolve)?,
        (None, None) => return Ok(Err(format!("image {index} has neither a buffer view nor a URI"))),
    };
    let declared = image.mime_type.clone().or(uri_mime);
    let mime = declared.filter(|m| m.starts_with("image/")).or_else(|| sniff_mime(&bytes).map(String::from));
    Ok(match mime {
        Some(mime) => Ok((bytes, mime)),
        None => Err(format!("image {index} is in an unknown format")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_escapes_decode() {
        assert_eq!(percent_decode("my%20model%2Fa.bin").unwrap(), "my model/a.bin");
        assert_eq!(percent_decode("100%").unwrap(), "100%");
        assert_eq!(percent_decode("%4").unwrap(), "%4");
    }

    #[test]
    fn data_uris_decode_with_or_without_padding() {
        let (bytes, mime) = decode_data_uri("data:application/octet-stream;base64,AAEC").unwrap().unwrap();
        assert_eq!((bytes, mime.as_str()), (vec![0, 1, 2], "application/octet-stream"));
        let (bytes, _) = decode_data_uri("data:;base64,AAE").unwrap().unwrap();
        assert_eq!(bytes, vec![0, 1]);
        assert!(decode_data_uri("data:text/plain,hello").unwrap().is_err());
        assert!(decode_data_uri("model.bin").is_none());
    }

    #[test]
    fn glb_chunks_split_and_truncation_is_reported() {
        let mut glb = Vec::new();
        glb.extend_from_slice(b"glTF");
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&36u32.to_le_bytes());
        glb.extend_from_slice(&4u32.to_le_bytes());
        glb.extend_from_slice(b"JSON{}  ");
        glb.extend_from_slice(&4u32.to_le_bytes());
        glb.extend_from_slice(b"BIN\0");
        glb.extend_from_slice(&[1, 2, 3, 4]);
        let split = split_glb(&glb).unwrap();
        assert_eq!((split.json, split.bin), (&b"{}  "[..], Some(&[1u8, 2, 3, 4][..])));
        let err = split_glb(&glb[..30]).err().unwrap().to_string();
        assert!(err.contains("truncated"), "{err}");
    }

    #[test]
    fn image_formats_are_sniffed() {
        assert_eq!(sniff_mime(b"\x89PNG\r\n\x1a\n...."), Some("image/png"));
        assert_eq!(sniff_mime(&[0xFF, 0xD8, 0xFF, 0xE0]), Some("image/jpeg"));
        assert_eq!(sniff_mime(b"GIF89a"), None);
    }
}
