//! Animations (glTF 2.0 §3.11) as [`Clip`]s over the skeleton's nodes.
//!
//! Each channel becomes one [`Curve`]: key times from the sampler's input (seconds), values from
//! its output (floats, or for rotations normalized integers as §3.11 allows). Rotation keys are
//! normalized (writers store them with rounding error; a zero-length key is an error). Channels
//! on nodes outside the skeleton drive nothing we draw and are dropped. A `weights` channel of
//! `N` weights becomes `N` scalar curves (`CUBICSPLINE` keys hold `N` in-tangents, `N` values,
//! `N` out-tangents), each driving the global morph targets of that weight index; one on a node
//! without imported morph targets is dropped with a warning.

use std::collections::HashMap;

use super::document::{self, Interpolation as JsonInterpolation, Property, Type};
use glam::{Quat, Vec3};

use super::accessor::{read_floats, Source};
use super::scene::node_name;
use super::{ImportError, MAX_KEYS};
use crate::animation::{Channel, ChannelCurve, Clip, Curve, CurveError, Interpolation};

/// Every animation of the file, in file order; clips are named by the file or `clip <index>`.
///
/// # Errors
/// Bad accessors, or keys that do not make a valid curve (named by clip and channel).
pub(crate) fn read_clips(
    src: Source,
    slots: &[Option<usize>],
    morph_by_node: &HashMap<usize, Vec<Vec<u32>>>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Clip>, ImportError> {
    let mut clips = Vec::with_capacity(src.root.animations.len());
    for (a, anim) in src.root.animations.iter().enumerate() {
        let name = anim.name.clone().unwrap_or_else(|| format!("clip {a}"));
        let mut channels = Vec::new();
        let mut dropped_weights = false;
        for (c, channel) in anim.channels.iter().enumerate() {
            let (node, property) = (channel.node, channel.path);
            let morph_targets = morph_by_node.get(&node);
            if property == Property::MorphTargetWeights && morph_targets.is_none() {
                dropped_weights = true;
                continue;
            }
            let Some(slot) = slots.get(node).copied().flatten() else { continue };
            let to = ChannelTarget { clip: &name, index: c, node, slot, property, morph_targets };
            read_channel(src, anim, channel, &to, &mut channels)?;
        }
        if dropped_weights {
            warnings.push(format!(
                "animation '{name}' animates morph weights of a node without imported morph targets; \
                 those channels are dropped"
            ));
        }
        clips.push(Clip::new(name, channels));
    }
    Ok(clips)
}

/// Where a channel writes: its clip and index (for messages), the node it animates and that
/// node's skeleton slot, the property, and the node's morph targets by weight index (for a
/// `weights` channel, which the caller drops for a node without them).
struct ChannelTarget<'a> {
    clip: &'a str,
    index: usize,
    node: usize,
    slot: usize,
    property: Property,
    morph_targets: Option<&'a Vec<Vec<u32>>>,
}

