//! The pairs handed to the engine: the structure's candidate pairs, counted as the structure adds
//! and drops them, turned into add and delete events.
//!
//! A candidate is handed to the engine (added) in a call whose window (the positions' time to
//! the end of the step the structure has looked ahead over) it is a candidate in at any
//! moment, if the two proxies can meet within that window: two balls whose centres come within
//! the sum of their radii ([`proxies_meet`]), or any other two shapes (their boxes overlap, or
//! they would not be candidates). It is deleted in a later call whose whole
//! window it is absent from: it stopped being a candidate before the positions' time and has
//! not come back by the window's end, or its two balls stay apart over the whole window.

use kinetic_core::kds::{PairChange, ordered_pair};
use kinetic_core::{Body, Real, Shape, Vec3};
use rustc_hash::FxHashMap;

/// One pair's state.
#[derive(Clone, Copy, Debug)]
struct PairState {
    /// How many reasons the structure has to keep the pair (0: none now).
    count: i32,
    /// Whether the engine has it (an add went out and no delete since).
    reported: bool,
    /// When its count last fell to 0.
    dropped_at: Real,
    /// When to ask the gate again while the plans are still those of versions `plans`: for
    /// a pair not reported, a time before which its proxies cannot meet (asked again once a
    /// window ends past it); for a reported one, a time before which they surely still
    /// overlap (asked again once a window starts at or past it).
    wake: Real,
    plans: (u32, u32),
}

/// The gate's answer for a pair: whether the proxies can meet within the window, and when
/// to ask again with the same plans: for a pair that cannot meet, a time before which it
/// cannot (asked again once a window ends past it); for one that can, a time before which
/// its proxies surely still overlap (asked again once a window starts past it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Gate {
    pub(crate) meet: bool,
    pub(crate) wake: Real,
}

/// What the pair book asks the engine to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum PairOut {
    Add(u32, u32),
    Delete(u32, u32),
}

/// The candidate pairs by collider index `(a, b)`, `a < b`.
#[derive(Debug, Default)]
pub(crate) struct PairBook {
    pairs: FxHashMap<(u32, u32), PairState>,
    /// Pairs whose count fell to 0 and that the engine may still have.
    dropped: Vec<(u32, u32)>,
    reported: usize,
    /// Whether the structure changed a pair since [`PairBook::take_changed`].
    changed: bool,
    /// Whether a pair or a proxy's plan changed since the last pass over the book.
    pending: bool,
    /// From the last pass: the least wake time of the reported pairs and of the others. Until
    /// a window starts at the first or ends past the second, with nothing pending and nothing
    /// dropped, a pass would change nothing and is skipped (a resting world costs nothing).
    quiet_until: (Real, Real),
}

impl PairBook {
    /// Counts the structure's changes, made at time `t`.
    pub(crate) fn apply(&mut self, changes: &mut Vec<PairChange>, t: Real) {
        self.changed |= !changes.is_empty();
        self.pending |= !changes.is_empty();
        for c in changes.drain(..) {
            let key = (c.a.min(c.b), c.a.max(c.b));
            let e = self.pairs.entry(key).or_insert(PairState {
                count: 0,
                reported: false,
                dropped_at: Real::NEG_INFINITY,
                wake: Real::NEG_INFINITY,
                plans: (u32::MAX, u32::MAX),
            });
            let before = e.count;
            e.count += c.delta;
            if before > 0 && e.count <= 0 {
                e.dropped_at = t;
                self.dropped.push(key);
            }
        }
    }

