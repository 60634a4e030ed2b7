//! Colliders as proxies: put into the structure, taken out, and the structure picked for
//! the first ones.

use super::{BroadPhaseCore, Proxy, Structure, mode};
use super::{REGION_MARGIN, REGION_STEPS};
use crate::Aabb;
use crate::{BodyState, Bound, Engine, EngineStep, Key};
use kinetic_core::{Body, FlightPlan, Real, Shape, Vec3};
use kinetic_flight::{ConvexShape, Grid, LooseGrid};

impl BroadPhaseCore {
    /// The structure's shape for collider `i` held by `hold`: its fat box if it has one.
    fn shape(&self, i: u32, hold: &Bound) -> Shape {
        if let Some(Aabb { min, max }) = self.fat_box(i) {
            return box_shape(min, max);
        }
        match *hold {
            Bound::Moving {
                body,
                radius,
                slack,
            } => {
                // The hold's radius has its base slack; a grown slack adds the rest.
                let extra = self
                    .motions
                    .get(body)
                    .map_or(0.0, |m| slack * (m.scale() - 1.0));
                Shape::Ball {
                    radius: radius + extra,
                }
            }
            Bound::Fixed { min, max } => box_shape(min, max),
        }
    }

    /// Collider `i`'s fat box, if it has one.
    fn fat_box(&self, i: u32) -> Option<Aabb> {
        self.proxies.get(i as usize).copied().flatten()?.fat
    }

    /// The structure's plan for collider `i` held by `hold`: at rest in its fat box's centre
    /// if it has one.
    fn plan_of(&self, i: u32, hold: &Bound) -> FlightPlan {
        if let Some(Aabb { min, max }) = self.fat_box(i) {
            return FlightPlan::at_rest((min + max) / 2.0);
        }
        match *hold {
            Bound::Fixed { min, max } => FlightPlan::at_rest((min + max) / 2.0),
            Bound::Moving { body, .. } => self.motions[body].plan,
        }
    }

    /// Drops collider `h` and its pairs without events (it was removed or disabled: the
    /// engine's narrow phase drops its pairs itself).
    pub(super) fn remove_collider(&mut self, h: Key) {
        if self.knows(h) {
            self.detach(h.index, true);
        }
    }

    /// Takes held collider `i` out of the structure and forgets its proxy. Its pairs go
    /// silently, or (`silent` false) drop out as usual to be deleted once out for a window.
    pub(super) fn detach(&mut self, i: u32, silent: bool) {
        self.take_out(i);
        if let Some(st) = self.stepped.as_mut() {
            st.forget(i, silent);
        }
        let mut changes = std::mem::take(&mut self.changes);
        if silent {
            self.book.forget(i, &mut changes);
        } else {
            self.book.apply(&mut changes, self.clock.kds);
        }
        self.changes = changes;
        let proxy = self.proxies[i as usize].take().expect("held");
        self.held -= 1;
        self.movers[i as usize] = None;
        if let Bound::Moving { body, .. } = proxy.hold
            && let Some(m) = self.motions.get_mut(body)
        {
            m.colliders.retain(|c| *c != i);
            if m.colliders.is_empty() {
                self.motions.remove(body);
                self.moving.retain(|&b| b != body);
            }
        }
    }

    /// Takes collider `i` out of the structure, leaving its pair changes in `self.changes`.
    pub(super) fn take_out(&mut self, i: u32) {
        if let Some(s) = self.structure.as_mut() {
            s.remove(i, &self.bodies, self.clock.kds, &mut self.changes);
        }
        if let Some(b) = self.bodies.get_mut(i as usize) {
            *b = None;
        }
        self.plans[i as usize] = self.plans[i as usize].wrapping_add(1);
    }

    /// Puts collider `i` with `hold` into the structure at its clock, grown by `grow` (a
    /// change that happened `kds - pos` before the structure's clock).
    pub(super) fn put_in(&mut self, i: u32, hold: Bound, grow: Real) {
        let mut shape = self.shape(i, &hold);
        if grow > 0.0 {
            shape = Shape::Ball {
                radius: shape.outer_radius() + grow,
            };
        }
        let plan = self.plan_of(i, &hold);
        self.body_slots();
        self.bodies[i as usize] = Some(Body { shape, plan });
        self.plans[i as usize] = self.plans[i as usize].wrapping_add(1);
        if let Some(s) = self.structure.as_mut() {
            s.insert(i, &self.bodies, self.clock.kds, &mut self.changes);
        }
        self.proxies[i as usize].as_mut().expect("held").grown_until =
            (grow > 0.0).then_some(self.clock.kds);
        if grow > 0.0 {
            self.grown.push(i);
        }
        self.stats.inserts += 1;
        self.step.inserts += 1;
    }

    /// Whether the proxies live in the loose grid (the caller's choice, or the one made for
    /// the first colliders), else in the hierarchical grid (before any).
    fn in_loose_grid(&self) -> bool {
        self.loose_grid.unwrap_or(false)
    }

