//! The Draco decoder of clod-viewer (`KHR_draco_mesh_compression`): one stream in, the mesh's
//! faces and the requested attributes out. A crate of its own so that the viewer page does not
//! download the decoder (draco-core, a pure Rust port of Google's decoder) with the viewer: the
//! page loads this crate's wasm (`www/pkg-draco/`, feature `js`) only when a file has Draco
//! streams, and hands its [`decode`](js::decode) to the viewer, which calls it for each stream
//! (the importer's `src/import/draco.rs` decides what to ask and checks what comes back). Native
//! programs and the node build link the decoder in (feature `decoder`, the viewer's `draco`).
//!
//! Across the wasm boundary a [`Request`] travels as `u32` words ([`Request::to_words`]) and the
//! answer as bytes ([`write_answer`] / [`read_answer`]), so the two modules share no memory and
//! no JavaScript object shapes. Every length in an answer is checked against the bytes present.

/// What to decode from one stream.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Request {
    /// Limits the decoder stops at ([`DecodeError::LimitExceeded`]).
    pub max_points: u64,
    pub max_faces: u64,
    pub max_decoded_bytes: u64,
    /// `(Draco unique attribute id, components)` of each attribute wanted, in answer order.
    pub attributes: Vec<(u32, usize)>,
}

/// One decoded stream.
#[derive(Clone, Debug, PartialEq)]
pub struct Decoded {
    /// Three point indices per triangle.
    pub faces: Vec<u32>,
    /// Points (vertices) of the decoded mesh.
    pub points: usize,
    /// Per requested attribute, in request order; `None` when the stream has no such id.
    pub attributes: Vec<Option<Attribute>>,
}

/// One attribute's values, `points × components` of the request (missing components are 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Attribute {
    /// Whether Draco stores it as floats (reconstructed positions, normals, uvs): a float stored
    /// into a normalized integer accessor is scaled to its range.
    pub float: bool,
    pub values: Vec<f32>,
}

/// Why a stream did not decode.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// It decodes to more than the request's limits.
    LimitExceeded,
    /// It is not a Draco mesh stream this decoder reads (the decoder's own words).
    Invalid(String),
}

impl Request {
    /// `[max_points lo, hi, max_faces lo, hi, max_decoded_bytes lo, hi, count, (id, components)…]`.
    pub fn to_words(&self) -> Vec<u32> {
        let split = |x: u64| [x as u32, (x >> 32) as u32];
        let mut words = Vec::with_capacity(7 + 2 * self.attributes.len());
        for x in [self.max_points, self.max_faces, self.max_decoded_bytes] {
            words.extend(split(x));
        }
        words.push(self.attributes.len() as u32);
        for &(id, components) in &self.attributes {
            words.extend([id, components as u32]);
        }
        words
    }

    /// The request of [`Request::to_words`]'s words; `None` when they are not one.
    pub fn from_words(words: &[u32]) -> Option<Request> {
        let join = |i: usize| Some(u64::from(*words.get(i)?) | u64::from(*words.get(i + 1)?) << 32);
        let count = *words.get(6)? as usize;
        let pairs = words.get(7..)?;
        if pairs.len() != 2 * count {
            return None;
        }
        Some(Request {
            max_points: join(0)?,
            max_faces: join(2)?,
            max_decoded_bytes: join(4)?,
            attributes: pairs.chunks_exact(2).map(|p| (p[0], p[1] as usize)).collect(),
        })
    }
}

/// Decodes one stream (feature `decoder`).
///
/// # Errors
/// [`DecodeError::LimitExceeded`] past the request's limits, [`DecodeError::Invalid`] for a
/// stream that does not decode.
#[cfg(feature = "decoder")]
pub fn decode(stream: &[u8], request: &Request) -> Result<Decoded, DecodeError> {
    use draco_core::{DataType, DecodeLimits, DecoderBuffer, ErrorKind, FaceIndex, Mesh, MeshDecoder};
    let limits = DecodeLimits::default()
        .with_max_points(request.max_points)
        .with_max_faces(request.max_faces)
        .with_max_decoded_bytes(request.max_decoded_bytes);
    let mut mesh = Mesh::new();
    MeshDecoder::new().decode(&mut DecoderBuffer::new(stream).with_limits(limits), &mut mesh).map_err(
        |e| match e.kind() {
            ErrorKind::LimitExceeded => DecodeError::LimitExceeded,
            _ => DecodeError::Invalid(e.to_string()),
        },
    )?;
    let faces = (0..mesh.num_faces()).flat_map(|f| mesh.face(FaceIndex(f as u32)).map(|p| p.0)).collect();
    let points = mesh.num_points();
    let attributes = request
        .attributes
        .iter()
        .map(|&(id, components)| {
            mesh.attribute_by_unique_id(id).map(|a| Attribute {
                float: matches!(a.data_type(), DataType::Float32 | DataType::Float64),
                values: a.read_f32s(points, components),
            })
        })
        .collect();
    Ok(Decoded { faces, points, attributes })
}

const OK: u32 = 0;
const LIMIT_EXCEEDED: u32 = 1;
const INVALID: u32 = 2;

