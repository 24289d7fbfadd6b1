//! `EXT_meshopt_compression` and `KHR_meshopt_compression`: buffer views stored compressed by
//! meshoptimizer's codecs (gltfpack `-c`/`-cc`/`-cz`, gltf-transform `meshopt`), decoded here into
//! the plain bytes the accessors then read like any other.
//!
//! Follows the extension's specification (Khronos glTF repository, `EXT_meshopt_compression`,
//! appendices A and B): three bitstreams — attributes (mode 0: per-byte zigzag deltas between
//! consecutive elements, in blocks of up to 256 elements, groups of 16 with 0/2/4/8-bit deltas),
//! triangles (mode 1: one code byte per triangle against a FIFO of recent edges and vertices) and
//! indices (mode 2: LEB128 zigzag deltas against two baselines) — and three filters applied after
//! mode 0 (octahedral unit vectors, max-component quaternions, exponent/mantissa floats).
//! `KHR_meshopt_compression` (gltfpack `-cz`, `-ce khr`) adds version 1 of the attribute
//! bitstream (per-byte control modes with 1-bit deltas or literal bytes, and per-channel 16-bit
//! or rotated-XOR 32-bit deltas) and a YCoCg colour filter; everything else is shared.
//!
//! Every read is bounds-checked against the compressed bytes: a corrupt stream is an error naming
//! the buffer view, never a panic. A view's decoded size is its declared `byteStride × count`,
//! allowed only up to [`MAX_EXPANSION`] times its compressed size (and all views together that many
//! times the file), so a forged count cannot make a small file allocate gigabytes.

use serde_json::Value;

use super::document::{BufferView, Root};

use super::ImportError;

/// The extensions this module reads (the same JSON on buffers and buffer views).
pub(crate) const EXTENSIONS: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// Largest decoded size per compressed byte. The attribute codec's best case is a group of 16
/// zero deltas in 2 header bits, 64 decoded bytes per compressed byte; the triangle codec's is 12
/// bytes (a triangle of `u32` indices per code byte). A stream claiming more is corrupt.
pub(crate) const MAX_EXPANSION: usize = 64;

/// Attribute stream headers: version 0 (both extensions) and version 1 (KHR only).
const VERTEX_HEADER_V0: u8 = 0xa0;
const VERTEX_HEADER_V1: u8 = 0xa1;
const TRIANGLE_HEADER: u8 = 0xe1;
const SEQUENCE_HEADER: u8 = 0xd1;
/// The tail of an attribute stream (baseline element, and channel modes in version 1) is padded
/// to at least this size: version 0, version 1.
const TAIL_MIN: usize = 32;
const TAIL_MIN_V1: usize = 24;
/// Bits per delta for each 2-bit group header: version 0, and version 1's control modes 0 and 1.
const BITS_V0: [u8; 4] = [0, 2, 4, 8];
const BITS_V1: [[u8; 4]; 2] = [[0, 1, 2, 4], [1, 2, 4, 8]];

/// One compressed buffer view, as its extension object describes it.
#[derive(Clone, Debug, PartialEq)]
struct Compressed {
    buffer: usize,
    byte_offset: usize,
    byte_length: usize,
    byte_stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    /// `KHR_meshopt_compression` only: YCoCg colours.
    Color,
}

/// Whether buffer `index` is a placeholder for decompressed data: no bytes of its own, marked
/// `fallback`, or named only by compressed buffer views. Such a buffer is not loaded.
pub(crate) fn is_placeholder(root: &Root, index: usize) -> bool {
    let Some(buffer) = root.buffers.get(index) else { return false };
    let marked = EXTENSIONS.iter().any(|name| {
        buffer.extensions.get(*name).and_then(|e| e.get("fallback")).and_then(Value::as_bool) == Some(true)
    });
    let views: Vec<_> = root.buffer_views.iter().filter(|v| v.buffer == index).collect();
    marked || (!views.is_empty() && views.iter().all(|v| extension_of(v).is_some()))
}