    fn grow_slots(&mut self, i: u32) {
        let need = i as usize + 1;
        if self.proxies.len() < need {
            self.plans.resize(need, 0);
            self.proxies.resize(need, None);
            self.movers.resize(need, None);
        }
        if !self.is_stepped() {
            self.body_slots();
        }
    }

    /// The structure's bodies as many as the proxies: kept only while the world is kinetic
    /// (a stepped world has no structure, and its first step then fills no table it does not
    /// read).
    pub(super) fn body_slots(&mut self) {
        if self.bodies.len() < self.proxies.len() {
            self.bodies.resize(self.proxies.len(), None);
        }
    }

    /// Adds the colliders `new` (enabled, not held, with their holds) at the positions' time.
    pub(super) fn install(
        &mut self,
        new: &[(Key, Bound)],
        engine: &impl Engine,
        step: EngineStep,
        update: u64,
    ) {
        if new.is_empty() {
            return;
        }
        // Each moving hold's body read once (for its plan: none on the engine's boxes). A
        // moving hold whose body the engine does not give breaks the contract: the collider
        // waits until it is changed again.
        let plans = !self.engine_boxes;
        let mut holds: Vec<(Key, Bound, Option<BodyState>)> = Vec::with_capacity(new.len());
        holds.extend(new.iter().filter_map(|&(h, hold)| match hold {
            Bound::Moving { body, .. } if plans => engine.body(body).map(|s| (h, hold, Some(s))),
            _ => Some((h, hold, None)),
        }));
        if self.loose_grid.is_none() {
            self.loose_grid = Some(plans && loose_grid_fits(&holds));
        }
        if self.structure.is_none() && !self.is_stepped() {
            // A world starts stepped, its first steps showing whether plans hold; one of
            // sleeping bodies too, whose resting boxes stay filed between steps (an engine
            // that keeps enlarged boxes: stepped for good, see `mode.rs`).
            if self.may_step() {
                self.stepped = Some(mode::Stepped::new(self.engine_boxes));
            } else {
                self.structure = Some(new_structure(self.in_loose_grid(), step.dt));
            }
        }
        // The tables grown once for the bulk, not copied over as they double.
        if let Some(last) = holds.iter().map(|(h, ..)| h.index).max() {
            self.grow_slots(last);
        }
        let bodies = holds.iter().filter_map(|(_, hold, _)| match hold {
            Bound::Moving { body, .. } => Some(body.index as usize),
            Bound::Fixed { .. } => None,
        });
        if let Some(last) = bodies.max()
            && plans
        {
            self.motions.reach(last);
        }
        // Plans first: a body seen for the first time gets a plan fitted to its state now; a
        // body already moving keeps its plan for the collider it gains.
        for &(h, hold, state) in &holds {
            let i = h.index;
            self.grow_slots(i);
            if let (Bound::Moving { body, slack, .. }, Some(state)) = (hold, state) {
                let fresh = !self.motions.contains(body);
                if fresh {
                    let m = self.motion_for(body, &state, slack);
                    m.colliders.push(i);
                    m.seen = update;
                    self.refit_to(body, &state, step, true);
                    // A body that starts at rest is held by fat boxes where the engine gives
                    // them.
                    let stepped = self.is_stepped();
                    let m = self.motions.get_mut(body).expect("a motion");
                    if m.at_rest() && !stepped && engine.bounds(h).is_some() {
                        m.fat = true;
                    }
                } else {
                    let m = self.motions.get_mut(body).expect("a motion");
                    m.slack = m.slack.min(slack);
                    m.colliders.push(i);
                }
            }
            let proxy = Proxy {
                key: h,
                hold,
                grown_until: None,
                fat: self.joining_box(engine, h, &hold),
            };
            self.movers[i as usize] = Some(proxy.mover());
            if self.proxies[i as usize].replace(proxy).is_none() {
                self.held += 1;
            }
            if let Some(st) = self.stepped.as_mut() {
                st.pending.push(i);
            }
        }
        let grow = self.lag_growth();
        if grow == 0.0 {
            // Level with the structure's clock: all at once (an empty structure builds in bulk).
            let ids: Vec<u32> = holds.iter().map(|(h, ..)| h.index).collect();
            let kinetic = !self.is_stepped();
            for (h, hold, _) in &holds {
                let i = h.index as usize;
                if kinetic {
                    self.bodies[i] = Some(Body {
                        shape: self.shape(h.index, hold),
                        plan: self.plan_of(h.index, hold),
                    });
                }
                self.plans[i] = self.plans[i].wrapping_add(1);
            }
            if let Some(s) = self.structure.as_mut() {
                s.insert_many(&ids, &self.bodies, self.clock.kds, &mut self.changes);
            }
            self.stats.inserts += ids.len() as u64;
            self.step.inserts += ids.len() as u64;
            self.book.apply(&mut self.changes, self.clock.kds);
            return;
        }
        for (h, hold, _) in holds {
            let i = h.index;
            let g = grow + self.own_reach(&hold);
            self.put_in(i, hold, g);
            self.book.apply(&mut self.changes, self.clock.kds);
        }
    }
}

