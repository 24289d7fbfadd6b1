//! One collapse step, shared by both orders ([`Engine::try_collapse`]): the candidate's current
//! plan, the error limit, the checks (parking both ends of one that fails), the distance floor,
//! and the commit. Then the collapse itself, in four stages (house.md §3): new vertices for the
//! merged wedges, the corners and triangles around the edge, the surviving class's state and the
//! log step, and the re-pricing of the edges whose plans changed (at once in the strict order,
//! queued for the end of the pass in the batched one); and the level's reach, which lets open
//! parts waiting for it go. Part of the collapse engine in `mod.rs`.

use super::super::queue::Candidate;
use super::super::topology::{other_corners, Kind, NONE};
use super::super::{CollapseMode, Schedule};
use super::checks::check;
use super::costs::Costs;
use super::mesh::Mesh;
use super::record::Record;
use super::scratch::Pairing;
use super::scratch::Scratch;
use super::{Engine, Plan};
use crate::progressive::{RawCornerChange, RawStep};
use glam::{DVec3, Vec3};

/// What [`Engine::try_collapse`] did with a candidate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Step {
    /// The collapse is made and logged.
    Committed,
    /// The collapse is no longer valid, or is priced otherwise now (a vanishing part then goes
    /// back in line at its new price, see [`Engine::current_plan`]).
    Stale,
    /// Over the error limit or the distance floor: skipped, and the run, when it ends for want
    /// of candidates, ends at the limit.
    OverFloor,
    /// Failed a check: both ends are parked until a collapse nearby changes them.
    Failed,
}