fn extension_of(view: &BufferView) -> Option<(&'static str, &Value)> {
    EXTENSIONS.iter().find_map(|name| view.extensions.get(*name).map(|v| (*name, v)))
}

/// The decoded bytes of every compressed buffer view (`None` for the others), from the loaded
/// buffers that hold the compressed streams.
///
/// # Errors
/// [`ImportError::Invalid`] naming the buffer view, for a malformed extension object or a corrupt
/// stream.
pub(crate) fn decode_views(root: &Root, buffers: &[&[u8]]) -> Result<Vec<Option<Vec<u8>>>, ImportError> {
    let mut out = Vec::with_capacity(root.buffer_views.len());
    let file_bytes: usize = buffers.iter().map(|b| b.len()).sum();
    let mut decoded_total = 0usize;
    for (index, view) in root.buffer_views.iter().enumerate() {
        let Some((name, json)) = extension_of(view) else {
            out.push(None);
            continue;
        };
        let fail = |problem: String| {
            ImportError::Invalid(format!("bufferViews[{index}].extensions.{name}: {problem}"))
        };
        let khr = name == EXTENSIONS[1];
        let c = parse(json, khr).map_err(fail)?;
        if c.byte_stride * c.count != view.byte_length as usize {
            return Err(fail(format!(
                "decodes to {} × {} bytes but the buffer view has {}",
                c.count, c.byte_stride, view.byte_length
            )));
        }
        let source = buffers
            .get(c.buffer)
            .and_then(|b| b.get(c.byte_offset..c.byte_offset.checked_add(c.byte_length)?))
            .ok_or_else(|| fail(format!("its bytes are not inside buffer {}", c.buffer)))?;
        let size = c.byte_stride * c.count;
        // Saturating: on wasm32 64 × a large file's size does not fit a usize.
        if size > MAX_EXPANSION.saturating_mul(source.len()).saturating_add(4096) {
            return Err(fail(format!(
                "claims {size} decoded bytes from {} compressed ones (corrupt file?)",
                source.len()
            )));
        }
        // Views may share compressed bytes: the total is bounded by the file's size as well.
        decoded_total = decoded_total.saturating_add(size);
        if decoded_total > MAX_EXPANSION.saturating_mul(file_bytes).saturating_add(4096) {
            return Err(fail(format!(
                "the compressed views decode to over {MAX_EXPANSION} times the file's size"
            )));
        }
        let mut bytes = vec![0u8; size];
        let decoded = match c.mode {
            Mode::Attributes => decode_vertex_buffer(&mut bytes, c.count, c.byte_stride, source, khr),
            Mode::Triangles => decode_index_buffer(&mut bytes, c.count, c.byte_stride, source),
            Mode::Indices => decode_index_sequence(&mut bytes, c.count, c.byte_stride, source),
        };
        decoded.map_err(|e| fail(format!("corrupt {:?} stream: {e}", c.mode)))?;
        apply_filter(&mut bytes, c.byte_stride, c.filter);
        out.push(Some(bytes));
    }
    Ok(out)
}

