//! Hand-made streams with exact results for each codec and filter, the specification's own
//! example, and corrupt or random input (errors, never panics).

use super::*;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

/// A version 0 attribute stream of `count` elements of `stride` bytes whose data blocks are the
/// given `(header bytes, group bytes)` per byte of the element, then `baseline` in the tail.
fn attribute_stream(stride: usize, blocks: &[(&[u8], &[u8])], baseline: &[u8]) -> Vec<u8> {
    let mut out = vec![VERTEX_HEADER_V0];
    for (headers, groups) in blocks {
        out.extend_from_slice(headers);
        out.extend_from_slice(groups);
    }
    out.resize(out.len() + stride.max(TAIL_MIN) - stride, 0);
    out.extend_from_slice(baseline);
    out
}

#[test]
fn the_specifications_four_bit_example_decodes_to_its_deltas() {
    let bytes = [0x17, 0x5f, 0xf0, 0xbc, 0x77, 0xa9, 0x21, 0x00, 0x34, 0xb5];
    let mut reader = Reader { bytes: &bytes, at: 0 };
    let mut deltas = [0u8; 16];
    decode_group(&mut reader, 4, &mut deltas).unwrap();
    let signed: Vec<i8> = deltas.iter().map(|&d| unzigzag8(d) as i8).collect();
    assert_eq!(signed, [-1, -4, -3, 26, -91, 0, -6, 6, -4, -4, 5, -5, 1, -1, 0, 0]);
    assert_eq!(reader.at, bytes.len(), "both sentinel bytes read");
}

#[test]
fn two_bit_groups_read_most_significant_bits_first() {
    // Deltas 0, +1 (zigzag 2), -1 (zigzag 1), then a sentinel whose byte is +3 (zigzag 6).
    let bytes = [0b00_10_01_11, 0, 0, 0, 6];
    let mut reader = Reader { bytes: &bytes, at: 0 };
    let mut deltas = [0u8; 16];
    decode_group(&mut reader, 2, &mut deltas).unwrap();
    assert_eq!(&deltas[..4], &[0, 2, 1, 6]);
    assert_eq!(reader.at, 5);
}

#[test]
fn an_attribute_stream_adds_deltas_to_the_baseline_byte_by_byte() {
    // Two elements of 4 bytes. Byte 0: raw deltas +1, +2 (zigzag 2, 4); bytes 1-3: no change.
    let mut raw = [0u8; 16];
    raw[..2].copy_from_slice(&[2, 4]);
    let blocks: [(&[u8], &[u8]); 4] = [(&[3], &raw), (&[0], &[]), (&[0], &[]), (&[0], &[])];
    let stream = attribute_stream(4, &blocks, &[10, 20, 30, 40]);
    let mut out = [0u8; 8];
    decode_vertex_buffer(&mut out, 2, 4, &stream, false).unwrap();
    assert_eq!(out, [11, 20, 30, 40, 13, 20, 30, 40]);
    // Deltas wrap around in 8 bits: -1 from 0 is 255.
    let blocks: [(&[u8], &[u8]); 4] =
        [(&[1], &[0b01_00_00_00, 0, 0, 0]), (&[0], &[]), (&[0], &[]), (&[0], &[])];
    let stream = attribute_stream(4, &blocks, &[0, 0, 0, 0]);
    let mut out = [0u8; 4];
    decode_vertex_buffer(&mut out, 1, 4, &stream, false).unwrap();
    assert_eq!(out, [255, 0, 0, 0]);
}

/// A version 1 stream of one 4-byte element whose bytes are all literal, with channel mode `mode`.
fn v1_single_element(deltas: [u8; 4], baseline: [u8; 4], mode: u8) -> Vec<u8> {
    let mut out = vec![VERTEX_HEADER_V1, 0xff]; // control 3 (literal) for all four bytes
    out.extend_from_slice(&deltas); // one byte each: literal blocks hold the block's elements only
    out.resize(out.len() + TAIL_MIN_V1 - 5, 0);
    out.extend_from_slice(&baseline);
    out.push(mode);
    out
}

#[test]
fn version_1_channels_decode_16_bit_deltas_and_rotated_xor() {
    let mut out = [0u8; 4];
    // Mode 1: two 16-bit zigzag deltas, +1 (2) and -1 (1), from 1000 and 2000.
    let base = [1000u16.to_le_bytes(), 2000u16.to_le_bytes()].concat();
    let stream = v1_single_element([2, 0, 1, 0], base.try_into().unwrap(), 1);
    decode_vertex_buffer(&mut out, 1, 4, &stream, true).unwrap();
    assert_eq!(out, [1001u16.to_le_bytes(), 1999u16.to_le_bytes()].concat()[..]);
    // Mode 2 with rotation 8: the value is the previous one XOR the delta rotated right by 8
    // (checked against gltfpack's -cz output, whose float animation times use this mode).
    let stream = v1_single_element([0xff, 0, 0, 0], 0x1122_3344u32.to_le_bytes(), 0x82);
    decode_vertex_buffer(&mut out, 1, 4, &stream, true).unwrap();
    assert_eq!(u32::from_le_bytes(out), 0xee22_3344);
    // Mode 0 is version 0's byte deltas.
    let stream = v1_single_element([2, 1, 0, 0], [5, 5, 5, 5], 0);
    decode_vertex_buffer(&mut out, 1, 4, &stream, true).unwrap();
    assert_eq!(out, [6, 4, 5, 5]);
}