/// An answer as bytes (little-endian `u32`s and `f32`s): a status (0 decoded, 1 over the limits,
/// 2 invalid, then the message's length and UTF-8); decoded: points, triangles, the faces, the
/// attribute count, then per attribute `0`, or `1`, its float flag, its value count and values.
pub fn write_answer(answer: &Result<Decoded, DecodeError>) -> Vec<u8> {
    let mut out = Vec::new();
    let word = |out: &mut Vec<u8>, x: u32| out.extend(x.to_le_bytes());
    match answer {
        Err(DecodeError::LimitExceeded) => word(&mut out, LIMIT_EXCEEDED),
        Err(DecodeError::Invalid(message)) => {
            word(&mut out, INVALID);
            word(&mut out, message.len() as u32);
            out.extend(message.as_bytes());
        }
        Ok(d) => {
            out.reserve(16 + 4 * d.faces.len());
            word(&mut out, OK);
            word(&mut out, d.points as u32);
            word(&mut out, (d.faces.len() / 3) as u32);
            for &f in &d.faces[..d.faces.len() / 3 * 3] {
                word(&mut out, f);
            }
            word(&mut out, d.attributes.len() as u32);
            for a in &d.attributes {
                match a {
                    None => word(&mut out, 0),
                    Some(a) => {
                        word(&mut out, 1);
                        word(&mut out, u32::from(a.float));
                        word(&mut out, a.values.len() as u32);
                        for v in &a.values {
                            out.extend(v.to_le_bytes());
                        }
                    }
                }
            }
        }
    }
    out
}

/// The answer [`write_answer`] wrote.
///
/// # Errors
/// A sentence when `bytes` are not such an answer (cut short, or a count beyond the bytes).
pub fn read_answer(bytes: &[u8]) -> Result<Result<Decoded, DecodeError>, String> {
    let mut r = Reader { bytes, at: 0 };
    match r.word()? {
        LIMIT_EXCEEDED => Ok(Err(DecodeError::LimitExceeded)),
        INVALID => {
            let len = r.word()? as usize;
            let text = r.take(len)?;
            Ok(Err(DecodeError::Invalid(String::from_utf8_lossy(text).into_owned())))
        }
        OK => {
            let points = r.word()? as usize;
            let triangles = r.word()? as usize;
            let faces = r.words(triangles.saturating_mul(3))?;
            let count = r.word()? as usize;
            let mut attributes = Vec::new();
            for _ in 0..count {
                attributes.push(match r.word()? {
                    0 => None,
                    _ => {
                        let float = r.word()? != 0;
                        let n = r.word()? as usize;
                        Some(Attribute {
                            float,
                            values: r.words(n)?.into_iter().map(f32::from_bits).collect(),
                        })
                    }
                });
            }
            if r.at != bytes.len() {
                return Err(MALFORMED.into());
            }
            Ok(Ok(Decoded { faces, points, attributes }))
        }
        _ => Err(MALFORMED.into()),
    }
}

const MALFORMED: &str = "the Draco decoder's answer is malformed";

/// Reads an answer front to back, every length checked against what is left.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&end| end <= self.bytes.len()).ok_or(MALFORMED)?;
        let slice = &self.bytes[self.at..end];
        self.at = end;
        Ok(slice)
    }

    fn word(&mut self) -> Result<u32, String> {
        let w = self.take(4)?;
        Ok(u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
    }

    /// `n` words, refused before allocating when the bytes cannot hold them.
    fn words(&mut self, n: usize) -> Result<Vec<u32>, String> {
        let bytes = self.take(n.checked_mul(4).ok_or(MALFORMED)?)?;
        Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
    }
}

/// The separate module's entry point (feature `js`).
#[cfg(feature = "js")]
pub mod js {
    use wasm_bindgen::prelude::*;

    /// Decodes one Draco stream: `request` is [`super::Request::to_words`], the result
    /// [`super::write_answer`]'s bytes (an undecodable stream is an answer, never a throw).
    #[wasm_bindgen]
    pub fn decode(stream: &[u8], request: &[u32]) -> Vec<u8> {
        let answer = match super::Request::from_words(request) {
            Some(request) => super::decode(stream, &request),
            None => Err(super::DecodeError::Invalid("the request is malformed".into())),
        };
        super::write_answer(&answer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn requests_and_answers_cross_the_boundary_unchanged() {
        let request = Request {
            max_points: 1 << 40,
            max_faces: 7,
            max_decoded_bytes: u64::MAX,
            attributes: vec![(3, 2), (0, 4)],
        };
        assert_eq!(Request::from_words(&request.to_words()), Some(request));
        assert_eq!(Request::from_words(&[1, 0, 2, 0, 3, 0, 1, 5]), None);
        let decoded = Decoded {
            faces: vec![0, 1, 2, 2, 1, 3],
            points: 4,
            attributes: vec![None, Some(Attribute { float: true, values: vec![0.5, -1.0, 2.0, 3.0] })],
        };
        for answer in
            [Ok(decoded), Err(DecodeError::LimitExceeded), Err(DecodeError::Invalid("short".into()))]
        {
            let bytes = write_answer(&answer);
            assert_eq!(read_answer(&bytes), Ok(answer.clone()));
            // Cut anywhere, or with a byte more, it is malformed: never a wrong mesh or a panic.
            for cut in 0..bytes.len() {
                assert!(read_answer(&bytes[..cut]).is_err(), "cut at {cut}");
            }
            if answer.is_ok() {
                assert!(read_answer(&[&bytes[..], &[0]].concat()).is_err());
            }
        }
        // A count beyond the bytes is refused before anything is allocated for it.
        assert!(read_answer(&[0, 0, 0, 0, 1, 0, 0, 0, 255, 255, 255, 255]).is_err());
    }

    #[cfg(feature = "decoder")]
    #[test]
    fn a_stream_that_is_not_draco_is_invalid() {
        let request = Request { max_points: 10, max_faces: 10, max_decoded_bytes: 1000, attributes: vec![] };
        assert!(matches!(decode(b"not a draco stream", &request), Err(DecodeError::Invalid(_))));
    }
}