/// Reads and checks an extension object (the spec's validity rules).
fn parse(json: &Value, khr: bool) -> Result<Compressed, String> {
    let size = |key: &str, required: bool| -> Result<usize, String> {
        match json.get(key) {
            None if !required => Ok(0),
            None => Err(format!("has no {key}")),
            Some(v) => v
                .as_u64()
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| format!("{key} {v} is not a whole number")),
        }
    };
    let text = |key: &str| json.get(key).and_then(Value::as_str);
    let mode = match text("mode") {
        Some("ATTRIBUTES") => Mode::Attributes,
        Some("TRIANGLES") => Mode::Triangles,
        Some("INDICES") => Mode::Indices,
        other => return Err(format!("unknown mode {other:?}")),
    };
    let filter = match text("filter") {
        None | Some("NONE") => Filter::None,
        Some("OCTAHEDRAL") => Filter::Octahedral,
        Some("QUATERNION") => Filter::Quaternion,
        Some("EXPONENTIAL") => Filter::Exponential,
        Some("COLOR") if khr => Filter::Color,
        Some(other) => return Err(format!("unknown filter {other:?}")),
    };
    let c = Compressed {
        buffer: size("buffer", true)?,
        byte_offset: size("byteOffset", false)?,
        byte_length: size("byteLength", true)?,
        byte_stride: size("byteStride", true)?,
        count: size("count", true)?,
        mode,
        filter,
    };
    let stride = c.byte_stride;
    let valid = match (mode, filter) {
        (Mode::Attributes, _) if stride == 0 || stride % 4 != 0 || stride > 256 => false,
        (Mode::Attributes, Filter::Octahedral) => stride == 4 || stride == 8,
        (Mode::Attributes, Filter::Quaternion) => stride == 8,
        (Mode::Attributes, Filter::Color) => stride == 4 || stride == 8,
        (Mode::Attributes, _) => true,
        (Mode::Triangles, Filter::None) => (stride == 2 || stride == 4) && c.count % 3 == 0,
        (Mode::Indices, Filter::None) => stride == 2 || stride == 4,
        _ => false,
    };
    if !valid {
        return Err(format!(
            "{mode:?} with filter {filter:?}, byte stride {stride} and count {} is not allowed",
            c.count
        ));
    }
    c.count.checked_mul(stride).ok_or("its decoded size overflows")?;
    Ok(c)
}

/// A forward reader over compressed bytes; every read is checked.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], &'static str> {
        let slice = self.bytes.get(self.at..self.at + n).ok_or("it ends early")?;
        self.at += n;
        Ok(slice)
    }

    fn byte(&mut self) -> Result<u8, &'static str> {
        Ok(self.take(1)?[0])
    }

    /// Unsigned LEB128, at most 5 bytes (32 bits).
    fn varint(&mut self) -> Result<u32, &'static str> {
        let mut value = 0u32;
        for shift in (0..35).step_by(7) {
            let b = self.byte()?;
            value |= u32::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err("a varint is longer than 5 bytes")
    }
}

/// `decode(v) = v & 1 ? ~(v >> 1) : v >> 1`, on bytes.
pub(crate) fn unzigzag8(v: u8) -> u8 {
    if v & 1 != 0 {
        !(v >> 1)
    } else {
        v >> 1
    }
}

fn unzigzag16(v: u16) -> u16 {
    if v & 1 != 0 {
        !(v >> 1)
    } else {
        v >> 1
    }
}

fn unzigzag32(v: u32) -> u32 {
    if v & 1 != 0 {
        !(v >> 1)
    } else {
        v >> 1
    }
}

/// Elements per attribute block: `min((8192 / stride) & ~15, 256)`.
pub(crate) fn block_elements(stride: usize) -> usize {
    ((8192 / stride) & !15).min(256)
}

