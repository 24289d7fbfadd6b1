//! The page's two presets: the **demonstration** it opens with, whose settings are exaggerated so
//! that a reader sees a change of level in every view within seconds, and the **realistic** one,
//! the engine's own defaults (half a pixel of screen-space error, real size, real-time
//! transitions), where a good LOD chain changes nothing a reader can see.
//!
//! At the realistic 0.5 px the built-in character's level changes are far below a pixel (the
//! live meter measured popping's silhouette pop at 0.005–0.009 % of a 400-px view). A pop's area
//! grows with the square of the magnified error (`magnify × tolerance`): at 2 px and ×2 the first
//! transition popped 0.22 % of the view, at 2.4 px and ×2 the switch to the coarsest level
//! happens at 1.14 framing distances in a 400-px view (the character 1.76× its framed size) and
//! pops about 0.4 %. The demonstration's threshold is per 400 px of view height, so the same
//! switches fall at the same distances in any window. So the demonstration allows 4.8× the error (2.4 px), enlarges the views 2×
//! about the point looked at, slows the transitions 4× (2 s instead of 0.5 s) and runs the dolly
//! twice as fast (8 s a sweep: on a software rasterizer drawing 3 frames a second, the first
//! switch then comes 12 frames after the levels arrive rather than 23), with the difference
//! overlay on. The threshold stays under the coarsest level's switch at the framing
//! distance (2.48 px in a 400-px view), so the dolly, which sweeps out from the framing distance,
//! crosses it both ways. Every view still shows the same level at the same moment; only
//! the method differs. Pure data: applied through [`Update`] like any `setState`, and each value
//! reported with its realistic counterpart so the page can say what is exaggerated.

use super::settings::{Settings, Update};
use crate::render::overlay::Overlay;

/// A named set of settings (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    Demonstration,
    Realistic,
}

/// The page's names of the presets.
pub const PRESET_NAMES: [&str; 2] = ["demonstration", "realistic"];

/// One setting a preset sets: its `setState` key, what it means to a reader, and its values in
/// the demonstration and in the realistic preset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PresetValue {
    pub key: &'static str,
    pub label: &'static str,
    pub demonstration: f32,
    pub realistic: f32,
}

/// Overlay of the demonstration: the difference from full detail, tinted.
const DEMONSTRATION_OVERLAY: Overlay = Overlay::Difference;

/// The view height the demonstration's threshold is given for: it scales with the view, so the
/// demonstration shows the same switches at the same distances in any window (in a 290-px view a
/// fixed 2.4 px put every switch inside the framing distance, and the dolly crossed none).
pub const DEMONSTRATION_HEIGHT: f32 = 400.0;

/// The threshold: the screen-space error at which a level switches.
const THRESHOLD: PresetValue = PresetValue {
    key: "tolerance",
    label: "screen-space error allowed before a coarser level is used (px; the demonstration's per 400 px of view height)",
    demonstration: 2.4,
    realistic: 0.5,
};

/// The numeric settings the presets differ in, in the order the page lists them. The overlay
/// (difference in the demonstration, none in the realistic preset) comes on top.
pub const PRESET_VALUES: [PresetValue; 4] = [
    THRESHOLD,
    PresetValue {
        key: "magnify",
        label: "magnifier about the point looked at (levels still chosen for the real size)",
        demonstration: 2.0,
        realistic: 1.0,
    },
    PresetValue {
        key: "transitionSpeed",
        label: "speed of the transitions (the animation and the dolly keep their pace)",
        demonstration: 0.25,
        realistic: 1.0,
    },
    PresetValue {
        key: "dollyPeriod",
        label: "seconds the automatic dolly takes out and back",
        demonstration: 8.0,
        realistic: 16.0,
    },
];

impl PresetValue {
    /// The value `s` has for this setting now.
    pub fn current(&self, s: &Settings) -> f32 {
        match self.key {
            "tolerance" => s.tolerance_px,
            "magnify" => s.magnify,
            "transitionSpeed" => s.transition_speed,
            "dollyPeriod" => s.dolly_period,
            other => unreachable!("no setting {other}"),
        }
    }
}