    /// Forgets every pair of collider `id` without events (it was removed: the engine drops its
    /// pairs itself). `changes` holds the structure's drops for its removal.
    pub(crate) fn forget(&mut self, id: u32, changes: &mut Vec<PairChange>) {
        self.changed = true;
        self.pending = true;
        for c in changes.drain(..) {
            let key = (c.a.min(c.b), c.a.max(c.b));
            if let Some(e) = self.pairs.remove(&key) {
                self.reported -= usize::from(e.reported);
            }
        }
        // Pairs that had already dropped out and wait for their `DeletePair`.
        let mut gone = Vec::new();
        self.dropped.retain(|&(a, b)| {
            let mine = a == id || b == id;
            if mine {
                gone.push((a, b));
            }
            !mine
        });
        for key in gone {
            if let Some(e) = self.pairs.remove(&key) {
                self.reported -= usize::from(e.reported);
            }
        }
    }

    /// Emits the events of one call whose window runs from the positions' time `t_pos` to
    /// `t_end`: a pair that dropped out before `t_pos` and is still out is deleted; every
    /// other pair is added or deleted as the gate (`gate(a, b)`) says. The gate is asked
    /// again only once its last answer runs out ([`Gate`]) or a proxy's plan changed
    /// (`plan(i)`, its plan's version).
    pub(crate) fn emit(
        &mut self,
        t_pos: Real,
        t_end: Real,
        gate: impl Fn(u32, u32) -> Gate,
        plan: impl Fn(u32) -> u32,
        out: &mut Vec<PairOut>,
    ) {
        if !self.pending
            && self.dropped.is_empty()
            && t_pos < self.quiet_until.0
            && t_end <= self.quiet_until.1
        {
            return;
        }
        let mut quiet = (Real::INFINITY, Real::INFINITY);
        let mut reported = self.reported;
        self.pairs.retain(|&(a, b), e| {
            if e.count <= 0 && e.dropped_at < t_pos {
                if e.reported {
                    out.push(PairOut::Delete(a, b));
                    reported -= 1;
                }
                return false;
            }
            let plans = (plan(a), plan(b));
            let due = if e.reported {
                e.wake <= t_pos
            } else {
                e.wake < t_end
            };
            if plans != e.plans || due {
                let g = gate(a, b);
                e.plans = plans;
                e.wake = g.wake;
                if g.meet != e.reported {
                    e.reported = g.meet;
                    if g.meet {
                        reported += 1;
                        out.push(PairOut::Add(a, b));
                    } else {
                        reported -= 1;
                        out.push(PairOut::Delete(a, b));
                    }
                }
            }
            if e.reported {
                quiet.0 = quiet.0.min(e.wake);
            } else {
                quiet.1 = quiet.1.min(e.wake);
            }
            true
        });
        self.reported = reported;
        self.pending = false;
        self.quiet_until = quiet;
        let pairs = &self.pairs;
        self.dropped
            .retain(|key| pairs.get(key).is_some_and(|e| e.count <= 0));
        // The map's order is not the pairs' order: events go out sorted.
        out.sort_unstable();
    }

    /// Notes that a proxy's plan changed: the next call passes over the book.
    pub(crate) fn touch(&mut self) {
        self.pending = true;
    }