/// Mode 0: `count` elements of `stride` bytes into `out`. Version 1 streams are read only where
/// `version_1` allows them (`KHR_meshopt_compression`).
fn decode_vertex_buffer(
    out: &mut [u8],
    count: usize,
    stride: usize,
    src: &[u8],
    version_1: bool,
) -> Result<(), &'static str> {
    let v1 = match src.first() {
        Some(&VERTEX_HEADER_V0) => false,
        Some(&VERTEX_HEADER_V1) if version_1 => true,
        Some(&VERTEX_HEADER_V1) => {
            return Err("version 1 of the attribute codec is KHR_meshopt_compression's")
        }
        _ => return Err("its header is not an attribute stream's"),
    };
    // The tail: zero padding, the baseline element (the one before the first), and in version 1
    // one channel mode byte per 4 bytes of the element.
    let modes_len = if v1 { stride / 4 } else { 0 };
    let tail = (stride + modes_len).max(if v1 { TAIL_MIN_V1 } else { TAIL_MIN });
    if src.len() < 1 + tail {
        return Err("it is shorter than its header and tail");
    }
    let modes = &src[src.len() - modes_len..];
    let mut last = src[src.len() - modes_len - stride..src.len() - modes_len].to_vec();
    if let Some(m) = modes.iter().find(|&&m| m & 15 > 2 || (m & 15 < 2 && m >> 4 != 0)) {
        return Err(if m & 15 > 2 {
            "a channel mode is unknown"
        } else {
            "a channel mode has rotation bits"
        });
    }
    let body = &src[1..src.len() - tail];
    let mut reader = Reader { bytes: body, at: 0 };
    let per_block = block_elements(stride);
    // Deltas of one block, byte position by byte position: `deltas[k * 256 + i]`.
    let mut deltas = vec![0u8; stride * 256];
    let mut start = 0;
    while start < count {
        let n = per_block.min(count - start);
        let groups = n.div_ceil(16);
        let control = if v1 { reader.take(stride / 4)? } else { &[][..] };
        for k in 0..stride {
            let column = &mut deltas[k * 256..k * 256 + groups * 16];
            let bits = match control.get(k / 4).map(|c| (c >> ((k % 4) * 2)) & 3) {
                None => BITS_V0,
                Some(0) => BITS_V1[0],
                Some(1) => BITS_V1[1],
                Some(2) => {
                    column.fill(0);
                    continue;
                }
                Some(_) => {
                    // Literal: the block's deltas as bytes, no header bits, no padding to 16.
                    column[..n].copy_from_slice(reader.take(n)?);
                    continue;
                }
            };
            let headers = reader.take(groups.div_ceil(4))?;
            for (g, group) in column.chunks_exact_mut(16).enumerate() {
                decode_group(&mut reader, bits[((headers[g / 4] >> ((g % 4) * 2)) & 3) as usize], group)?;
            }
        }
        for i in 0..n {
            let element = &mut out[(start + i) * stride..(start + i + 1) * stride];
            let delta = |k: usize| deltas[k * 256 + i];
            for c in 0..stride / 4 {
                let mode = modes.get(c).copied().unwrap_or(0);
                let at = 4 * c;
                let previous = &mut last[at..at + 4];
                match mode & 15 {
                    0 => {
                        for (k, p) in previous.iter_mut().enumerate() {
                            *p = p.wrapping_add(unzigzag8(delta(at + k)));
                        }
                    }
                    1 => {
                        for half in [0, 2] {
                            let d = u16::from_le_bytes([delta(at + half), delta(at + half + 1)]);
                            let p = u16::from_le_bytes([previous[half], previous[half + 1]]);
                            let v = p.wrapping_add(unzigzag16(d));
                            previous[half..half + 2].copy_from_slice(&v.to_le_bytes());
                        }
                    }
                    _ => {
                        let d = u32::from_le_bytes([0, 1, 2, 3].map(|k| delta(at + k)));
                        let p = u32::from_le_bytes([previous[0], previous[1], previous[2], previous[3]]);
                        let v = p ^ d.rotate_right(u32::from(mode >> 4));
                        previous.copy_from_slice(&v.to_le_bytes());
                    }
                }
            }
            element.copy_from_slice(&last);
        }
        start += n;
    }
    if reader.at != body.len() {
        return Err("it has bytes after its last block");
    }
    Ok(())
}

