//! What each view draws this frame: the draw calls that show the schedule's state by popping,
//! alpha-blending or geomorphing. Pure data, so the GPU code only executes it and the rules are
//! tested natively.
//!
//! Every view is planned from the same [`Transition`]: popping draws its `to` level, the others
//! draw the way from the finer to the coarser of its two levels ([`Transition::fine_coarse`]):
//! `s = 0` is exactly the finer level, `s = 1` exactly the coarser one, which may be several
//! levels coarser (the ancestor tables chain).

use super::schedule::Transition;

/// How a view shows a change of level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Draws the selected level; changes are instant.
    Popping,
    /// Draws both levels with complementary opacity during a transition.
    AlphaBlend(BlendVariant),
    /// Draws the fine level once, morphing each vertex towards its ancestor.
    Geomorph,
}

/// The alpha-blending variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlendVariant {
    /// Both levels translucent (`1 − t` and `t`), both writing depth, the more opaque drawn first:
    /// the background shows through mid-fade.
    Naive,
    /// The dominant level opaque, the other blended over it without writing depth (Giegl & Wimmer
    /// 2007, "Unpopping"): the fading level goes 0 → 1 over the first half, then they swap.
    OpaqueFirst,
    /// Screen-door: complementary 4×4 Bayer masks, both opaque; every pixel shows exactly one level.
    Dither,
}

/// Pipeline state of a draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PassKind {
    /// Depth test and write, no blending.
    Opaque,
    /// Alpha blending over what is there, depth test (less-equal) without depth write.
    BlendOver,
    /// Alpha blending with depth write (naive cross-fade).
    BlendNaive,
}

/// A geomorph: each vertex of the drawn level moves towards its ancestor in level `coarse` by `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Morph {
    pub coarse: usize,
    pub t: f32,
}

/// One draw call of a view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawCall {
    pub level: usize,
    pub pass: PassKind,
    /// `Some(m)` draws through the geomorph vertex shader with `morph_t = m.t`, the ancestors in
    /// level `m.coarse`.
    pub morph: Option<Morph>,
    pub opacity: f32,
    /// 0 none, 1 keep below `dither_threshold`, 2 keep the rest (see `skin.wgsl`).
    pub dither_mode: u32,
    pub dither_threshold: f32,
}

impl DrawCall {
    /// An opaque draw of `level` as it is.
    pub fn opaque_level(level: usize) -> Self {
        Self::opaque(level)
    }

    fn opaque(level: usize) -> Self {
        Self {
            level,
            pass: PassKind::Opaque,
            morph: None,
            opacity: 1.0,
            dither_mode: 0,
            dither_threshold: 0.0,
        }
    }

    fn blended(level: usize, pass: PassKind, opacity: f32) -> Self {
        Self { pass, opacity, ..Self::opaque(level) }
    }
}

/// What a view draws, and the transition it shows (the same in every view).
#[derive(Clone, Debug, PartialEq)]
pub struct ViewPlan {
    pub draws: Vec<DrawCall>,
    pub transition: Transition,
}