impl Engine<'_> {
    /// One collapse step for a current, exact candidate (not a bound): re-plans it (which
    /// leaves the pairing that the collapse uses), skips it over `max_mean_squared_error` or the
    /// distance floor, parks both ends when it fails a check, and otherwise commits it.
    pub(super) fn try_collapse(&mut self, entry: &Candidate, max_mean_squared_error: f32) -> Step {
        let (u, v) = (entry.u(), entry.v);
        // The stamp keeps 16 and 15 bits of the versions; a wrapped stamp is caught by the
        // cost, which a current entry reproduces exactly, unless a part near it vanished
        // (see `current_plan`).
        let Some(plan) = self.current_plan(u, v, entry.cost()) else {
            return Step::Stale;
        };
        if plan.mean_squared as f32 > max_mean_squared_error {
            self.floors.over_floor = true;
            return Step::OverFloor;
        }
        let steps = self.record.steps();
        let Some((farthest, distance)) = check(&self.mesh, &mut self.floors, &mut self.scratch, steps, &plan)
        else {
            self.order.parked.park(u, v);
            self.order.parked.park(v, u);
            return Step::Failed;
        };
        if self.floors.distance_floor && distance > self.floors.max_distance {
            self.floors.over_floor = true;
            return Step::OverFloor;
        }
        self.commit(&plan, farthest, distance);
        Step::Committed
    }

    /// The plan of `u → v` if it still costs `queued`, the cost its queue entry was keyed by;
    /// `None` for a collapse no longer valid or priced otherwise. A vanishing part's price changes
    /// with no version of its own changing: a closed part's rises when a part near it vanishes
    /// first (`clearance.rs`), an open part's moves with the live triangles near it (`plan.rs`).
    /// Such an entry goes back in line at its new price.
    fn current_plan(&mut self, u: u32, v: u32, queued: f32) -> Option<Plan> {
        let plan = self.pricing().plan(u, v)?;
        let cost = plan.cost as f32;
        if cost == queued {
            return Some(plan);
        }
        if self.mesh.vanishing_corner(u, v).is_some() {
            // Cheaper than queued, it is still the cheapest: everything else in line costs at
            // least what it was queued at.
            if cost < queued {
                return Some(plan);
            }
            self.order.push(&self.mesh, &plan);
        }
        None
    }

    /// Applies a checked collapse that leaves input vertex `farthest` at `distance` from the
    /// level, the merged vertex tracking it; a part that vanishes with it leaves the clearance,
    /// and its farthest input points to the nearest parts left (`clearance.rs`).
    fn commit(&mut self, plan: &Plan, farthest: u32, distance: f64) {
        let vanishing = self.mesh.vanishing_corner(plan.u, plan.v).is_some();
        self.apply(plan);
        self.floors.farthest_input[plan.v as usize] = farthest;
        if vanishing {
            self.floors.clearance.vanish(&self.mesh.classes, plan.u, self.floors.max_distance as f32);
        }
        self.reach(distance);
    }

    /// Records that the level has left an input point `distance` from it: the open parts
    /// waiting for the level to reach that far are priced again.
    fn reach(&mut self, distance: f64) {
        if distance > self.floors.reached_distance {
            self.floors.reached_distance = distance;
            self.release_waiting(distance);
        }
    }

    /// When nothing else can collapse: lets the level reach the nearest waiting open part, so
    /// that parts still vanish, nearest first, where nothing else moves (a model of flat plates
    /// alone). Whether one was waiting.
    pub(super) fn reach_nearest_waiting(&mut self) -> bool {
        let Some(nearest) = self.floors.waiting.nearest(&self.mesh.alive) else {
            return false;
        };
        self.floors.reached_distance = self.floors.reached_distance.max(nearest);
        self.release_waiting(nearest);
        true
    }

    /// Prices again the waiting open parts whose points lie within `distance` of the level.
    fn release_waiting(&mut self, distance: f64) {
        // Taken out first: pricing one again may put it back (its points moved farther from the
        // level since it began waiting).
        for (_, a, b) in self.floors.waiting.take_due(distance) {
            if self.mesh.alive[a as usize] && self.mesh.alive[b as usize] {
                self.requeue(a, b);
            }
        }
    }

    /// Performs a planned (and checked) collapse; `plan` must be the latest plan priced, whose
    /// pairing scratch it uses.
    fn apply(&mut self, plan: &Plan) {
        let step = self.record.steps() as u32 + 1;
        let (first_new, new_count) =
            merge_wedges(&self.mesh, &mut self.costs, &mut self.scratch, &mut self.record, plan, step);
        let thirds = self.mesh.move_corners(&self.scratch.pairing, &mut self.record, (plan.u, plan.v), step);
        self.merge_classes(plan, first_new, new_count);
        self.requeue_neighbours(plan.v, thirds);
    }

    /// Class state: `v` takes `u`'s quadrics and the new position, `u` dies, both versions move
    /// on (every candidate of either is stale); the step goes to the log.
    fn merge_classes(&mut self, plan: &Plan, first_new: u32, new_count: u32) {
        let distance = self.costs.merge_classes(&self.mesh.classes, plan.u as usize, plan.v as usize, plan.p);
        self.mesh.merge_classes(plan.u, plan.v, plan.p);
        self.order.parked.clear(plan.v); // every edge of v is queued again below
        self.record.log.steps.push(RawStep {
            cost: plan.mean_squared,
            distance,
            triangles_after: self.mesh.live_triangles as u32,
            first_new_vertex: first_new,
            new_vertex_count: new_count,
            corner_changes_end: self.record.log.corner_changes.len() as u32,
        });
    }

    /// Re-prices what collapsing into `v` changed (see the comment inside).
    fn requeue_neighbours(&mut self, v: u32, thirds: [u32; 2]) {
        // Re-queue: every edge of v, the failed edges of a parked neighbour (they may pass now),
        // and the edges of a neighbour whose plan this collapse may have changed.
        //
        // A plan along x–y (neither v) pairs the wedges of x and y at their corners in the
        // triangles beside the edge, and needs every wedge of the moving end that a live triangle
        // uses to follow one. This collapse changed no corner of x or y (only corners of u, now
        // v) and removed triangles only at the thirds, so x–y changed only when x or y is a third
        // (one of its wedges may have fallen out of use). A third's edges are priced again when
        // it is a junction or parked, whose plans depend on that (and had been, before this rule:
        // every edge of every junction and parked neighbour); every other queued entry is still
        // exact and stays.
        let mut neighbours = std::mem::take(&mut self.scratch.neighbours);
        let mut second = std::mem::take(&mut self.scratch.second_neighbours);
        self.mesh.neighbours_into(v, &mut self.scratch.marks, &mut neighbours);
        let is_third = |x: u32| x == thirds[0] || x == thirds[1];
        for &x in &neighbours {
            let xi = x as usize;
            let parked = self.order.parked.is_parked(x);
            if !parked && self.mesh.kind[xi] != Kind::Junction {
                continue;
            }
            if is_third(x) {
                self.order.parked.clear(x);
                self.mesh.version[xi] = self.mesh.version[xi].wrapping_add(1);
                self.mesh.neighbours_into(x, &mut self.scratch.marks, &mut second);
                for &y in &second {
                    if y != v {
                        self.requeue(x, y);
                    }
                }
                continue;
            }
            self.mesh.neighbours_into(x, &mut self.scratch.marks, &mut second);
            let stamp = self.scratch.marks.next_stamp();
            let marks = &mut self.scratch.marks;
            self.order.parked.take(x, |partner| marks.set(partner, stamp));
            for &y in &second {
                if y != v && (is_third(y) || self.scratch.marks.is_set(y, stamp)) {
                    self.requeue(x, y);
                }
            }
        }
        match self.order.schedule {
            Schedule::Strict => {
                self.order.queue_bounds(&self.mesh, &self.costs, &mut self.record.stats, v, &neighbours)
            }
            Schedule::Passes => {
                for &x in &neighbours {
                    self.requeue(v, x);
                }
            }
        }
        self.scratch.neighbours = neighbours;
        self.scratch.second_neighbours = second;
    }
}