/// One group of 16 zigzag deltas of `bits` bits each: 0 all zero, 8 a byte each, 1, 2 or 4 packed
/// (1-bit deltas from the least significant bit of a byte, 2 and 4 from the most significant),
/// where the all-ones value is a sentinel for a full byte after the group's packed bits.
fn decode_group(reader: &mut Reader, bits: u8, deltas: &mut [u8]) -> Result<(), &'static str> {
    match bits {
        0 => deltas.fill(0),
        8 => deltas.copy_from_slice(reader.take(16)?),
        _ => {
            let bits = bits as usize;
            let packed = reader.take(2 * bits)?;
            let sentinel = (1u8 << bits) - 1;
            let per_byte = 8 / bits;
            for (i, delta) in deltas.iter_mut().enumerate() {
                let place = if bits == 1 { i % 8 } else { 8 - bits * (i % per_byte + 1) };
                let v = (packed[i / per_byte] >> place) & sentinel;
                *delta = if v == sentinel { reader.byte()? } else { v };
            }
        }
    }
    Ok(())
}

/// Writes index `i` of `value` as a `u16` or `u32`; a value a `u16` cannot hold is an error.
fn put_index(out: &mut [u8], stride: usize, i: usize, value: u32) -> Result<(), &'static str> {
    if stride == 2 {
        let v = u16::try_from(value).map_err(|_| "an index does not fit 16 bits")?;
        out[2 * i..2 * i + 2].copy_from_slice(&v.to_le_bytes());
    } else {
        out[4 * i..4 * i + 4].copy_from_slice(&value.to_le_bytes());
    }
    Ok(())
}

/// The `next` index of the triangle codec, post-incremented.
fn fresh(next: &mut u32) -> u32 {
    *next = next.wrapping_add(1);
    next.wrapping_sub(1)
}

/// An explicit index: a zigzag varint delta from `last`, which it updates.
fn explicit(data: &mut Reader, last: &mut u32) -> Result<u32, &'static str> {
    *last = last.wrapping_add(unzigzag32(data.varint()?));
    Ok(*last)
}

/// Pushes onto a 16-entry FIFO whose most recent entry is at `at - 1`.
fn push<T>(fifo: &mut [T; 16], at: &mut usize, value: T) {
    fifo[*at] = value;
    *at = (*at + 1) & 15;
}

/// Mode 1: a triangle list of `count` indices.
fn decode_index_buffer(out: &mut [u8], count: usize, stride: usize, src: &[u8]) -> Result<(), &'static str> {
    let triangles = count / 3;
    if src.len() < 1 + triangles + 16 || src[0] != TRIANGLE_HEADER {
        return Err("its header, codes or table are missing");
    }
    let codes = &src[1..1 + triangles];
    let aux = &src[src.len() - 16..];
    let mut data = Reader { bytes: &src[1 + triangles..src.len() - 16], at: 0 };
    let mut edges = [[0u32; 2]; 16];
    let mut edge_at = 0usize;
    let mut vertices = [0u32; 16];
    let mut vertex_at = 0usize;
    let (mut next, mut last) = (0u32, 0u32);
    for (t, &code) in codes.iter().enumerate() {
        let (x, y) = ((code >> 4) as usize, (code & 15) as usize);
        let [a, b, c];
        if x < 15 {
            [a, b] = edges[(edge_at + 15 - x) & 15];
            c = match y {
                0 => fresh(&mut next),
                1..=12 => vertices[(vertex_at + 15 - y) & 15],
                13 => {
                    last = last.wrapping_sub(1);
                    last
                }
                14 => {
                    last = last.wrapping_add(1);
                    last
                }
                _ => explicit(&mut data, &mut last)?,
            };
            if !(1..=12).contains(&y) {
                push(&mut vertices, &mut vertex_at, c);
            }
            push(&mut edges, &mut edge_at, [c, b]);
            push(&mut edges, &mut edge_at, [a, c]);
        } else {
            // `0xfY`: Y < 14 looks (Z, W) up in the table; 0xfe and 0xff read it from the data,
            // where 0xff's first index and a Z or W of 15 are explicit.
            let (z, w, escaped) = if y < 14 {
                (aux[y] >> 4, aux[y] & 15, false)
            } else {
                let zw = data.byte()?;
                if zw == 0 {
                    next = 0;
                }
                (zw >> 4, zw & 15, true)
            };
            a = if y == 15 { explicit(&mut data, &mut last)? } else { fresh(&mut next) };
            let other = |zw: u8, data: &mut Reader, last: &mut u32, next: &mut u32| match zw {
                0 => Ok(fresh(next)),
                15 if escaped => explicit(data, last),
                _ => Ok(vertices[(vertex_at + 16 - zw as usize) & 15]),
            };
            b = other(z, &mut data, &mut last, &mut next)?;
            c = other(w, &mut data, &mut last, &mut next)?;
            let pushed = |zw: u8| zw == 0 || (zw == 15 && escaped);
            push(&mut vertices, &mut vertex_at, a);
            if pushed(z) {
                push(&mut vertices, &mut vertex_at, b);
            }
            if pushed(w) {
                push(&mut vertices, &mut vertex_at, c);
            }
            push(&mut edges, &mut edge_at, [b, a]);
            push(&mut edges, &mut edge_at, [c, b]);
            push(&mut edges, &mut edge_at, [a, c]);
        }
        for (k, v) in [a, b, c].into_iter().enumerate() {
            put_index(out, stride, 3 * t + k, v)?;
        }
    }
    if data.at != data.bytes.len() {
        return Err("it has data no triangle reads");
    }
    Ok(())
}