impl BroadPhaseCore {
    /// A fresh structure holding every proxy, at the structure's clock, level with the
    /// positions (a stepped world going back to kinetic).
    pub(super) fn build_structure(&mut self) {
        let mut s = new_structure(self.in_loose_grid(), self.clock.dt);
        let mut ids = Vec::new();
        self.body_slots();
        for i in 0..self.proxies.len() {
            let Some(p) = self.proxies[i] else { continue };
            self.bodies[i] = Some(Body {
                shape: self.shape(i as u32, &p.hold),
                plan: self.plan_of(i as u32, &p.hold),
            });
            self.plans[i] = self.plans[i].wrapping_add(1);
            ids.push(i as u32);
        }
        s.insert_many(&ids, &self.bodies, self.clock.kds, &mut self.changes);
        self.structure = Some(s);
        self.stats.inserts += ids.len() as u64;
        self.step.inserts += ids.len() as u64;
        self.book.apply(&mut self.changes, self.clock.kds);
    }
}

/// Moving bodies whose radii (the middle 98%) are within this factor get the loose grid:
/// bodies re-planned every few steps keep their regions there (measured on rains and piles of
/// alike sizes against debris fields of sizes spread over three orders, the rapier bench's
/// scenes at 1e3 to 5e4 bodies).
const SIZES_ALIKE: Real = 8.0;

/// A fresh, empty structure for an engine stepping by `dt`: the loose grid, or the
/// hierarchical grid.
fn new_structure(loose: bool, dt: Real) -> Structure {
    // Both grids give a fast body's region at least a step of flight: a shot then costs an
    // event a step, not one per cell or per two widths it flies.
    if loose {
        Box::new(
            LooseGrid::new()
                .with_margin(REGION_MARGIN)
                .with_horizon(REGION_STEPS * dt)
                .with_least_flight(dt),
        )
    } else {
        Box::new(Grid::new().with_least_flight(dt))
    }
}

/// The structure's shape for the box `min..max` at rest: the cuboid, or the ball about a box
/// too thin to be one.
fn box_shape(min: Vec3, max: Vec3) -> Shape {
    let half = (max - min) / 2.0;
    match ConvexShape::cuboid(half) {
        Ok(cuboid) => cuboid.into_shape(),
        Err(_) => Shape::Ball {
            radius: half.length().max(1e-9),
        },
    }
}

/// Whether the first colliders `holds` go in the loose grid: the middle 98% of the moving
/// ones' radii are within [`SIZES_ALIKE`] (a rain, a pile). Otherwise (a debris field, where
/// small pieces drift as fast as large ones and would leave regions sized by their own width
/// every few steps), and for none, the hierarchical grid.
fn loose_grid_fits(holds: &[(Key, Bound, Option<BodyState>)]) -> bool {
    sizes_alike(holds.iter().filter_map(|(_, h, _)| match *h {
        Bound::Moving { radius, .. } => Some(radius),
        _ => None,
    }))
}

/// Whether the middle 98% of `radii` are within [`SIZES_ALIKE`] (false for none).
fn sizes_alike(radii: impl IntoIterator<Item = Real>) -> bool {
    let mut r: Vec<Real> = radii
        .into_iter()
        .filter(|r| *r > 0.0 && r.is_finite())
        .collect();
    if r.is_empty() {
        return false;
    }
    // The radii at two ranks, each found in linear time (no need to sort them all).
    let mut pick = |q: Real| {
        let rank = ((r.len() - 1) as Real * q).round() as usize;
        *r.select_nth_unstable_by(rank, Real::total_cmp).1
    };
    let (large, small) = (pick(0.99), pick(0.01));
    large <= SIZES_ALIKE * small
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loose_grid_for_alike_middle_sizes() {
        assert!(!sizes_alike([]));
        assert!(sizes_alike([1.0; 50]));
        // One boulder among pebbles is outside the middle 98%.
        let mut r = vec![1.0; 200];
        r.push(1000.0);
        assert!(sizes_alike(r.iter().copied()));
        let spread_wide: Vec<Real> = (0..200).map(|i| 1.0 + i as Real).collect();
        assert!(!sizes_alike(spread_wide));
        // The ranks as a full sort gives them, on spreads either side of the line.
        let mut both = [0; 2];
        for k in 0..400u32 {
            let spread = 1.0 + 14.0 * (k as Real / 400.0);
            let n = 1 + (k as usize * 37) % 299;
            let r: Vec<Real> = (0..n)
                .map(|i| 1.0 + (spread - 1.0) * ((i * 7919 + k as usize) % n) as Real / n as Real)
                .collect();
            let mut sorted = r.clone();
            sorted.sort_unstable_by(Real::total_cmp);
            let at = |q: Real| sorted[((n - 1) as Real * q).round() as usize];
            let want = at(0.99) <= SIZES_ALIKE * at(0.01);
            assert_eq!(sizes_alike(r), want, "spread {spread}, {n} radii");
            both[usize::from(want)] += 1;
        }
        assert!(both[0] > 0 && both[1] > 0, "{both:?}");
    }
}
