//! `buildClod(options)` and `buildClodBytes(options)`: the options object as a Rust type, read with
//! serde ([`super::read`]), and turned into the core's [`ClodOptions`]. Every key is optional; a
//! key this type does not have, or a value of the wrong kind, is an error naming the key and what
//! it accepts.

use std::fmt;

use serde::de::{self, Deserialize, Deserializer, MapAccess, Visitor};
use serde::Serialize;

use super::read::{Accepts, Got, Leaf, List, Names, Number, OneOf, Take, Text};
use crate::character::Character;
use crate::clod::{poses::DEFAULT_FRAMES_PER_CLIP, ClodOptions, SimplificationPose, WeightRule};
use crate::simplify::{CollapseMode, Schedule};

/// The options of `buildClod` and `buildClodBytes` (see [`super::Character::build_clod`]).
#[derive(Default, serde::Deserialize, Serialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct BuildOptions {
    /// `'multi'` (default), `'mid-clip'`, `'bind'` or `{ clip, time }`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pose: Option<Pose>,
    /// Decreasing triangle counts of the levels.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub levels: Option<List<TriangleCount>>,
    /// `'full'` (default) or `'halfedge'`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode: Option<OneOf<CollapseMode>>,
    /// `'blend'` (default) or `'survivor'`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weights: Option<OneOf<WeightRule>>,
    /// `'strict'` (default) or `'passes'`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub schedule: Option<OneOf<Schedule>>,
    /// The floor, a positive fraction of the diagonal (`Infinity`: as far as the topology allows).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_error: Option<Number>,
    /// Called with fractions from 0 to 1.
    #[serde(skip_serializing)]
    pub on_progress: Option<Callback>,
}

impl BuildOptions {
    /// The core's options for `character` (whose clips a `{ clip, time }` pose must name).
    ///
    /// # Errors
    /// A clip the character does not have, or a `maxError` that is not a positive fraction.
    pub fn clod_options(&self, character: &Character) -> Result<ClodOptions, String> {
        let mut out = ClodOptions::default();
        match &self.pose {
            None => {}
            Some(Pose::Named(OneOf(pose))) => out.pose = pose.pose(),
            Some(Pose::ClipFrame { clip, time }) => {
                if character.clip(clip).is_none() {
                    return Err(format!(
                        "buildClod: pose.clip: {}",
                        super::unknown_clip_message(character, clip)
                    ));
                }
                out.pose = SimplificationPose::ClipFrame { clip: clip.clone(), time: *time as f32 };
            }
        }
        if let Some(List(counts)) = &self.levels {
            out.level_triangles = Some(counts.iter().map(|c| c.0 as usize).collect());
        }
        if let Some(OneOf(mode)) = self.mode {
            out.mode = mode;
        }
        if let Some(OneOf(weights)) = self.weights {
            out.weights = weights;
        }
        if let Some(OneOf(schedule)) = self.schedule {
            out.schedule = schedule;
        }
        if let Some(Number(e)) = self.max_error {
            if e <= 0.0 {
                return Err(format!(
                    "buildClod: maxError must be a positive fraction of the diagonal (Infinity: no floor), got {}",
                    super::read::js_number(e)
                ));
            }
            out.max_relative_error = e as f32;
        }
        Ok(out)
    }
}

/// The simplification pose: a name, or a clip frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Pose {
    Named(OneOf<PoseName>),
    ClipFrame { clip: String, time: f64 },
}

/// The poses that go by a name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PoseName {
    Multi,
    MidClip,
    Bind,
}

impl PoseName {
    fn pose(self) -> SimplificationPose {
        match self {
            PoseName::Multi => SimplificationPose::MultiPose { frames_per_clip: DEFAULT_FRAMES_PER_CLIP },
            PoseName::MidClip => SimplificationPose::MidClip,
            PoseName::Bind => SimplificationPose::Bind,
        }
    }
}

impl Names for PoseName {
    const NAMES: &'static [&'static str] = &["multi", "mid-clip", "bind"];
    fn named(name: &str) -> Option<Self> {
        [PoseName::Multi, PoseName::MidClip, PoseName::Bind].into_iter().find(|p| p.name() == name)
    }
    fn name(self) -> &'static str {
        match self {
            PoseName::Multi => "multi",
            PoseName::MidClip => "mid-clip",
            PoseName::Bind => "bind",
        }
    }
}

impl Accepts for Pose {
    fn accepts() -> String {
        format!("{} or {{ clip, time }}", OneOf::<PoseName>::accepts())
    }
}

struct PoseVisitor;

impl<'de> Visitor<'de> for PoseVisitor {
    type Value = Pose;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&Pose::accepts())
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Pose, E> {
        PoseName::named(v)
            .map(|p| Pose::Named(OneOf(p)))
            .ok_or_else(|| E::custom(format_args!("must be {}, got {v:?}", Pose::accepts())))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Pose, A::Error> {
        let (mut clip, mut time) = (None, None);
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "clip" => clip = Some(map.next_value::<Text>()?.0),
                "time" => time = Some(map.next_value::<Number>()?.0),
                other => {
                    return Err(de::Error::custom(format_args!(
                        "must be {{ clip, time }}: unknown field {other:?}"
                    )))
                }
            }
        }
        match (clip, time) {
            (Some(clip), Some(time)) if time.is_finite() => Ok(Pose::ClipFrame { clip, time }),
            _ => {
                Err(de::Error::custom("must be { clip, time } with a clip name and a finite time in seconds"))
            }
        }
    }
}