/// Mode 2: `count` indices, each a zigzag delta against one of two baselines.
fn decode_index_sequence(
    out: &mut [u8],
    count: usize,
    stride: usize,
    src: &[u8],
) -> Result<(), &'static str> {
    if src.len() < 1 + 4 || src[0] != SEQUENCE_HEADER {
        return Err("its header or tail is missing");
    }
    let mut data = Reader { bytes: &src[1..src.len() - 4], at: 0 };
    let mut last = [0u32; 2];
    for i in 0..count {
        let v = data.varint()?;
        let baseline = (v & 1) as usize;
        let delta = if v & 2 != 0 { !(v >> 2) } else { v >> 2 };
        last[baseline] = last[baseline].wrapping_add(delta);
        put_index(out, stride, i, last[baseline])?;
    }
    if data.at != data.bytes.len() {
        return Err("it has bytes after its last index");
    }
    Ok(())
}

/// Appendix B: the filter's transform of every decoded element, in place.
fn apply_filter(bytes: &mut [u8], stride: usize, filter: Filter) {
    match filter {
        Filter::None => {}
        Filter::Octahedral if stride == 4 => {
            for e in bytes.chunks_exact_mut(4) {
                let v = octahedral([e[0] as i8 as f32, e[1] as i8 as f32, e[2] as i8 as f32], 127.0);
                for k in 0..3 {
                    e[k] = v[k] as i8 as u8;
                }
            }
        }
        Filter::Octahedral => {
            for e in bytes.chunks_exact_mut(8) {
                let c = |k: usize| i16::from_le_bytes([e[2 * k], e[2 * k + 1]]) as f32;
                let v = octahedral([c(0), c(1), c(2)], 32767.0);
                for k in 0..3 {
                    e[2 * k..2 * k + 2].copy_from_slice(&(v[k] as i16).to_le_bytes());
                }
            }
        }
        Filter::Quaternion => {
            for e in bytes.chunks_exact_mut(8) {
                let c = |k: usize| i16::from_le_bytes([e[2 * k], e[2 * k + 1]]);
                let q = quaternion([c(0), c(1), c(2), c(3)]);
                for (k, v) in q.into_iter().enumerate() {
                    e[2 * k..2 * k + 2].copy_from_slice(&v.to_le_bytes());
                }
            }
        }
        Filter::Exponential => {
            for e in bytes.chunks_exact_mut(4) {
                let v = i32::from_le_bytes([e[0], e[1], e[2], e[3]]);
                e.copy_from_slice(&exponential(v).to_le_bytes());
            }
        }
        Filter::Color if stride == 4 => {
            for e in bytes.chunks_exact_mut(4) {
                let rgba = color([0, 1, 2, 3].map(|k| i32::from(e[k] as i8)), i32::from(e[3]), 255.0);
                for k in 0..4 {
                    e[k] = rgba[k] as u8;
                }
            }
        }
        Filter::Color => {
            for e in bytes.chunks_exact_mut(8) {
                let c = |k: usize| i16::from_le_bytes([e[2 * k], e[2 * k + 1]]);
                let alpha = i32::from(u16::from_le_bytes([e[6], e[7]]));
                let rgba = color([0, 1, 2, 3].map(|k| i32::from(c(k))), alpha, 65535.0);
                for k in 0..4 {
                    e[2 * k..2 * k + 2].copy_from_slice(&(rgba[k] as u16).to_le_bytes());
                }
            }
        }
    }
}