    /// Whether the structure changed a pair since the last call; clears the flag.
    pub(crate) fn take_changed(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    /// Pairs the engine has.
    pub(crate) fn reported(&self) -> usize {
        self.reported
    }

    /// Pairs the structure holds now.
    pub(crate) fn candidates(&self) -> usize {
        self.pairs.values().filter(|e| e.count > 0).count()
    }

    /// Checks the book against itself: counts are never negative, the reported count is
    /// right and (`settled`, between calls) every candidate whose proxies can meet in the
    /// window (`meet`) is reported.
    pub(crate) fn audit(
        &self,
        settled: bool,
        meet: impl Fn(u32, u32) -> bool,
    ) -> Result<(), String> {
        let mut reported = 0;
        for (&(a, b), e) in &self.pairs {
            if e.count < 0 {
                return Err(format!("pair ({a}, {b}): count {}", e.count));
            }
            if settled && e.count > 0 && !e.reported && meet(a, b) {
                return Err(format!(
                    "pair ({a}, {b}) is a candidate the engine does not have (asked again at \
                     {}, plans {:?})",
                    e.wake, e.plans
                ));
            }
            reported += usize::from(e.reported);
        }
        if reported != self.reported {
            return Err(format!(
                "{} pairs reported, {reported} marked so",
                self.reported
            ));
        }
        Ok(())
    }

    /// The pairs the engine has by this book, in no order.
    pub(crate) fn reported_pairs(&self) -> Vec<(u32, u32)> {
        self.pairs
            .iter()
            .filter(|(_, e)| e.reported)
            .map(|(k, _)| *k)
            .collect()
    }

    /// Takes the engine's pairs `had` (each `(a, b)` with `a < b`) as handed over: those the
    /// book holds are marked so, to be asked at the next pass; the others go to `gone`, to be
    /// deleted.
    pub(crate) fn adopt(&mut self, had: &[(u32, u32)], gone: &mut Vec<(u32, u32)>) {
        for key in had {
            match self.pairs.get_mut(key) {
                Some(e) if !e.reported => {
                    e.reported = true;
                    e.plans = (u32::MAX, u32::MAX);
                    self.reported += 1;
                }
                Some(_) => {}
                None => gone.push(*key),
            }
        }
        self.pending = true;
    }

    /// Whether the engine has pair `(a, b)` by this book.
    pub(crate) fn has(&self, a: u32, b: u32) -> bool {
        self.pairs
            .get(&ordered_pair(a, b))
            .is_some_and(|e| e.reported)
    }
}

/// The gate for proxies `a` and `b` over the window from `t0` to `t1` ([`Gate`]): whether
/// they can meet ([`proxies_meet`]), and when to ask again ([`proxies_overlap_until`] for
/// proxies that can, [`apart_after`] for proxies that cannot).
pub(crate) fn proxies_gate(a: &Body, b: &Body, t0: Real, t1: Real) -> Gate {
    if proxies_meet(a, b, t0, t1) {
        Gate {
            meet: true,
            wake: proxies_overlap_until(a, b, t0),
        }
    } else {
        Gate {
            meet: false,
            wake: apart_after(a, b, t0, t1),
        }
    }
}

/// The rounding allowance for proxies `a` and `b` at positions `pa` and `pb`.
fn tolerance(a: &Body, b: &Body, pa: Vec3, pb: Vec3) -> Real {
    let reach = a.shape.outer_radius() + b.shape.outer_radius();
    1e-9 * (reach + pa.abs().max_element() + pb.abs().max_element())
}

/// The least time from `t0` in which the relative motion of `a` and `b` can cover `gap`:
/// the first tau with `|dv| tau + |da| tau^2 / 2 = gap`, a hair short for rounding. `None`
/// for a gap that is not positive (or NaN).
fn time_to_cover(a: &Body, b: &Body, t0: Real, gap: Real) -> Option<Real> {
    if gap.is_nan() || gap <= 0.0 {
        return None;
    }
    let d1 = (a.plan.velocity_at(t0) - b.plan.velocity_at(t0)).length();
    let d2 = ((a.plan.acceleration - b.plan.acceleration) * 0.5).length();
    let tau = 2.0 * gap / (d1 + (d1 * d1 + 4.0 * d2 * gap).sqrt());
    (!tau.is_nan()).then_some(tau * (1.0 - 1e-9))
}

/// A time before which proxies `a` and `b`, overlapping at `t0`, surely still overlap
/// (`t0` when they do not overlap at `t0`, or only by rounding): the depth of the overlap
/// less the most the relative velocity and acceleration can open. Balls by their centres'
/// distance, other shapes by their boxes'.
fn proxies_overlap_until(a: &Body, b: &Body, t0: Real) -> Real {
    let (pa, pb) = (a.plan.position_at(t0), b.plan.position_at(t0));
    let depth = match (&a.shape, &b.shape) {
        (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) => ra + rb - (pa - pb).length(),
        _ => {
            let ((alo, ahi), (blo, bhi)) = (swept_box(a, t0, t0), swept_box(b, t0, t0));
            (ahi - blo).min(bhi - alo).min_element()
        }
    };
    let depth = depth - 2.0 * tolerance(a, b, pa, pb);
    time_to_cover(a, b, t0, depth).map_or(t0, |tau| t0 + tau)
}

/// For proxies `a` and `b` that cannot meet between `t0` and `t1`, a time before which they
/// cannot meet, at least `t1`: beyond the window, the gap now less the most the relative
/// velocity and acceleration can close. Two balls' gap is that of their centres less the
/// radii; other shapes meet when their boxes do, and their gap is the larger of the boxes'
/// separation along an axis and the gap of the balls about the boxes (a box reaches as far
/// as its corners): the relative motion covers each before the boxes meet.
fn apart_after(a: &Body, b: &Body, t0: Real, t1: Real) -> Real {
    let (pa, pb) = (a.plan.position_at(t0), b.plan.position_at(t0));
    let gap = match (&a.shape, &b.shape) {
        (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) => (pa - pb).length() - ra - rb,
        _ => {
            // Each box about its position now, its own box looked up once.
            let ((alo, ahi), (blo, bhi)) = (a.local_box(), b.local_box());
            let apart = ((pb + blo) - (pa + ahi)).max((pa + alo) - (pb + bhi));
            let reach = |lo: Vec3, hi: Vec3| lo.abs().max(hi.abs()).length();
            let balls = (pa - pb).length() - reach(alo, ahi) - reach(blo, bhi);
            apart.max_element().max(balls)
        }
    };
    let gap = gap - 2.0 * tolerance(a, b, pa, pb);
    time_to_cover(a, b, t0, gap).map_or(t1, |tau| t1.max(t0 + tau))
}

/// The time before which proxies `a` and `b`, on their plans, cannot meet, looking from `t0`:
/// minus infinity when they can meet between `t0` and `t1`, else [`apart_after`].
#[cfg(test)]
fn proxies_apart_until(a: &Body, b: &Body, t0: Real, t1: Real) -> Real {
    if proxies_meet(a, b, t0, t1) {
        Real::NEG_INFINITY
    } else {
        apart_after(a, b, t0, t1)
    }
}

/// Whether proxies `a` and `b`, on their plans, can meet between `t0` and `t1`: for two
/// balls, whether their centres come within the sum of their radii (conservatively: the
/// relative acceleration's part is bounded by its largest value over the window, and a
/// rounding allowance is added); for other shapes, whether the boxes they sweep over the
/// window overlap.
pub(crate) fn proxies_meet(a: &Body, b: &Body, t0: Real, t1: Real) -> bool {
    let (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) = (&a.shape, &b.shape) else {
        let ((alo, ahi), (blo, bhi)) = (swept_box(a, t0, t1), swept_box(b, t0, t1));
        let tol = 1e-9 * (a.shape.outer_radius() + b.shape.outer_radius())
            + 1e-12
                * alo
                    .abs()
                    .max(ahi.abs())
                    .max(blo.abs())
                    .max(bhi.abs())
                    .max_element();
        return (alo - bhi).max_element() <= tol && (blo - ahi).max_element() <= tol;
    };
    let (pa, pb) = (a.plan.position_at(t0), b.plan.position_at(t0));
    let d0 = pa - pb;
    let d1 = a.plan.velocity_at(t0) - b.plan.velocity_at(t0);
    let d2 = (a.plan.acceleration - b.plan.acceleration) * 0.5;
    let h = (t1 - t0).max(0.0);
    // Closest approach of the linear part over [0, h].
    let v2 = d1.length_squared();
    let s = if v2 > 0.0 {
        (-d0.dot(d1) / v2).clamp(0.0, h)
    } else {
        0.0
    };
    let gap = (d0 + d1 * s).length() - d2.length() * h * h;
    let reach = ra + rb;
    let tol = 1e-9 * (reach + pa.abs().max_element() + pb.abs().max_element());
    gap <= reach + tol
}

/// The box that `body` sweeps between `t0` and `t1`: its own box (when it does not spin and
/// its geometry gives one) or its outer ball's ([`Body::local_box`]), about each position on
/// the way.
fn swept_box(body: &Body, t0: Real, t1: Real) -> (Vec3, Vec3) {
    let plan = &body.plan;
    let (lo, hi) = body.local_box();
    let h = (t1 - t0).max(0.0);
    let (p0, v) = (plan.position_at(t0), plan.velocity_at(t0));
    let (mut plo, mut phi) = (p0, p0);
    for k in 0..3 {
        let (a, vk) = (plan.acceleration[k], v[k]);
        let at = |t: Real| p0[k] + (vk + 0.5 * a * t) * t;
        let turn = if a != 0.0 { -vk / a } else { 0.0 };
        for t in [h, if turn > 0.0 && turn < h { turn } else { 0.0 }] {
            plo[k] = plo[k].min(at(t));
            phi[k] = phi[k].max(at(t));
        }
    }
    (plo + lo, phi + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::{next, next_vec};
    use kinetic_core::FlightPlan;
    use kinetic_flight::ConvexShape;

    fn change(a: u32, b: u32, delta: i32) -> PairChange {
        PairChange { a, b, delta }
    }

    fn always(_: u32, _: u32) -> bool {
        true
    }

    /// A gate for which every pair can meet (asked again at every call).
    fn meets(_: u32, _: u32) -> Gate {
        Gate {
            meet: true,
            wake: Real::NEG_INFINITY,
        }
    }

    /// A gate for which every pair stays apart until `t` (the window's end).
    fn apart(t: Real) -> impl Fn(u32, u32) -> Gate {
        move |_, _| Gate {
            meet: false,
            wake: t,
        }
    }

    fn same_plans(_: u32) -> u32 {
        0
    }

    #[test]
    fn a_candidate_goes_to_the_engine_only_while_its_proxies_can_meet() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1)], 0.0);
        book.emit(0.0, 1.0, apart(1.0), same_plans, &mut out);
        assert!(out.is_empty());
        assert_eq!(book.candidates(), 1);
        book.audit(true, |_, _| false).unwrap();
        assert!(
            book.audit(true, always).is_err(),
            "a meeting candidate must be reported"
        );
        book.emit(1.0, 2.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 1)]);
        // Still a candidate, but its balls stay apart over the next window: deleted.
        out.clear();
        book.emit(2.0, 3.0, apart(3.0), same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Delete(0, 1)]);
        assert_eq!(book.reported(), 0);
        assert_eq!(book.candidates(), 1);
    }

    #[test]
    fn the_gate_is_asked_again_only_once_its_answer_runs_out_or_a_plan_changes() {
        use std::cell::Cell;
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1)], 0.0);
        let asked = Cell::new(0);
        // Apart until 3.5 on plans of version 0.
        let gate = |_, _| {
            asked.set(asked.get() + 1);
            Gate {
                meet: false,
                wake: 3.5,
            }
        };
        let version = Cell::new(0);
        let plan = |_| version.get();
        for t in [0.0, 1.0, 2.0, 2.4] {
            book.emit(t, t + 1.0, gate, plan, &mut out);
        }
        assert_eq!(asked.get(), 1, "windows ending by 3.5 reuse the answer");
        version.set(1);
        book.touch();
        book.emit(2.5, 3.5, gate, plan, &mut out);
        assert_eq!(asked.get(), 2, "a new plan asks again");
        assert!(out.is_empty());
        // A window past 3.5 asks again: the proxies meet now, and surely overlap until 4.2:
        // not asked again by windows starting before 4.2.
        let meet = |_, _| {
            asked.set(asked.get() + 1);
            Gate {
                meet: true,
                wake: 4.2,
            }
        };
        book.emit(3.0, 4.0, meet, plan, &mut out);
        book.emit(3.1, 4.1, meet, plan, &mut out);
        book.emit(4.1, 5.1, meet, plan, &mut out);
        assert_eq!(asked.get(), 3);
        assert_eq!(out, vec![PairOut::Add(0, 1)]);
        let never = |_, _| Gate {
            meet: false,
            wake: Real::INFINITY,
        };
        book.emit(4.2, 5.2, never, plan, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 1), PairOut::Delete(0, 1)]);
    }

    #[test]
    fn a_ball_and_a_box_meet_when_their_swept_boxes_overlap() {
        let slab = slab();
        // A ball of radius 0.5 falling from 3 at speed 2: its box reaches the slab's top at
        // t = 1.25.
        let ball = ball(
            0.5,
            FlightPlan::linear(Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, -2.0, 0.0)),
        );
        assert!(!proxies_meet(&ball, &slab, 0.0, 1.2));
        assert!(proxies_meet(&ball, &slab, 0.0, 1.3));
        assert!(proxies_meet(&slab, &ball, 1.2, 1.3));
        // Apart over [0, 1.2], and no earlier than the outer balls allow after.
        let until = proxies_apart_until(&ball, &slab, 0.0, 1.2);
        assert!((1.2..1.25).contains(&until), "{until}");
        // Two balls closing at 1 from a gap of 3: apart until 3 (to rounding).
        let (a, b) = (ball_at(1.0, 0.0, 0.0), ball_at(1.0, 5.0, -1.0));
        let until = proxies_apart_until(&a, &b, 0.0, 1.0);
        assert!((until - 3.0).abs() < 1e-6, "{until}");
        assert_eq!(proxies_apart_until(&a, &b, 0.0, 3.5), Real::NEG_INFINITY);
    }

    #[test]
    fn a_ball_coming_at_a_boxs_corner_is_not_woken_too_late() {
        // A cube of half-width 0.5 at the origin and a ball of radius 1 coming along the
        // diagonal: their boxes meet corner to corner when the ball's centre is at
        // (1.5, 1.5, 1.5), at t = 3.5, before the two outer balls could touch.
        let cube = Body {
            shape: ConvexShape::cuboid(Vec3::splat(0.5)).unwrap().into_shape(),
            plan: FlightPlan::at_rest(Vec3::ZERO),
        };
        let ball = ball(1.0, FlightPlan::linear(Vec3::splat(5.0), Vec3::splat(-1.0)));
        assert!(proxies_meet(&ball, &cube, 3.4, 3.6));
        for (a, b) in [(&ball, &cube), (&cube, &ball)] {
            let until = proxies_apart_until(a, b, 0.0, 1.0);
            assert!((1.0..=3.5).contains(&until), "{until}");
            assert!(!proxies_meet(a, b, 0.0, until));
        }
    }

    #[test]
    fn boxes_side_by_side_are_apart_until_their_gap_can_close() {
        // Unit cubes 0.1 apart along x, closing at 0.1: the balls about their boxes overlap,
        // but the boxes cannot meet before t = 1.
        let cube = |x: Real, v: Real| Body {
            shape: ConvexShape::cuboid(Vec3::splat(0.5)).unwrap().into_shape(),
            plan: FlightPlan::linear(Vec3::new(x, 0.0, 0.0), Vec3::new(v, 0.0, 0.0)),
        };
        let (a, b) = (cube(0.0, 0.0), cube(1.1, -0.1));
        let until = proxies_apart_until(&a, &b, 0.0, 0.5);
        assert!((until - 1.0).abs() < 1e-6, "{until}");
        assert!(proxies_meet(&a, &b, 0.0, 1.0 + 1e-6));
    }

    #[test]
    fn proxies_apart_until_a_time_meet_at_no_instant_before_it() {
        // Balls and boxes on random accelerated plans: at no instant before the bound do
        // their boxes overlap (balls: come within their radii).
        let body = |s: &mut u64| Body {
            shape: if next(s) < 0.5 {
                Shape::Ball {
                    radius: 0.05 + next(s),
                }
            } else {
                let half = next_vec(s) * 0.5 + Vec3::splat(0.05);
                ConvexShape::cuboid(half).unwrap().into_shape()
            },
            plan: FlightPlan::accelerated(
                next_vec(s) * 4.0,
                next_vec(s) - Vec3::splat(0.5),
                (next_vec(s) - Vec3::splat(0.5)) * 0.4,
            ),
        };
        let (mut s, mut apart) = (11, 0);
        for _ in 0..2000 {
            let (a, b) = (body(&mut s), body(&mut s));
            let until = proxies_apart_until(&a, &b, 0.0, 0.1);
            if until == Real::NEG_INFINITY {
                continue;
            }
            apart += 1;
            assert!(until >= 0.1, "{until}");
            for k in 0..100 {
                let t = until.min(100.0) * k as Real / 100.0;
                assert!(
                    !proxies_meet(&a, &b, t, t),
                    "{a:?} {b:?} meet at {t} < {until}"
                );
            }
        }
        assert!(apart > 500, "{apart} pairs apart");
    }

    #[test]
    fn overlapping_proxies_surely_overlap_until_their_depth_can_open() {
        // Balls of radius 1, 1.5 apart (depth 0.5), parting at 1: still overlapping until
        // 0.5, and not for sure any later.
        let (a, b) = (ball_at(1.0, 0.0, 0.0), ball_at(1.0, 1.5, 1.0));
        let until = proxies_overlap_until(&a, &b, 0.0);
        assert!((until - 0.5).abs() < 1e-6, "{until}");
        assert_eq!(
            proxies_gate(&a, &b, 0.0, 0.1),
            Gate {
                meet: true,
                wake: until
            }
        );
        // Not overlapping now (only meeting later in the window): asked again next call.
        let c = ball_at(1.0, 2.5, -1.0);
        assert_eq!(proxies_overlap_until(&a, &c, 0.0), 0.0);
        assert!(proxies_gate(&a, &c, 0.0, 1.0).meet);
        // At rest together: overlapping for ever.
        let d = ball_at(1.0, 1.5, 0.0);
        assert_eq!(proxies_overlap_until(&a, &d, 0.0), Real::INFINITY);
        // A ball resting 0.2 deep in a slab, falling at 2 from rest: the boxes' depth 0.2
        // opens no sooner than sqrt(0.2) (acceleration 2 is 1 t^2).
        let slab = slab();
        let rising = ball(
            0.5,
            FlightPlan::accelerated(
                Vec3::new(0.0, 0.3, 0.0),
                Vec3::ZERO,
                Vec3::new(0.0, 2.0, 0.0),
            ),
        );
        let until = proxies_overlap_until(&rising, &slab, 0.0);
        assert!((until - 0.2f64.sqrt()).abs() < 1e-6, "{until}");
    }

    /// A resting slab 20 wide and 1 thick, its top at 0 (a ground).
    fn slab() -> Body {
        Body {
            shape: ConvexShape::cuboid(Vec3::new(10.0, 0.5, 10.0))
                .unwrap()
                .into_shape(),
            plan: FlightPlan::at_rest(Vec3::new(0.0, -0.5, 0.0)),
        }
    }

    fn ball_at(radius: Real, x: Real, v: Real) -> Body {
        ball(
            radius,
            FlightPlan::linear(Vec3::new(x, 0.0, 0.0), Vec3::new(v, 0.0, 0.0)),
        )
    }

    fn ball(radius: Real, plan: FlightPlan) -> Body {
        Body {
            shape: Shape::Ball { radius },
            plan,
        }
    }

    #[test]
    fn balls_meet_when_their_paths_come_within_the_sum_of_the_radii() {
        let at = |x: Real| FlightPlan::at_rest(Vec3::new(x, 0.0, 0.0));
        let moving =
            |x: Real, v: Real| FlightPlan::linear(Vec3::new(x, 0.0, 0.0), Vec3::new(v, 0.0, 0.0));
        // At rest 2 apart: radii 1 + 0.99 miss, 1 + 1 touch.
        assert!(!proxies_meet(
            &ball(1.0, at(0.0)),
            &ball(0.99, at(2.0)),
            0.0,
            1.0
        ));
        assert!(proxies_meet(
            &ball(1.0, at(0.0)),
            &ball(1.0, at(2.0)),
            0.0,
            1.0
        ));
        // Closing at 1 per unit time from 3 apart: they touch at t = 1.
        let (a, b) = (ball(1.0, at(0.0)), ball(1.0, moving(3.0, -1.0)));
        assert!(!proxies_meet(&a, &b, 0.0, 0.99));
        assert!(proxies_meet(&a, &b, 0.0, 1.01));
        // Passing through each other within the window, apart at both ends.
        let b = ball(0.1, moving(-5.0, 10.0));
        assert!(proxies_meet(&ball(0.1, at(0.0)), &b, 0.0, 1.0));
        assert!(!proxies_meet(&ball(0.1, at(0.0)), &b, 0.0, 0.4));
        // Falling onto a resting ball: the relative acceleration is bounded over the window.
        let fall = |t: Real| {
            FlightPlan::accelerated(
                Vec3::new(0.0, 3.0, 0.0),
                Vec3::ZERO,
                Vec3::new(0.0, -2.0, 0.0),
            )
            .starting_at(t)
        };
        let rest = ball(1.0, at(0.0));
        assert!(proxies_meet(&rest, &ball(1.0, fall(0.0)), 0.0, 1.0));
        assert!(!proxies_meet(&rest, &ball(1.0, fall(0.0)), 0.0, 0.5));
        // Other shapes: always (their boxes overlap).
        let cube = Body {
            shape: Shape::Ball { radius: 1.0 },
            plan: at(100.0),
        };
        let mut other = cube.clone();
        other.shape = kinetic_flight::ConvexShape::cuboid(Vec3::ONE)
            .unwrap()
            .into_shape();
        assert!(proxies_meet(&cube, &other, 0.0, 1.0));
    }

    #[test]
    fn a_pair_that_comes_and_goes_within_a_window_is_added_then_deleted_later() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        // Window [0, 1]: the pair appears at 0.4 and leaves at 0.6.
        book.apply(&mut vec![change(3, 1, 1)], 0.4);
        book.apply(&mut vec![change(1, 3, -1)], 0.6);
        book.emit(0.0, 1.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(1, 3)]);
        assert!(book.has(1, 3));
        // Next call, positions at 0.5: it left at 0.6, within that call's window: kept.
        out.clear();
        book.emit(0.5, 1.5, meets, same_plans, &mut out);
        assert!(out.is_empty());
        // Positions at 1.0: it has been out since 0.6: deleted.
        book.emit(1.0, 2.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Delete(1, 3)]);
        assert_eq!(book.reported(), 0);
        book.audit(true, always).unwrap();
    }

    #[test]
    fn a_pair_needed_twice_stays_until_both_reasons_go() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 2, 1), change(0, 2, 1)], 0.0);
        book.emit(0.0, 1.0, meets, same_plans, &mut out);
        book.apply(&mut vec![change(0, 2, -1)], 0.5);
        book.emit(1.0, 2.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2)]);
        book.apply(&mut vec![change(0, 2, -1)], 1.5);
        book.emit(2.0, 3.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2), PairOut::Delete(0, 2)]);
    }

    #[test]
    fn a_removed_colliders_pairs_go_silently() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1), change(1, 2, 1)], 0.0);
        book.emit(0.0, 1.0, meets, same_plans, &mut out);
        book.apply(&mut vec![change(1, 2, -1)], 0.5);
        book.forget(1, &mut vec![change(0, 1, -1)]);
        out.clear();
        book.emit(2.0, 3.0, meets, same_plans, &mut out);
        assert!(out.is_empty(), "{out:?}");
        assert_eq!(book.reported(), 0);
        book.audit(true, always).unwrap();
    }
}