#[test]
fn one_bit_groups_read_least_significant_bits_first() {
    // In one bit the only non-zero value is the sentinel: delta 0 is the byte after the bits.
    let bytes = [0b0000_0001, 0, 4];
    let mut reader = Reader { bytes: &bytes, at: 0 };
    let mut deltas = [0u8; 16];
    decode_group(&mut reader, 1, &mut deltas).unwrap();
    assert_eq!(&deltas[..4], &[4, 0, 0, 0]);
    let bytes = [0b0000_0110, 0, 4, 9];
    let mut reader = Reader { bytes: &bytes, at: 0 };
    decode_group(&mut reader, 1, &mut deltas).unwrap();
    assert_eq!(&deltas[..4], &[0, 4, 9, 0]);
    assert_eq!(reader.at, 4);
}

#[test]
fn attribute_blocks_hold_at_most_256_elements_or_8_kib() {
    assert_eq!(block_elements(4), 256);
    assert_eq!(block_elements(64), 128);
    assert_eq!(block_elements(256), 32);
    assert_eq!(block_elements(12), 256);
}

#[test]
fn a_triangle_stream_reuses_edges_from_its_fifo() {
    // Triangle (0, 1, 2) from three new vertices (0xfe with Z = W = 0; the data byte 0 also
    // resets `next`), then (2, 1, 3) on its edge (2, 1), the second most recent (0x10).
    let mut stream = vec![TRIANGLE_HEADER, 0xfe, 0x10, 0x00];
    stream.extend_from_slice(&[0; 16]);
    let mut out = [0u8; 12];
    decode_index_buffer(&mut out, 6, 2, &stream).unwrap();
    let indices: Vec<u16> = out.chunks_exact(2).map(|b| u16::from_le_bytes([b[0], b[1]])).collect();
    assert_eq!(indices, [0, 1, 2, 2, 1, 3]);
}

#[test]
fn explicit_triangle_indices_are_zigzag_deltas_from_the_last() {
    // 0xff: a explicit (+7: zigzag 14), b explicit (-2: zigzag 3), c new (next = 0); Z = 15, W = 0.
    let mut stream = vec![TRIANGLE_HEADER, 0xff, 0xf0, 14, 3];
    stream.extend_from_slice(&[0; 16]);
    let mut out = [0u8; 12];
    decode_index_buffer(&mut out, 3, 4, &stream).unwrap();
    let indices: Vec<u32> =
        out.chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    assert_eq!(indices, [7, 5, 0]);
}

#[test]
fn an_index_sequence_follows_two_baselines() {
    // +5 and +1 on baseline 0, +100 on baseline 1, -4 on baseline 0.
    let mut stream = vec![SEQUENCE_HEADER, 5 << 2, 1 << 2];
    stream.extend_from_slice(&[0x91, 0x03]); // (100 << 2) | 1 = 401 as LEB128
    stream.push((3 << 2) | 2);
    stream.extend_from_slice(&[0; 4]);
    let mut out = [0u8; 16];
    decode_index_sequence(&mut out, 4, 4, &stream).unwrap();
    let indices: Vec<u32> =
        out.chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    assert_eq!(indices, [5, 6, 100, 2]);
}

#[test]
fn filters_decode_their_exact_cases() {
    // Octahedral: +z, and -z through the fold of the lower hemisphere (x = 1, y = 0 with one = 1
    // gives z = 0: the equator at +x).
    assert_eq!(octahedral([0.0, 0.0, 127.0], 127.0), [0.0, 0.0, 127.0]);
    assert_eq!(octahedral([127.0, 0.0, 127.0], 127.0), [127.0, 0.0, 0.0]);
    assert_eq!(octahedral([0.0, 0.0, 32767.0], 32767.0), [0.0, 0.0, 32767.0]);
    // Quaternion: the identity with w the omitted largest component (index 3), 16 bits.
    assert_eq!(quaternion([0, 0, 0, 32767]), [0, 0, 0, 32767]);
    // A 90° turn about x, x = w = √½, with x (index 0) omitted: the stored triple is (y, z, w),
    // each × √2 in units of `one`, so w is stored as `one` itself.
    let s = (32767.0 * std::f32::consts::FRAC_1_SQRT_2 * std::f32::consts::SQRT_2).round() as i16;
    let q = quaternion([0, 0, s, (32767 & !3)]);
    assert_eq!(q, [23170, 0, 0, 23170]);
    // Colour (YCoCg, K = 8, alpha's marker bit 7): grey 128 opaque, and red 252 (Y 63, Co 126,
    // Cg -63) with alpha 63 of 127, expanded to 127 of 255.
    assert_eq!(color([128, 0, 0, -1], 255, 255.0), [128.0, 128.0, 128.0, 255.0]);
    assert_eq!(color([63, 126, -63, 0], 0x80 | 63, 255.0), [252.0, 0.0, 0.0, 127.0]);
    // Exponential: 6 · 2⁻² and -3 · 2⁴.
    assert_eq!(exponential((-2i32 << 24) | 6), 1.5);
    assert_eq!(exponential((4 << 24) | (-3i32 & 0x00ff_ffff)), -48.0);
}

