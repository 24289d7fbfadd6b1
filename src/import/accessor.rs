//! Reading glTF accessors (§3.6.2, §5.1) into flat arrays, with every bound checked before any
//! allocation: the element count against the caller's cap, `byteOffset + (count - 1) * stride +
//! element size` against the buffer view, sparse indices against the count.
//!
//! Integer components convert to floats as the spec's normalization table says (§3.11: `u8 / 255`,
//! `i8 / 127` clamped at -1, …) when the accessor is `normalized`, and by value otherwise.
//! Components are read byte-wise in little endian, so misaligned data is read, not rejected.

use std::collections::HashMap;
use std::rc::Rc;

use super::document::{ComponentType, Root, Sparse, Type};

use super::container::{view_bytes, Buffers};
use super::ImportError;

/// The parsed document and its loaded buffers: everything an accessor read needs.
#[derive(Clone, Copy)]
pub(crate) struct Source<'a> {
    pub root: &'a Root,
    pub buffers: &'a Buffers<'a>,
}

/// Flat accessor data: `values.len() == count * components`.
pub(crate) struct Elements<T> {
    pub values: Vec<T>,
    pub components: usize,
}

impl<T: Copy> Elements<T> {
    /// Number of elements.
    pub fn count(&self) -> usize {
        self.values.len().checked_div(self.components).unwrap_or(0)
    }
}

impl<T> Elements<T> {
    /// Element `i` as a slice of its components.
    pub fn get(&self, i: usize) -> &[T] {
        &self.values[i * self.components..(i + 1) * self.components]
    }
}

/// Most elements of an accessor without buffer view (all zeros, then sparse substitutions). Its
/// size is not backed by file bytes, so a tiny file could otherwise ask for gigabytes; 2^22
/// elements (64 MiB of `vec4<f32>`) is far beyond any sparse use in a character.
const MAX_ZERO_FILLED: usize = 1 << 22;

fn accessor_error(index: usize, usage: &str, problem: String) -> ImportError {
    ImportError::Accessor { index, usage: usage.to_string(), problem }
}

/// One component as `f32`, per the spec's normalization rules; `bytes` holds at least its size.
fn component_f32(ct: ComponentType, normalized: bool, b: &[u8]) -> f32 {
    match ct {
        ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        ComponentType::U8 if normalized => b[0] as f32 / 255.0,
        ComponentType::U8 => b[0] as f32,
        ComponentType::I8 if normalized => (b[0] as i8 as f32 / 127.0).max(-1.0),
        ComponentType::I8 => b[0] as i8 as f32,
        ComponentType::U16 if normalized => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
        ComponentType::U16 => u16::from_le_bytes([b[0], b[1]]) as f32,
        ComponentType::I16 if normalized => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
        ComponentType::I16 => i16::from_le_bytes([b[0], b[1]]) as f32,
        // Normalized u32 is not allowed by the spec; map it to [0, 1] like the other unsigned types.
        ComponentType::U32 if normalized => {
            u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32 / u32::MAX as f32
        }
        ComponentType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
    }
}