/// The draws of one view showing `transition` by `method`.
pub fn plan_view(method: Method, transition: &Transition) -> ViewPlan {
    let (fine, coarse, t) = transition.fine_coarse();
    let plan = |draws| ViewPlan { draws, transition: *transition };
    if method == Method::Popping {
        return plan(vec![DrawCall::opaque(transition.to)]);
    }
    if fine == coarse || t <= 0.0 {
        return plan(vec![DrawCall::opaque(fine)]);
    }
    let draws = match method {
        Method::Popping => unreachable!("handled above"),
        Method::Geomorph => vec![DrawCall { morph: Some(Morph { coarse, t }), ..DrawCall::opaque(fine) }],
        Method::AlphaBlend(BlendVariant::Naive) => {
            // The more opaque level first: both write depth, so the second shows only where it is
            // in front. Drawn the other way round, a nearly transparent fine level would hide the
            // nearly opaque coarse one at the end of the fade, and the finish would pop.
            let fine_draw = DrawCall::blended(fine, PassKind::BlendNaive, 1.0 - t);
            let coarse_draw = DrawCall::blended(coarse, PassKind::BlendNaive, t);
            if t < 0.5 {
                vec![fine_draw, coarse_draw]
            } else {
                vec![coarse_draw, fine_draw]
            }
        }
        Method::AlphaBlend(BlendVariant::OpaqueFirst) => {
            if t < 0.5 {
                vec![DrawCall::opaque(fine), DrawCall::blended(coarse, PassKind::BlendOver, 2.0 * t)]
            } else {
                vec![DrawCall::opaque(coarse), DrawCall::blended(fine, PassKind::BlendOver, 2.0 * (1.0 - t))]
            }
        }
        Method::AlphaBlend(BlendVariant::Dither) => {
            // One threshold for both: the masks are exact complements, whatever the rounding.
            let threshold = 1.0 - t;
            vec![
                DrawCall { dither_mode: 1, dither_threshold: threshold, ..DrawCall::opaque(fine) },
                DrawCall { dither_mode: 2, dither_threshold: threshold, ..DrawCall::opaque(coarse) },
            ]
        }
    };
    plan(draws)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn at(from: usize, to: usize, t: f32) -> Transition {
        Transition { from, to, t }
    }

    #[test]
    fn popping_draws_the_level_switched_to() {
        let p = plan_view(Method::Popping, &at(1, 3, 0.25));
        assert_eq!(p.draws, vec![DrawCall::opaque(3)]);
        assert_eq!(p.transition, at(1, 3, 0.25), "every view reports the same transition");
    }

    #[test]
    fn geomorph_is_one_draw_of_the_finer_level() {
        let p = plan_view(Method::Geomorph, &at(1, 3, 0.25));
        assert_eq!(p.draws.len(), 1);
        assert_eq!((p.draws[0].level, p.draws[0].morph), (1, Some(Morph { coarse: 3, t: 0.25 })));
        let refining = plan_view(Method::Geomorph, &at(3, 1, 0.25));
        assert_eq!(
            (refining.draws[0].level, refining.draws[0].morph),
            (1, Some(Morph { coarse: 3, t: 0.75 }))
        );
        let idle = plan_view(Method::Geomorph, &Transition::at(2));
        assert_eq!(idle.draws, vec![DrawCall::opaque(2)], "no morph outside transitions");
        let start = plan_view(Method::Geomorph, &at(0, 2, 0.0));
        assert_eq!(start.draws, vec![DrawCall::opaque(0)], "a transition starts exactly at its first level");
    }

    #[test]
    fn blend_variants_use_complementary_opacity() {
        let naive = plan_view(Method::AlphaBlend(BlendVariant::Naive), &at(0, 1, 0.25));
        assert_eq!(
            naive.draws.iter().map(|d| (d.level, d.opacity)).collect::<Vec<_>>(),
            [(0, 0.75), (1, 0.25)]
        );
        let late_naive = plan_view(Method::AlphaBlend(BlendVariant::Naive), &at(0, 1, 0.75));
        assert_eq!(
            late_naive.draws.iter().map(|d| (d.level, d.opacity)).collect::<Vec<_>>(),
            [(1, 0.75), (0, 0.25)],
            "the more opaque level first"
        );
        let early = plan_view(Method::AlphaBlend(BlendVariant::OpaqueFirst), &at(0, 1, 0.25));
        assert_eq!(early.draws[0], DrawCall::opaque(0));
        assert_eq!(
            (early.draws[1].level, early.draws[1].pass, early.draws[1].opacity),
            (1, PassKind::BlendOver, 0.5)
        );
        let late = plan_view(Method::AlphaBlend(BlendVariant::OpaqueFirst), &at(0, 1, 0.75));
        assert_eq!(late.draws[0], DrawCall::opaque(1));
        assert_eq!((late.draws[1].level, late.draws[1].opacity), (0, 0.5));
        let skip = plan_view(Method::AlphaBlend(BlendVariant::OpaqueFirst), &at(4, 1, 0.25));
        assert_eq!(skip.draws[0], DrawCall::opaque(4), "refining from 4 straight to 1: 4 dominates first");
        assert_eq!((skip.draws[1].level, skip.draws[1].opacity), (1, 0.5));
        let dither = plan_view(Method::AlphaBlend(BlendVariant::Dither), &at(0, 1, 0.25));
        assert_eq!(
            dither.draws.iter().map(|d| (d.dither_mode, d.dither_threshold)).collect::<Vec<_>>(),
            [(1, 0.75), (2, 0.75)]
        );
    }
}