impl<'de> Deserialize<'de> for Pose {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(PoseVisitor)
    }
}

impl Serialize for Pose {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        match self {
            Pose::Named(name) => name.serialize(s),
            Pose::ClipFrame { clip, time } => {
                let mut frame = s.serialize_struct("ClipFrame", 2)?;
                frame.serialize_field("clip", clip)?;
                frame.serialize_field("time", time)?;
                frame.end()
            }
        }
    }
}

/// A level's triangle count: a whole number, at least 1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct TriangleCount(pub u32);

impl Accepts for TriangleCount {
    fn accepts() -> String {
        "a whole number of triangles ≥ 1".into()
    }
}

impl Take for TriangleCount {
    fn take(got: &Got<'_>) -> Option<Self> {
        match *got {
            Got::Number(n) if n >= 1.0 && n.fract() == 0.0 && n <= f64::from(u32::MAX) => {
                Some(TriangleCount(n as u32))
            }
            _ => None,
        }
    }
}

impl<'de> Deserialize<'de> for TriangleCount {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(Leaf::<TriangleCount>::new())
    }
}

/// A JavaScript function (kept as it is: serde-wasm-bindgen hands it over untouched).
pub struct Callback(pub js_sys::Function);

impl<'de> Deserialize<'de> for Callback {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use wasm_bindgen::JsCast;
        let value: wasm_bindgen::JsValue = serde_wasm_bindgen::preserve::deserialize(d)?;
        value.dyn_into().map(Callback).map_err(|v| {
            de::Error::custom(format_args!(
                "must be a function, got {}",
                v.js_typeof().as_string().unwrap_or_default()
            ))
        })
    }
}

impl Names for CollapseMode {
    const NAMES: &'static [&'static str] = &["full", "halfedge"];
    fn named(name: &str) -> Option<Self> {
        [CollapseMode::Full, CollapseMode::HalfEdge].into_iter().find(|m| m.name() == name)
    }
    fn name(self) -> &'static str {
        match self {
            CollapseMode::Full => "full",
            CollapseMode::HalfEdge => "halfedge",
        }
    }
}

impl Names for WeightRule {
    const NAMES: &'static [&'static str] = &["blend", "survivor"];
    fn named(name: &str) -> Option<Self> {
        [WeightRule::Blend, WeightRule::Survivor].into_iter().find(|w| w.name() == name)
    }
    fn name(self) -> &'static str {
        match self {
            WeightRule::Blend => "blend",
            WeightRule::Survivor => "survivor",
        }
    }
}

impl Names for Schedule {
    const NAMES: &'static [&'static str] = &["strict", "passes"];
    fn named(name: &str) -> Option<Self> {
        [Schedule::Strict, Schedule::Passes].into_iter().find(|s| s.name() == name)
    }
    fn name(self) -> &'static str {
        match self {
            Schedule::Strict => "strict",
            Schedule::Passes => "passes",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::js_api::read::read_json;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn read(json: &str) -> Result<BuildOptions, String> {
        read_json("buildClod", json)
    }

    #[test]
    fn every_option_reads() {
        let o = read(
            r#"{"pose":{"clip":"Walk","time":0.5},"levels":[400,200],"mode":"halfedge","weights":"survivor","schedule":"passes","maxError":0.1}"#,
        )
        .unwrap();
        assert_eq!(o.pose, Some(Pose::ClipFrame { clip: "Walk".into(), time: 0.5 }));
        assert_eq!(o.levels.unwrap().0, [TriangleCount(400), TriangleCount(200)]);
        assert_eq!(
            (o.mode, o.weights),
            (Some(OneOf(CollapseMode::HalfEdge)), Some(OneOf(WeightRule::Survivor)))
        );
        assert_eq!((o.schedule, o.max_error), (Some(OneOf(Schedule::Passes)), Some(Number(0.1))));
        assert_eq!(read(r#"{"pose":"mid-clip"}"#).unwrap().pose, Some(Pose::Named(OneOf(PoseName::MidClip))));
    }

    #[test]
    fn unknown_and_ill_typed_keys_name_the_key_and_what_it_takes() {
        let unknown = read(r#"{"level":[100]}"#).err().unwrap();
        assert!(
            unknown.starts_with("buildClod: unknown field `level`, expected one of `pose`, `levels`"),
            "{unknown}"
        );
        assert_eq!(
            read(r#"{"mode":"quarter"}"#).err().unwrap(),
            r#"buildClod: mode must be one of "full", "halfedge", got "quarter""#
        );
        assert_eq!(
            read(r#"{"levels":[400,1.5]}"#).err().unwrap(),
            "buildClod: levels[1] must be a whole number of triangles ≥ 1, got 1.5"
        );
        assert_eq!(
            read(r#"{"levels":400}"#).err().unwrap(),
            "buildClod: levels must be an array, each item a whole number of triangles ≥ 1, got 400"
        );
        assert_eq!(
            read(r#"{"pose":"sideways"}"#).err().unwrap(),
            r#"buildClod: pose must be one of "multi", "mid-clip", "bind" or { clip, time }, got "sideways""#
        );
        assert_eq!(
            read(r#"{"pose":{"clip":"Walk","time":"soon"}}"#).err().unwrap(),
            r#"buildClod: pose.time must be a number, got "soon""#
        );
        assert_eq!(
            read(r#"{"maxError":"low"}"#).err().unwrap(),
            r#"buildClod: maxError must be a number, got "low""#
        );
    }
}