impl Preset {
    /// The page's name.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Demonstration => PRESET_NAMES[0],
            Preset::Realistic => PRESET_NAMES[1],
        }
    }

    /// The preset of a page name.
    pub fn named(name: &str) -> Option<Preset> {
        [Preset::Demonstration, Preset::Realistic].into_iter().find(|p| p.name() == name)
    }

    /// This preset's value of `v`.
    pub fn value(self, v: &PresetValue) -> f32 {
        match self {
            Preset::Demonstration => v.demonstration,
            Preset::Realistic => v.realistic,
        }
    }

    fn overlay(self) -> Overlay {
        match self {
            Preset::Demonstration => DEMONSTRATION_OVERLAY,
            Preset::Realistic => Overlay::None,
        }
    }

    /// Writes this preset's settings into `s` (the rest is left as it is).
    pub fn apply(self, s: &mut Settings) {
        for v in &PRESET_VALUES {
            let value = self.value(v);
            match v.key {
                "tolerance" => {}
                "magnify" => s.magnify = value,
                "transitionSpeed" => s.transition_speed = value,
                "dollyPeriod" => s.dolly_period = value,
                other => unreachable!("no setting {other}"),
            }
        }
        s.overlay = self.overlay();
        self.apply_threshold(s);
    }

    /// Writes this preset's threshold into `s`, with its unit (the demonstration's is per
    /// [`DEMONSTRATION_HEIGHT`] pixels of view height), and nothing else of the preset.
    pub fn apply_threshold(self, s: &mut Settings) {
        s.tolerance_px = self.value(&THRESHOLD);
        s.tolerance_height = match self {
            Preset::Demonstration => Some(DEMONSTRATION_HEIGHT),
            Preset::Realistic => None,
        };
    }

    /// The preset whose every setting `s` has, if any (a reader who moved a control is on
    /// neither: the page then offers both).
    pub fn of(s: &Settings) -> Option<Preset> {
        [Preset::Demonstration, Preset::Realistic].into_iter().find(|&p| {
            let mut probe = s.clone();
            p.apply(&mut probe);
            probe == *s
        })
    }

    /// The `setState` update that turns this preset on.
    pub fn update(self) -> Update {
        Update { preset: Some(self), ..Default::default() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_realistic_preset_is_the_engines_defaults_and_names_round_trip() {
        assert_eq!(Preset::of(&Settings::default()), Some(Preset::Realistic));
        for name in PRESET_NAMES {
            assert_eq!(Preset::named(name).map(Preset::name), Some(name));
        }
        assert_eq!(Preset::named("demo"), None);
    }

    #[test]
    fn switching_presets_changes_only_their_settings_and_back() {
        let mut s = Settings { speed: 0.5, yaw_degrees: 12.0, ..Default::default() };
        let before = s.clone();
        Preset::Demonstration.update().apply(&mut s);
        assert_eq!(Preset::of(&s), Some(Preset::Demonstration));
        assert_eq!((s.tolerance_px, s.magnify, s.transition_speed), (2.4, 2.0, 0.25));
        assert_eq!((s.tolerance_for(400.0), s.tolerance_for(800.0)), (2.4, 4.8), "per 400 px of view");
        assert_eq!(s.overlay, Overlay::Difference);
        assert_eq!((s.speed, s.yaw_degrees), (0.5, 12.0), "the rest is the reader's");
        Preset::Realistic.update().apply(&mut s);
        assert_eq!(s, before);
        // A control moved after the preset: on neither.
        Preset::Demonstration.update().apply(&mut s);
        Update { tolerance: Some(3.0), ..Default::default() }.apply(&mut s);
        assert_eq!(Preset::of(&s), None);
        assert_eq!(s.tolerance_for(800.0), 3.0, "a threshold set in pixels is pixels");
    }

    #[test]
    fn every_demonstration_value_exaggerates() {
        for v in &PRESET_VALUES {
            let (d, r) = (v.demonstration, v.realistic);
            match v.key {
                "transitionSpeed" | "dollyPeriod" => assert!(d < r, "{v:?}"),
                _ => assert!(d > r, "{v:?}"),
            }
        }
    }
}