impl Mesh<'_> {
    /// Class `v` takes class `u`'s place at `p`: a junction's survivor stays a junction, outlines are inherited; `u` dies, merged into `v`,
    /// and both versions move on (every candidate of either is stale).
    fn merge_classes(&mut self, u: u32, v: u32, p: DVec3) {
        let (ui, vi) = (u as usize, v as usize);
        self.position[vi] = p;
        // The survivor of a junction inherits its line ends or meeting lines: it stays put from
        // now on and collapses only under the junction rules (a stale interior or line kind
        // would let it drag those lines freely).
        if self.kind[ui] == Kind::Junction && self.kind[vi] != Kind::Locked {
            self.kind[vi] = Kind::Junction;
        }
        self.on_outline[vi] |= self.on_outline[ui];
        self.alive[ui] = false;
        self.merged_into[ui] = v;
        self.version[ui] = self.version[ui].wrapping_add(1);
        self.version[vi] = self.version[vi].wrapping_add(1);
    }

    /// Triangles: those on the edge `u`–`v` die at `step`, the others move their `u` corner to
    /// `v`'s wedge (as `pairing` pairs them), logged in `record`; returns the classes opposite
    /// the edge (NONE where there is none).
    fn move_corners(
        &mut self,
        pairing: &Pairing,
        record: &mut Record,
        (u, v): (u32, u32),
        step: u32,
    ) -> [u32; 2] {
        let u_range = self.class_wedges(u as usize);
        let v_range = self.class_wedges(v as usize);
        let mut thirds = [NONE; 2];
        let mut dead_triangles = [NONE; 2];
        let mut dead = 0;
        for corner in self.lists.iter(u) {
            let ci = corner as usize;
            let (n, pc) = other_corners(corner);
            let (a, b) = (self.class_at(n), self.class_at(pc));
            if a == v || b == v {
                self.triangle_alive[ci / 3] = false;
                record.log.triangle_death[ci / 3] = step;
                self.live_triangles -= 1;
                if dead < 2 {
                    thirds[dead] = if a == v { b } else { a };
                    dead_triangles[dead] = corner / 3;
                }
                dead += 1;
                continue;
            }
            let wu = self.corner_wedge[ci];
            let iu = self.classes.wedges[u_range.clone()].iter().position(|&w| w == wu).unwrap_or(0);
            let wv = self.classes.wedges[v_range.start + pairing.u_pair[iu] as usize];
            self.corner_wedge[ci] = wv;
            self.corner_class[ci] = v;
            record.log.corner_changes.push(RawCornerChange {
                corner,
                from_vertex: record.vertex_id[wu as usize],
                to_vertex: record.vertex_id[wv as usize],
            });
        }
        // A checked collapse has at most two triangles on its edge.
        debug_assert!(dead <= 2);
        self.lists.splice(u, v);
        for t in dead_triangles.into_iter().filter(|&t| t != NONE) {
            for corner in 3 * t..3 * t + 3 {
                let c = self.class_at(corner);
                self.lists.unlink(if c == u { v } else { c }, corner);
            }
        }
        thirds
    }
}

