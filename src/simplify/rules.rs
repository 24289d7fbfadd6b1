//! The collapse engine's special rules, named in one place: what each does beyond plain quadric
//! simplification (Garland & Heckbert's planes, Hoppe's attribute quadrics, the link condition
//! and the fold test), why, and the test that pins it. Like meshoptimizer's vertex-kind tables,
//! the engine asks the table ([`Rules`]) instead of carrying each rule as a flag of its own, and
//! a run can leave any rule out, so the benchmarks can measure what each one pays
//! (`examples/rule_ablation.rs`, `examples/clod_timing.rs --without RULE`).
//!
//! Every rule is on by default. A rule stays only if it pays, in animated error or in how far the
//! levels can go, on the project's characters and on the generated kinds it was not tuned on;
//! `docs/lod-build.md` gives the current measurements. Two rules did not and are gone: hard
//! corners of rigid flat-shaded parts kept where they were (the generated flat-shaded robot's
//! levels were half as good with it), and the distance floor held in the animation frames too
//! (no judged level of any model changed without it, and it took a quarter to a third of the
//! build on rigid robots and many-part models).

/// One special rule of the collapse engine (see [`RULES`] for what each does and why).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Rule {
    /// A pair smaller than `SMALL_PAIR` (0.3) of the mean pair area is ordered as if it were that
    /// large.
    SmallPairs,
    /// Two vertices of one border or seam line merge at the quadric's minimiser (held near the
    /// line by its penalty planes) instead of the best point of their edge.
    LinesMergeFree,
    /// An interior vertex onto a uv or colour seam that is no outline (no border, material line or
    /// crease) merges at the minimiser: the seam moves with its surface.
    SeamsMoveWithSurface,
    /// A closed part that vanishes whole is priced by its distance to the other parts.
    ClosedPartsByClearance,
    /// An open part's last triangle goes only once the part lies within the distance the level
    /// has already reached (until then it waits).
    OpenPartsWithinReach,
    /// No collapse leaves a tracked input vertex farther than the build's error limit from the
    /// level (a distance, beside the quadric's mean squared error).
    DistanceFloor,
}

/// What a rule does, why it exists, and where that is tested.
#[derive(Clone, Copy, Debug)]
pub struct RuleInfo {
    pub rule: Rule,
    /// The name the tools take (`--without NAME`).
    pub name: &'static str,
    /// Why the rule exists: the failure plain quadrics show without it.
    pub reason: &'static str,
    /// The test that pins it (file and function): it shows the failure with the rule left out.
    pub test: &'static str,
}

/// Every rule, in the order the engine meets them (ordering, placement, vanishing parts, floors).
pub const RULES: [RuleInfo; 6] = [
    RuleInfo {
        rule: Rule::SmallPairs,
        name: "small-pairs",
        reason:
            "ordered by the area-weighted error alone, a small part coarsens while its distance is several \
                 times the rest's (parts.glb's neck plates)",
        test: "src/simplify/collapse/costs.rs: a_small_pair_is_ordered_as_if_it_were_a_fraction_of_the_mean",
    },
    RuleInfo {
        rule: Rule::LinesMergeFree,
        name: "lines-merge-free",
        reason:
            "held on the edge, a coarse open plate is a chord through its border and misses its bulge, and \
                 a corner moved onto its neighbour is cut off",
        test: "tests/simplify/main.rs: a_bent_plate_keeps_its_bulge",
    },
    RuleInfo {
        rule: Rule::SeamsMoveWithSurface,
        name: "seams-move-with-surface",
        reason:
            "a uv or colour seam inside a smooth surface pins every vertex collapsed onto it, so the seam's \
                 neighbourhood keeps the input's shape and the rest pays",
        test: "tests/simplify/main.rs: a_seam_moves_with_its_surface_and_a_crease_stays",
    },
    RuleInfo {
        rule: Rule::ClosedPartsByClearance,
        name: "closed-parts-by-clearance",
        reason:
            "a sheet lies in its own planes and a finger's side planes pass its axis, so the plane quadric \
                 lets whole parts vanish for almost nothing",
        test: "tests/simplify/parts.rs: a_part_beside_another_vanishes_before_one_standing_alone",
    },
    RuleInfo {
        rule: Rule::OpenPartsWithinReach,
        name: "open-parts-within-reach",
        reason:
            "an open part's last triangle lies in its own plane: the plane quadric lets a plate vanish at \
                 no cost, however far it stands from everything else",
        test: "tests/simplify/parts.rs: open_parts_vanish_nearest_the_level_first",
    },
    RuleInfo {
        rule: Rule::DistanceFloor,
        name: "distance-floor",
        reason:
            "the mean squared error over a pair's area misses a small part cut short (a toe merged with its \
                 heel)",
        test: "tests/simplify/main.rs: max_distance_keeps_a_ridge_that_the_quadric_floor_cuts",
    },
];

/// The set of rules a run applies; [`Rules::ALL`] by default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rules(u16);

impl Rules {
    /// Every rule: the engine as built and measured.
    pub const ALL: Rules = Rules((1 << RULES.len()) - 1);
    /// No rule: plain quadric simplification with the link condition and the fold test.
    pub const NONE: Rules = Rules(0);

    /// Whether the set holds `rule`.
    pub fn has(self, rule: Rule) -> bool {
        self.0 & (1 << rule as u16) != 0
    }

    /// The set without `rule`.
    #[must_use]
    pub fn without(self, rule: Rule) -> Rules {
        Rules(self.0 & !(1 << rule as u16))
    }

    /// The set with `rule`.
    #[must_use]
    pub fn with(self, rule: Rule) -> Rules {
        Rules(self.0 | (1 << rule as u16))
    }

    /// The rule the tools call `name` (see [`RuleInfo::name`]).
    pub fn parse(name: &str) -> Option<Rule> {
        RULES.iter().find(|info| info.name == name).map(|info| info.rule)
    }
}

impl Default for Rules {
    fn default() -> Self {
        Rules::ALL
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_table_lists_every_rule_once_in_declaration_order() {
        for (i, info) in RULES.iter().enumerate() {
            assert_eq!(info.rule as usize, i, "{}", info.name);
            assert_eq!(Rules::parse(info.name), Some(info.rule));
        }
        assert_eq!(Rules::parse("no-such-rule"), None);
    }

    #[test]
    fn a_set_leaves_out_and_takes_back_one_rule() {
        let without = Rules::ALL.without(Rule::DistanceFloor);
        assert!(!without.has(Rule::DistanceFloor));
        assert!(RULES.iter().filter(|i| i.rule != Rule::DistanceFloor).all(|i| without.has(i.rule)));
        assert_eq!(without.with(Rule::DistanceFloor), Rules::ALL);
        assert!(RULES.iter().all(|i| !Rules::NONE.has(i.rule)));
    }
}