#[test]
fn corrupt_streams_are_errors() {
    let mut out = [0u8; 8];
    assert!(decode_vertex_buffer(&mut out, 2, 4, &[VERTEX_HEADER_V0; 10], false).is_err(), "too short");
    let good = attribute_stream(4, &[(&[0], &[]), (&[0], &[]), (&[0], &[]), (&[0], &[])], &[1, 2, 3, 4]);
    decode_vertex_buffer(&mut out, 2, 4, &good, false).unwrap();
    let mut extra = good.clone();
    extra.insert(5, 0);
    assert!(decode_vertex_buffer(&mut out, 2, 4, &extra, false).is_err(), "bytes after the last block");
    let mut v1 = good.clone();
    v1[0] = 0xa1;
    assert!(decode_vertex_buffer(&mut out, 2, 4, &v1, false).is_err(), "version 1 is KHR's");
    let mut mode = good.clone();
    *mode.last_mut().unwrap() = 3; // in a version 1 stream this byte is the channel mode
    mode[0] = VERTEX_HEADER_V1;
    assert!(decode_vertex_buffer(&mut out, 2, 4, &mode, true).is_err(), "channel mode 3 is unknown");
    // A triangle that needs more data than there is.
    let mut stream = vec![TRIANGLE_HEADER, 0x0f];
    stream.extend_from_slice(&[0; 16]);
    assert!(decode_index_buffer(&mut [0u8; 6], 3, 2, &stream).is_err());
    // An index over 65535 in a 16-bit buffer.
    let mut stream = vec![SEQUENCE_HEADER, 0x80, 0x80, 0x10];
    stream.extend_from_slice(&[0; 4]);
    assert!(decode_index_sequence(&mut [0u8; 2], 1, 2, &stream).is_err());
}

#[test]
fn random_bytes_never_panic() {
    let mut rng = crate::metrics::SplitMix64(7);
    for round in 0..2000 {
        let len = rng.below(300);
        let mut bytes: Vec<u8> = (0..len).map(|_| rng.next_u64() as u8).collect();
        if let Some(first) = bytes.first_mut() {
            *first = [VERTEX_HEADER_V0, TRIANGLE_HEADER, SEQUENCE_HEADER][round % 3];
        }
        let count = 3 * rng.below(40);
        let stride = [4, 8, 12][rng.below(3)];
        let mut out = vec![0u8; count * stride];
        let _ = decode_vertex_buffer(&mut out, count, stride, &bytes, round % 2 == 0);
        let mut out = vec![0u8; count * 4];
        let _ = decode_index_buffer(&mut out, count, 4, &bytes);
        let _ = decode_index_sequence(&mut out, count, 4, &bytes);
        let mut out = vec![0u8; count * 2];
        let _ = decode_index_buffer(&mut out, count, 2, &bytes);
    }
}

#[test]
fn extension_objects_follow_the_specifications_rules() {
    let json = |s: &str| -> Value { serde_json::from_str(s).unwrap() };
    let ok = parse(
        &json(
            r#"{"buffer": 0, "byteLength": 9, "byteStride": 8, "count": 2, "mode": "ATTRIBUTES", "filter": "QUATERNION"}"#,
        ),
        false,
    );
    assert_eq!(ok.unwrap().filter, Filter::Quaternion);
    for bad in [
        r#"{"buffer": 0, "byteLength": 9, "byteStride": 6, "count": 2, "mode": "ATTRIBUTES"}"#,
        r#"{"buffer": 0, "byteLength": 9, "byteStride": 4, "count": 2, "mode": "ATTRIBUTES", "filter": "QUATERNION"}"#,
        r#"{"buffer": 0, "byteLength": 9, "byteStride": 2, "count": 4, "mode": "TRIANGLES"}"#,
        r#"{"buffer": 0, "byteLength": 9, "byteStride": 2, "count": 3, "mode": "TRIANGLES", "filter": "OCTAHEDRAL"}"#,
        r#"{"buffer": 0, "byteLength": 9, "byteStride": 2, "count": 3, "mode": "STRIPS"}"#,
        r#"{"buffer": 0, "byteStride": 4, "count": 3, "mode": "INDICES"}"#,
    ] {
        assert!(parse(&json(bad), false).is_err(), "{bad}");
    }
}