/// The octahedral filter: `[x, y, one]` (K-bit signed integers, `one` encoding 1.0) to a unit
/// vector in `[-max, max]` integers, rounded.
fn octahedral([x, y, one]: [f32; 3], max: f32) -> [f32; 3] {
    if one == 0.0 {
        return [0.0; 3]; // not a valid encoding; the spec leaves the result unspecified
    }
    let (mut x, mut y) = (x / one, y / one);
    let z = 1.0 - x.abs() - y.abs();
    let t = z.min(0.0);
    x -= t.copysign(x);
    y -= t.copysign(y);
    let len = (x * x + y * y + z * z).sqrt();
    [x, y, z].map(|c| (c / len * max).round())
}

/// The quaternion filter: three components scaled by √2 and the index of the omitted largest one
/// in the low two bits of the fourth, to four `i16` normalized components.
fn quaternion(input: [i16; 4]) -> [i16; 4] {
    let range = std::f32::consts::FRAC_1_SQRT_2;
    let one = f32::from(input[3] | 3);
    let [x, y, z] = [0, 1, 2].map(|k| f32::from(input[k]) / one * range);
    let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
    let max_component = (input[3] & 3) as usize;
    let mut out = [0i16; 4];
    for (k, v) in [w, x, y, z].into_iter().enumerate() {
        out[(max_component + k) % 4] = (v * 32767.0).round() as i16;
    }
    out
}

/// The colour filter: Y, Co, Cg as K-bit integers (Y unsigned, read here from the signed
/// component: Y's K bits fit the component whatever its sign bit says, see below) and alpha as
/// K-1 bits under a marker bit K-1, to RGBA in `[0, max]` integers, rounded. `alpha` is the fourth
/// component unsigned; `input[3]` the same, sign-extended, unused.
fn color(input: [i32; 4], alpha: i32, max: f32) -> [f32; 4] {
    if alpha == 0 {
        return [0.0; 4]; // no marker bit: not a valid encoding, the spec leaves it unspecified
    }
    let scale = (1i32 << (32 - alpha.leading_zeros())) - 1; // (1 << (msb + 1)) - 1
                                                            // Y is unsigned: undo the sign extension of its component.
    let y = input[0] & scale;
    let (co, cg) = (input[1], input[2]);
    let a = alpha & (scale >> 1);
    let a = (a << 1) | (a & 1);
    let factor = max / scale as f32;
    [y + co - cg, y + cg, y - co - cg, a].map(|v| (v as f32 * factor).round().clamp(0.0, max))
}

/// The exponential filter: a signed 8-bit exponent over a signed 24-bit mantissa, `2^e · m`.
fn exponential(v: i32) -> f32 {
    let e = v >> 24;
    let m = (v << 8) >> 8;
    // e is in [-128, 127]; the spec's valid range is [-100, 100].
    (m as f32) * 2f32.powi(e)
}

#[cfg(test)]
#[path = "meshopt_tests.rs"]
mod tests;