/// One unsigned integer component; `None` for float and signed types.
fn component_u32(ct: ComponentType, b: &[u8]) -> Option<u32> {
    match ct {
        ComponentType::U8 => Some(b[0] as u32),
        ComponentType::U16 => Some(u16::from_le_bytes([b[0], b[1]]) as u32),
        ComponentType::U32 => Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}

/// Turns one component (type, `normalized` flag, its bytes) into a value, `None` if unsupported.
type ConvertFn<T> = dyn Fn(ComponentType, bool, &[u8]) -> Option<T>;

/// `offset + (count - 1) * stride + elem`, the bytes `count` strided elements need (0 for none).
fn bytes_needed(offset: u64, count: u64, stride: u64, elem: u64) -> u128 {
    if count == 0 {
        return 0;
    }
    offset as u128 + (count as u128 - 1) * stride as u128 + elem as u128
}

/// Reads accessor `index` for `usage` (a phrase naming its use, for error messages).
///
/// `types` lists the accepted accessor types, `max_count` caps the element count (checked before
/// any allocation), `convert` turns one component's bytes into a `T`.
fn read<T: Copy + Default>(
    src: Source,
    index: usize,
    usage: &str,
    types: &[Type],
    max_count: usize,
    convert: &ConvertFn<T>,
) -> Result<Elements<T>, ImportError> {
    let err = |problem: String| accessor_error(index, usage, problem);
    let acc = src.root.accessors.get(index).ok_or_else(|| err("does not exist".into()))?;
    let (ty, ct) = (acc.type_, acc.component_type);
    if !types.contains(&ty) {
        return Err(err(format!("is {ty:?} but must be one of {types:?}")));
    }
    // Matrices of 1- and 2-byte components pad their columns to 4 bytes; no use of ours has them.
    if matches!(ty, Type::Mat2 | Type::Mat3 | Type::Mat4) && ct != ComponentType::F32 {
        return Err(err("is a matrix of non-float components".into()));
    }
    let count = acc.count;
    if count > max_count as u64 {
        return Err(err(format!("has {count} elements, more than the limit of {max_count}")));
    }
    let count = count as usize;
    let components = ty.multiplicity();
    let size = ct.size();
    let elem = components * size;
    let check =
        |b: &[u8]| convert(ct, acc.normalized, b).ok_or_else(|| err(format!("has {ct:?} components")));
    // Elements read from bytes: the accessor's own buffer view, or what a Draco stream decoded
    // for it (tightly packed, from offset 0).
    let from_bytes = |bytes: &[u8], stride: usize, offset: u64, source: String| {
        let needed = bytes_needed(offset, count as u64, stride as u64, elem as u64);
        if needed > bytes.len() as u128 {
            return Err(err(format!("needs {needed} bytes but {source} has {}", bytes.len())));
        }
        let mut values = Vec::with_capacity(count * components);
        for i in 0..count {
            let base = offset as usize + i * stride;
            for c in 0..components {
                values.push(check(&bytes[base + c * size..base + (c + 1) * size])?);
            }
        }
        Ok(values)
    };
    let mut values: Vec<T> = match (src.buffers.draco_accessor(index), acc.buffer_view) {
        (Some(decoded), _) => from_bytes(decoded, elem, 0, "its Draco stream".into())?,
        (None, None) if count > MAX_ZERO_FILLED => {
            return Err(err(format!(
                "has no buffer view and {count} elements, more than the limit of {MAX_ZERO_FILLED}"
            )))
        }
        (None, None) => vec![T::default(); count * components],
        (None, Some(view)) => {
            let bytes = view_bytes(src.root, src.buffers, view)?;
            let stride = src.root.buffer_views[view].byte_stride.unwrap_or(elem);
            if stride < elem {
                return Err(err(format!("has {elem}-byte elements but a byte stride of {stride}")));
            }
            let offset = acc.byte_offset;
            from_bytes(bytes, stride, offset, format!("buffer view {view}"))?
        }
    };
    if let Some(sparse) = &acc.sparse {
        apply_sparse(src, sparse, count, elem, &mut values, &|b| check(b), &err)?;
    }
    Ok(Elements { values, components })
}

/// Overwrites the elements a sparse accessor substitutes (§3.6.2.3).
fn apply_sparse<T>(
    src: Source,
    sparse: &Sparse,
    count: usize,
    elem: usize,
    values: &mut [T],
    convert: &dyn Fn(&[u8]) -> Result<T, ImportError>,
    err: &dyn Fn(String) -> ImportError,
) -> Result<(), ImportError> {
    let n = sparse.count;
    if n > count as u64 {
        return Err(err(format!("substitutes {n} sparse elements but has only {count}")));
    }
    let n = n as usize;
    let index_type = sparse.indices.component_type;
    let index_size = index_type.size();
    let index_bytes = view_bytes(src.root, src.buffers, sparse.indices.buffer_view)?;
    let index_offset = sparse.indices.byte_offset;
    let value_bytes = view_bytes(src.root, src.buffers, sparse.values.buffer_view)?;
    let value_offset = sparse.values.byte_offset;
    if bytes_needed(index_offset, n as u64, index_size as u64, index_size as u64) > index_bytes.len() as u128
    {
        return Err(err(format!(
            "needs more sparse index bytes than its buffer view's {}",
            index_bytes.len()
        )));
    }
    if bytes_needed(value_offset, n as u64, elem as u64, elem as u64) > value_bytes.len() as u128 {
        return Err(err(format!(
            "needs more sparse value bytes than its buffer view's {}",
            value_bytes.len()
        )));
    }
    let components = values.len().checked_div(count).unwrap_or(0);
    let size = elem.checked_div(components).unwrap_or(0);
    for k in 0..n {
        let at = index_offset as usize + k * index_size;
        let target = component_u32(index_type, &index_bytes[at..at + index_size])
            .ok_or_else(|| err("has a non-integer sparse index type".into()))? as usize;
        if target >= count {
            return Err(err(format!("has sparse index {target}, out of range for {count} elements")));
        }
        let base = value_offset as usize + k * elem;
        for c in 0..components {
            values[target * components + c] = convert(&value_bytes[base + c * size..base + (c + 1) * size])?;
        }
    }
    Ok(())
}

/// Reads a float (or integer, converted) accessor; see the module docs for conversions.
///
/// # Errors
/// Missing accessor, wrong type, more than `max_count` elements, data outside its buffer view.
pub(crate) fn read_floats(
    src: Source,
    index: usize,
    usage: &str,
    types: &[Type],
    max_count: usize,
) -> Result<Elements<f32>, ImportError> {
    read(src, index, usage, types, max_count, &|ct, normalized, b| Some(component_f32(ct, normalized, b)))
}

/// Reads an accessor of unsigned integers (indices, joint indices).
///
/// # Errors
/// As [`read_floats`], plus float or signed component types.
pub(crate) fn read_uints(
    src: Source,
    index: usize,
    usage: &str,
    types: &[Type],
    max_count: usize,
) -> Result<Elements<u32>, ImportError> {
    read(src, index, usage, types, max_count, &|ct, _, b| component_u32(ct, b))
}

/// Accessors that several readers share, decoded once each. Some exporters write one vertex buffer
/// for a whole mesh and let every primitive index a part of it, and a mesh drawn by two nodes is
/// read twice: reading such an accessor again for every primitive would make an import quadratic
/// (200 primitives over one 100,000-vertex buffer read 20 million vertices). An accessor counted
/// more than once in [`SharedReads::new`] is kept from its first read until its last.
pub(crate) struct SharedReads {
    /// Reads still to come, per accessor counted more than once.
    reads_left: HashMap<usize, usize>,
    floats: HashMap<usize, Rc<Elements<f32>>>,
    uints: HashMap<usize, Rc<Elements<u32>>>,
}

impl SharedReads {
    /// Expects one read of each accessor in `reads` per time it is listed.
    pub fn new(reads: impl IntoIterator<Item = usize>) -> SharedReads {
        let mut reads_left = HashMap::new();
        for index in reads {
            *reads_left.entry(index).or_insert(0) += 1;
        }
        reads_left.retain(|_, count| *count > 1);
        SharedReads { reads_left, floats: HashMap::new(), uints: HashMap::new() }
    }

    /// [`read_floats`], decoding a shared accessor only the first time.
    ///
    /// # Errors
    /// As [`read_floats`]; a kept accessor's type is checked again for each use.
    pub fn floats(
        &mut self,
        src: Source,
        index: usize,
        usage: &str,
        types: &[Type],
        max_count: usize,
    ) -> Result<Rc<Elements<f32>>, ImportError> {
        let keep = self.read_once_more(src, index, usage, types)?;
        Self::shared(&mut self.floats, keep, index, || read_floats(src, index, usage, types, max_count))
    }

    /// [`read_uints`], decoding a shared accessor only the first time.
    ///
    /// # Errors
    /// As [`read_uints`].
    pub fn uints(
        &mut self,
        src: Source,
        index: usize,
        usage: &str,
        types: &[Type],
        max_count: usize,
    ) -> Result<Rc<Elements<u32>>, ImportError> {
        let keep = self.read_once_more(src, index, usage, types)?;
        Self::shared(&mut self.uints, keep, index, || read_uints(src, index, usage, types, max_count))
    }

    /// Counts one read of `index`: whether to keep it for a later one. A kept accessor was read
    /// for another use, so its type is checked against this one's.
    fn read_once_more(
        &mut self,
        src: Source,
        index: usize,
        usage: &str,
        types: &[Type],
    ) -> Result<bool, ImportError> {
        let Some(left) = self.reads_left.get_mut(&index) else { return Ok(false) };
        *left = left.saturating_sub(1);
        if let Some(ty) = src.root.accessors.get(index).map(|a| a.type_) {
            if !types.contains(&ty) {
                return Err(accessor_error(index, usage, format!("is {ty:?} but must be one of {types:?}")));
            }
        }
        Ok(*left > 0)
    }

    fn shared<T>(
        kept: &mut HashMap<usize, Rc<Elements<T>>>,
        keep: bool,
        index: usize,
        read: impl FnOnce() -> Result<Elements<T>, ImportError>,
    ) -> Result<Rc<Elements<T>>, ImportError> {
        let elements = match kept.remove(&index) {
            Some(elements) => elements,
            None => Rc::new(read()?),
        };
        if keep {
            kept.insert(index, Rc::clone(&elements));
        }
        Ok(elements)
    }
}

/// The elements at `rows` (all of them, in order, for `None`), without a copy when all are wanted
/// from an accessor no one else holds.
pub(crate) fn pick_rows<T: Copy>(elements: Rc<Elements<T>>, rows: Option<&[u32]>) -> Elements<T> {
    let Some(rows) = rows else {
        return Rc::try_unwrap(elements).unwrap_or_else(|shared| Elements {
            values: shared.values.clone(),
            components: shared.components,
        });
    };
    let values = rows.iter().flat_map(|&r| elements.get(r as usize).iter().copied()).collect();
    Elements { values, components: elements.components }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_follow_the_spec_table() {
        assert_eq!(component_f32(ComponentType::U8, true, &[255]), 1.0);
        assert_eq!(component_f32(ComponentType::I8, true, &[0x80]), -1.0);
        assert_eq!(component_f32(ComponentType::I8, true, &[0x81]), -1.0);
        assert_eq!(component_f32(ComponentType::U16, true, &[0xFF, 0xFF]), 1.0);
        assert_eq!(component_f32(ComponentType::I16, true, &[0xFF, 0x7F]), 1.0);
        assert_eq!(component_f32(ComponentType::U16, false, &[2, 1]), 258.0);
    }

    #[test]
    fn byte_span_of_strided_elements() {
        assert_eq!(bytes_needed(4, 3, 16, 12), 4 + 2 * 16 + 12);
        assert_eq!(bytes_needed(100, 0, 16, 12), 0);
        assert_eq!(bytes_needed(u64::MAX, u64::MAX, 252, 64), u64::MAX as u128 * 253 - 252 + 64);
    }
}
