//! Little-endian writing and bounds-checked reading for [`super`]'s format: every array is a
//! `u32` element count followed by its elements, and every count is checked against the bytes
//! left before anything is allocated.

use glam::Vec3;

use super::{ClodBytesError, Result};

pub(super) struct Writer {
    pub(super) out: Vec<u8>,
}

impl Writer {
    pub(super) fn u32(&mut self, x: u32) {
        self.out.extend_from_slice(&x.to_le_bytes());
    }

    pub(super) fn u64(&mut self, x: u64) {
        self.out.extend_from_slice(&x.to_le_bytes());
    }

    pub(super) fn f32(&mut self, x: f32) {
        self.out.extend_from_slice(&x.to_le_bytes());
    }

    /// A count or `usize` field, as `u32`.
    pub(super) fn len(&mut self, n: usize) {
        self.u32(u32::try_from(n).expect("CLOD arrays and counts fit in u32"));
    }

    pub(super) fn u32s(&mut self, xs: &[u32]) {
        self.len(xs.len());
        xs.iter().for_each(|&x| self.u32(x));
    }

    pub(super) fn f32s(&mut self, xs: &[f32]) {
        self.len(xs.len());
        xs.iter().for_each(|&x| self.f32(x));
    }

    pub(super) fn vec3s(&mut self, xs: &[Vec3]) {
        self.len(xs.len());
        xs.iter().flat_map(|v| v.to_array()).for_each(|x| self.f32(x));
    }
}

/// A cursor over the input bytes; every read checks the bytes left first.
pub(super) struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Self {
        Reader { bytes, at: 0 }
    }

    pub(super) fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    pub(super) fn take(&mut self, n: usize, field: &'static str) -> Result<&'a [u8]> {
        if n > self.remaining() {
            return Err(ClodBytesError::Truncated { field, needed: n as u64, remaining: self.remaining() });
        }
        let out = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(out)
    }

    pub(super) fn u32(&mut self, field: &'static str) -> Result<u32> {
        let b = self.take(4, field)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub(super) fn u64(&mut self, field: &'static str) -> Result<u64> {
        let (lo, hi) = (self.u32(field)?, self.u32(field)?);
        Ok(u64::from(lo) | u64::from(hi) << 32)
    }

    pub(super) fn f32(&mut self, field: &'static str) -> Result<f32> {
        Ok(f32::from_bits(self.u32(field)?))
    }

    /// An element count, checked against the bytes left (each element needs at least
    /// `element_bytes`), so a lying prefix cannot make the decoder allocate.
    pub(super) fn count(&mut self, field: &'static str, element_bytes: usize) -> Result<usize> {
        let n = self.u32(field)? as usize;
        let needed = n as u64 * element_bytes as u64;
        if needed > self.remaining() as u64 {
            return Err(ClodBytesError::Truncated { field, needed, remaining: self.remaining() });
        }
        Ok(n)
    }

    pub(super) fn u32s(&mut self, field: &'static str) -> Result<Vec<u32>> {
        let n = self.count(field, 4)?;
        let raw = self.take(4 * n, field)?;
        Ok(raw.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
    }

    pub(super) fn f32s(&mut self, field: &'static str) -> Result<Vec<f32>> {
        Ok(self.u32s(field)?.into_iter().map(f32::from_bits).collect())
    }

    pub(super) fn vec3s(&mut self, field: &'static str) -> Result<Vec<Vec3>> {
        let n = self.count(field, 12)?;
        let raw = self.take(12 * n, field)?;
        let f = |c: &[u8], k: usize| f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]);
        Ok(raw.chunks_exact(12).map(|c| Vec3::new(f(c, 0), f(c, 1), f(c, 2))).collect())
    }
}