/// Reads one channel's sampler into `out`: one [`Channel`], or one per weight for a `weights`
/// channel.
///
/// # Errors
/// A missing sampler or unknown interpolation, bad accessors, or keys that make no valid curve.
fn read_channel(
    src: Source,
    anim: &document::Animation,
    channel: &document::Channel,
    to: &ChannelTarget,
    out: &mut Vec<Channel>,
) -> Result<(), ImportError> {
    let (clip, c) = (to.clip, to.index);
    // The reader checked the sampler index against the animation's samplers.
    let sampler = &anim.samplers[channel.sampler];
    let interpolation = match sampler.interpolation {
        JsonInterpolation::Step => Interpolation::Step,
        JsonInterpolation::Linear => Interpolation::Linear,
        JsonInterpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let target = format!("{} of node '{}'", property_name(to.property), node_name(src.root, to.node));
    let usage = |what: &str| format!("{what} of animation '{clip}' channel {c}");
    let times = read_floats(src, sampler.input, &usage("key times"), &[Type::Scalar], MAX_KEYS)?;
    // Cubic splines store in-tangent, value and out-tangent per key.
    let max_values = if interpolation == Interpolation::CubicSpline { 3 * MAX_KEYS } else { MAX_KEYS };
    let curve_error = |source: CurveError| ImportError::Animation {
        clip: clip.to_string(),
        channel: c,
        target: target.clone(),
        source,
    };
    let key_values =
        |kind: Type, max: usize| read_floats(src, sampler.output, &usage("key values"), &[kind], max);
    let curve = match to.property {
        Property::Translation | Property::Scale => {
            let values =
                key_values(Type::Vec3, max_values)?.values.chunks_exact(3).map(Vec3::from_slice).collect();
            let curve = Curve::new(times.values, values, interpolation).map_err(curve_error)?;
            match to.property {
                Property::Translation => ChannelCurve::Translation(curve),
                _ => ChannelCurve::Scale(curve),
            }
        }
        Property::Rotation => {
            let values = rotation_keys(&key_values(Type::Vec4, max_values)?.values, interpolation)
                .map_err(curve_error)?;
            ChannelCurve::Rotation(Curve::new(times.values, values, interpolation).map_err(curve_error)?)
        }
        Property::MorphTargetWeights => {
            let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
            let targets = to.morph_targets.expect("the caller drops weights of nodes without targets");
            // Any number of weights per key: bounded by the targets the node has.
            let values = key_values(Type::Scalar, max_values.saturating_mul(targets.len().max(1)))?.values;
            let keys = times.values.len();
            let weights = values.len().checked_div(keys * per_key).unwrap_or(0);
            if weights == 0 || weights * keys * per_key != values.len() {
                return Err(curve_error(CurveError::CountMismatch {
                    times: keys,
                    values: values.len(),
                    expected: keys * per_key * targets.len(),
                }));
            }
            for (k, driven) in targets.iter().enumerate().take(weights) {
                let weight_values = weight_keys(&values, weights, k, per_key);
                let curve =
                    Curve::new(times.values.clone(), weight_values, interpolation).map_err(curve_error)?;
                out.push(Channel {
                    node: to.slot,
                    curve: ChannelCurve::MorphWeight { targets: driven.clone(), curve },
                });
            }
            return Ok(());
        }
    };
    out.push(Channel { node: to.slot, curve });
    Ok(())
}

fn property_name(p: Property) -> &'static str {
    match p {
        Property::Translation => "translation",
        Property::Rotation => "rotation",
        Property::Scale => "scale",
        Property::MorphTargetWeights => "weights",
    }
}

/// The keys of weight `k` out of a `weights` sampler's output with `n` weights per value:
/// `per_key` values per key (3 for cubic splines: in-tangent, value, out-tangent blocks of `n`).
fn weight_keys(values: &[f32], n: usize, k: usize, per_key: usize) -> Vec<f32> {
    // Blocks of `n` run key by key (and within a cubic key, in-tangents, values, out-tangents),
    // which is the order [`Curve`] wants for one weight.
    debug_assert!(values.len() % (n * per_key) == 0);
    values.chunks_exact(n).map(|block| block[k]).collect()
}

/// Smallest rotation key length we normalize; shorter keys carry no direction.
const MIN_QUAT_LENGTH: f32 = 1e-6;

/// Rotation keys as quaternions, key values normalized (cubic tangents are left as they are).
fn rotation_keys(xyzw: &[f32], interpolation: Interpolation) -> Result<Vec<Quat>, CurveError> {
    xyzw.chunks_exact(4)
        .enumerate()
        .map(|(k, c)| {
            let q = Quat::from_xyzw(c[0], c[1], c[2], c[3]);
            let is_value = interpolation != Interpolation::CubicSpline || k % 3 == 1;
            if !is_value {
                return Ok(q);
            }
            if !q.is_finite() {
                return Err(CurveError::NonFiniteValue);
            }
            if q.length() < MIN_QUAT_LENGTH {
                return Err(CurveError::ZeroRotation);
            }
            Ok(q.normalize())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_values_are_normalized_but_tangents_are_not() {
        let keys = rotation_keys(
            &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 4.0],
            Interpolation::CubicSpline,
        )
        .unwrap();
        assert_eq!(
            keys,
            vec![Quat::from_xyzw(0.0, 0.0, 0.0, 2.0), Quat::IDENTITY, Quat::from_xyzw(0.0, 0.0, 0.0, 4.0)]
        );
        assert_eq!(rotation_keys(&[0.0; 4], Interpolation::Linear), Err(CurveError::ZeroRotation));
    }
}