/// New vertices: one per merged wedge pair, and one per unmerged wedge of `v` that moves,
/// logged at `step`, with the attributes the costs give them (`scratch` holds the plan's pairing);
/// returns the first new vertex id and the count.
fn merge_wedges(
    mesh: &Mesh,
    costs: &mut Costs,
    scratch: &mut Scratch,
    record: &mut Record,
    plan: &Plan,
    step: u32,
) -> (u32, u32) {
    let (u, v, p) = (plan.u, plan.v, plan.p);
    let (ui, vi) = (u as usize, v as usize);
    let m = costs.channels;
    let stride = costs.priced.stride();
    let moved = p != mesh.position[vi];
    let first_new = record.log.positions.len() as u32;
    let u_range = mesh.class_wedges(ui);
    let v_range = mesh.class_wedges(vi);
    let pv = mesh.position[vi];
    let pu = mesh.position[ui];
    let edge = pu - pv;
    let t = if edge.length_squared() > 0.0 {
        ((p - pv).dot(edge) / edge.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    for (iv, k) in v_range.clone().enumerate() {
        let wv = mesh.classes.wedges[k] as usize;
        let partner = scratch.pairing.v_partner[iv];
        let wu = if partner == NONE {
            usize::MAX
        } else {
            mesh.classes.wedges[u_range.start + partner as usize] as usize
        };
        if wu == usize::MAX && !moved {
            continue;
        }
        if wu != usize::MAX {
            for k in 0..stride {
                costs.wedge_sums[wv * stride + k] += costs.wedge_sums[wu * stride + k];
            }
        }
        for j in 0..m {
            let own = costs.wedge_attributes[wv * m + j];
            let priced = costs.priced.source[j];
            let w = priced.map_or(0.0, |k| costs.priced.priced[k].1 as f64);
            let alpha_w = costs.wedge_sums[wv * stride] * w;
            let value = if costs.mode == CollapseMode::HalfEdge {
                own
            } else if let (Some(k), true) = (priced, alpha_w > 0.0) {
                let base = wv * stride + 1 + 4 * k;
                let g = DVec3::new(
                    costs.wedge_sums[base],
                    costs.wedge_sums[base + 1],
                    costs.wedge_sums[base + 2],
                );
                ((g.dot(p) + costs.wedge_sums[base + 3]) / alpha_w) as f32
            } else if wu != usize::MAX {
                let other = costs.wedge_attributes[wu * m + j];
                (own as f64 + (other as f64 - own as f64) * t) as f32
            } else {
                own
            };
            scratch.new_attributes[j] = value;
        }
        if let (Some(c), CollapseMode::Full) = (costs.normal_channel, costs.mode) {
            let normal = Vec3::from_slice(&scratch.new_attributes[c..c + 3]).normalize_or_zero();
            if normal != Vec3::ZERO {
                scratch.new_attributes[c..c + 3].copy_from_slice(&normal.to_array());
            }
        }
        let id = record.log.positions.len() as u32;
        record.log.positions.push(p.as_vec3());
        record.log.attributes.extend_from_slice(&scratch.new_attributes);
        record.log.parent.push(NONE);
        record.log.born_at.push(step);
        record.log.survivor_source.push(record.vertex_id[wv]);
        record.log.parent[record.vertex_id[wv] as usize] = id;
        if wu != usize::MAX {
            record.log.parent[record.vertex_id[wu] as usize] = id;
        }
        record.vertex_id[wv] = id;
        costs.wedge_attributes[wv * m..wv * m + m].copy_from_slice(&scratch.new_attributes);
    }
    let new_count = record.log.positions.len() as u32 - first_new;
    // Wedges of u that no live triangle uses any more end here too.
    for (iu, k) in u_range.clone().enumerate() {
        let wu = mesh.classes.wedges[k] as usize;
        if !scratch.pairing.u_seen[iu] && new_count > 0 {
            record.log.parent[record.vertex_id[wu] as usize] = first_new;
        }
    }
    (first_new, new_count)
}
