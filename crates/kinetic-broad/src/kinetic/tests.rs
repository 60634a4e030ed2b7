//! The core's own tests (its private tables), on a toy engine: balls falling onto a ground
//! under a semi-implicit Euler integrator, coming to rest on it.

use super::*;
use crate::{BodyState, ColliderStatus, Engine, EngineStep, PairEvent};

/// A collider of the toy engine: a ball on a body, or a fixed box.
#[derive(Clone, Copy)]
enum Part {
    Ball { body: Key, radius: Real },
    Box { min: Vec3, max: Vec3 },
}

#[derive(Default)]
struct Toy {
    bodies: Vec<(Key, BodyState)>,
    colliders: Vec<(Key, Part, bool)>,
    /// Colliders changed since the last call, and removed.
    modified: Vec<Key>,
    removed: Vec<Key>,
    /// The pairs the toy's narrow phase holds.
    pairs: Vec<(Key, Key)>,
    /// Whether it gives its colliders' boxes ([`Engine::bounds`]), and boxes enlarged
    /// about them ([`Engine::enlarged`]: grown by 0.1, moved with every collider it lists
    /// as moved).
    boxes: bool,
    enlarged: bool,
    /// Whether its narrow phase tests pairs at the poses it has now ([`Engine::ahead`]
    /// zero), rather than over the coming step.
    at_poses: bool,
}

const STEP: EngineStep = EngineStep {
    dt: 1.0 / 60.0,
    substeps: 1.0,
};

impl Engine for Toy {
    fn collider(&self, c: Key, slack: Slack) -> ColliderStatus {
        match self.colliders.iter().find(|(k, ..)| *k == c) {
            None => ColliderStatus::Missing,
            Some((_, _, false)) => ColliderStatus::Disabled,
            Some((_, Part::Ball { body, radius }, true)) => {
                ColliderStatus::Held(Bound::moving(*body, *radius, 0.01, slack))
            }
            Some((_, Part::Box { min, max }, true)) => {
                ColliderStatus::Held(Bound::fixed(*min, *max, 0.01))
            }
        }
    }

    fn body(&self, b: Key) -> Option<BodyState> {
        self.bodies.iter().find(|(k, _)| *k == b).map(|(_, s)| *s)
    }

    fn ahead(&self, _b: Key, d: Vec3) -> Vec3 {
        if self.at_poses { Vec3::ZERO } else { d }
    }

    fn enlarged(&self, c: Key) -> Option<Aabb> {
        let b = self.bounds(c).filter(|_| self.enlarged)?;
        Some(b.grown(Vec3::splat(0.1)))
    }

    fn bounds(&self, c: Key) -> Option<Aabb> {
        if !self.boxes {
            return None;
        }
        let margin = Vec3::splat(0.01);
        match self.colliders.iter().find(|(k, ..)| *k == c)?.1 {
            Part::Ball { body, radius } => {
                let centre = self.body(body)?.centre;
                let r = Vec3::splat(radius) + margin;
                Some(Aabb::new(centre - r, centre + r))
            }
            Part::Box { min, max } => Some(Aabb::new(min - margin, max + margin)),
        }
    }
}

impl Toy {
    /// A ground (its top at 0) and balls of radius 0.5 on bodies at `xs`, 1 up.
    fn new(xs: &[Real]) -> Toy {
        let mut toy = Toy::default();
        let ground = Key::new(0, 0);
        let part = Part::Box {
            min: Vec3::new(-50.0, -1.0, -50.0),
            max: Vec3::new(50.0, 0.0, 50.0),
        };
        toy.colliders.push((ground, part, true));
        for (k, &x) in xs.iter().enumerate() {
            let body = Key::new(k as u32, 0);
            let state = BodyState {
                centre: Vec3::new(x, 1.0, 0.0),
                velocity: Vec3::ZERO,
                sleeping: false,
            };
            toy.bodies.push((body, state));
            let radius = 0.5;
            toy.colliders
                .push((Key::new(k as u32 + 1, 0), Part::Ball { body, radius }, true));
        }
        toy.modified = toy.colliders.iter().map(|(k, ..)| *k).collect();
        toy
    }

    /// One step: the call with the user's changes, the bodies' motion (falling, stopped by
    /// the ground), the call after the position update. Validates after each call.
    fn step(&mut self, core: &mut BroadPhaseCore) {
        let mut events = Vec::new();
        let (modified, removed) = (
            std::mem::take(&mut self.modified),
            std::mem::take(&mut self.removed),
        );
        core.update(STEP, self, &modified, &removed, &mut events);
        self.apply(&events);
        events.clear();
        self.check(core);
        let mut moved = Vec::new();
        for (body, s) in &mut self.bodies {
            if s.sleeping {
                // Asleep: it does not move, and the engine does not list it.
                continue;
            }
            s.velocity.y -= 9.81 * STEP.dt;
            s.centre += s.velocity * STEP.dt;
            if s.centre.y < 0.5 {
                // Stopped by the ground; it slides on it without friction.
                s.centre.y = 0.5;
                s.velocity.y = 0.0;
            }
            moved.extend(
                self.colliders
                    .iter()
                    .filter(|(_, p, _)| matches!(p, Part::Ball { body: b, .. } if b == body))
                    .map(|(k, ..)| *k),
            );
        }
        core.update(STEP, self, &moved, &[], &mut events);
        self.apply(&events);
        self.check(core);
    }

    fn apply(&mut self, events: &[PairEvent]) {
        for e in events {
            match *e {
                PairEvent::Add(a, b) => {
                    assert!(a.index < b.index, "{e:?} out of order");
                    assert!(!self.pairs.contains(&(a, b)), "{e:?} added twice");
                    self.pairs.push((a, b));
                }
                PairEvent::Delete(a, b) => {
                    let at = self.pairs.iter().position(|p| *p == (a, b));
                    self.pairs.swap_remove(at.expect("a pair the engine has"));
                }
            }
        }
    }

    fn check(&self, core: &BroadPhaseCore) {
        let keys = self.colliders.iter().map(|(k, ..)| *k);
        core.validate(self, keys).expect("a valid broad phase");
        assert_eq!(core.stats().pairs, self.pairs.len());
    }

    fn remove(&mut self, c: Key) {
        self.colliders.retain(|(k, ..)| *k != c);
        self.removed.push(c);
    }
}

#[test]
fn the_mover_table_follows_the_held_colliders_and_validate_checks_it() {
    let mut toy = Toy::new(&[0.0, 2.0]);
    let mut core = BroadPhaseCore::new().with_audit();
    for _ in 0..5 {
        toy.step(&mut core);
    }
    let (ground, ball, other) = (Key::new(0, 0), Key::new(1, 0), Key::new(2, 0));
    assert_eq!(core.movers[ground.index as usize], Some((0, u32::MAX)));
    assert_eq!(core.movers[ball.index as usize], Some((0, 0)));
    // A stale entry (the ball taken for fixed) is caught.
    let kept = core.movers[ball.index as usize];
    core.movers[ball.index as usize] = Some((0, u32::MAX));
    let keys: Vec<Key> = toy.colliders.iter().map(|(k, ..)| *k).collect();
    let err = core
        .validate(&toy, keys.iter().copied())
        .expect_err("a stale mover entry");
    assert!(err.contains("mover"), "{err}");
    core.movers[ball.index as usize] = kept;
    // A removed collider leaves no entry and its pairs go silently; the other ball still
    // falls, is re-planned, and comes to rest on the ground with its pair handed over.
    toy.remove(other);
    for _ in 0..60 {
        toy.step(&mut core);
    }
    assert_eq!(core.movers[other.index as usize], None);
    assert!(!core.knows(other));
    assert!(core.stats().replans > 0);
    assert!(core.has_pair(ground, ball));
    assert_eq!(toy.pairs, vec![(ground, ball)]);
    assert_eq!(core.audit_error(), None);
}

#[test]
fn resting_bodies_cost_nothing_and_a_disabled_collider_drops_out() {
    let mut toy = Toy::new(&[0.0, 3.0, 6.0]);
    let mut core = BroadPhaseCore::new().with_audit();
    for _ in 0..120 {
        toy.step(&mut core);
    }
    // All three rest on the ground: planned at rest, no events, no re-plans.
    let before = core.stats();
    for _ in 0..30 {
        toy.step(&mut core);
        assert_eq!(core.last_step().events, 0);
        assert_eq!(core.last_step().replans, 0);
    }
    assert_eq!(core.stats().replans, before.replans);
    assert_eq!(toy.pairs.len(), 3);
    // The balls are 3 apart: never a pair between two of them.
    assert!(toy.pairs.iter().all(|(a, _)| a.index == 0));
    // Disabling a collider drops it and its pair without an event.
    let middle = Key::new(2, 0);
    toy.colliders
        .iter_mut()
        .find(|(k, ..)| *k == middle)
        .expect("held")
        .2 = false;
    toy.modified.push(middle);
    toy.pairs.retain(|(_, b)| *b != middle);
    toy.step(&mut core);
    assert!(!core.knows(middle));
    assert_eq!(core.held(), 3);
    assert_eq!(core.audit_error(), None);
}

/// An engine that keeps enlarged boxes of its own: the world steps on them for good, keeps
/// no plans (it reads no body to fit one), and hands over the pairs whose boxes overlap.
#[test]
fn a_world_on_the_engine_s_enlarged_boxes_keeps_no_plans() {
    let mut toy = Toy::new(&[0.0, 0.9, 5.0]);
    toy.boxes = true;
    toy.enlarged = true;
    let mut core = BroadPhaseCore::new().with_audit();
    for _ in 0..60 {
        toy.step(&mut core);
    }
    assert_eq!(core.structure_name(), "stepped");
    assert!(!core.reads_every_move());
    assert_eq!(core.motions.iter().count(), 0);
    // The three balls on the ground, and the two 0.9 apart (radius 0.5) with each other.
    let mut pairs = toy.pairs.clone();
    pairs.sort_unstable();
    let k = |i| Key::new(i, 0);
    assert_eq!(
        pairs,
        [(k(0), k(1)), (k(0), k(2)), (k(0), k(3)), (k(1), k(2))]
    );
    // A ball moved onto another body is held afresh, on it.
    toy.colliders[3].1 = Part::Ball {
        body: k(0),
        radius: 0.5,
    };
    toy.modified.push(k(3));
    for _ in 0..5 {
        toy.step(&mut core);
    }
    assert!(core.has_pair(k(1), k(3)) && core.has_pair(k(2), k(3)));
    assert_eq!(core.movers[3], Some((0, 0)));
    assert_eq!(core.audit_error(), None);
}

#[test]
fn bodies_at_rest_are_held_by_fat_boxes_until_they_move() {
    let mut toy = Toy::new(&[0.0, 3.0]);
    toy.boxes = true;
    // Kinetic throughout: the structure is the caller's.
    let mut core = BroadPhaseCore::new().with_loose_grid(true).with_audit();
    for _ in 0..120 {
        toy.step(&mut core);
    }
    // Both rest on the ground, each held by a box: no events, no re-plans.
    let boxed = core.stats().boxed;
    assert!(boxed >= 2, "{:?}", core.stats());
    let (left, right) = (Key::new(1, 0), Key::new(2, 0));
    for i in [left, right] {
        assert!(core.proxies[i.index as usize].expect("held").fat.is_some());
    }
    for _ in 0..30 {
        toy.step(&mut core);
        assert_eq!(core.last_step().events, 0);
        assert_eq!(core.last_step().replans, 0);
    }
    assert_eq!(core.stats().boxed, boxed);
    // A kick sends the left ball sliding at the right one: it leaves its box, is planned
    // again, and the pair is handed over before the balls touch (margins included).
    toy.bodies[0].1.velocity = Vec3::new(3.0, 0.0, 0.0);
    let mut met = false;
    for _ in 0..60 {
        toy.step(&mut core);
        let gap = (toy.bodies[0].1.centre - toy.bodies[1].1.centre).length() - 1.02;
        if gap <= 0.0 {
            met = true;
            assert!(
                toy.pairs.contains(&(left, right)),
                "touching without the pair"
            );
        }
    }
    assert!(met, "the balls never met");
    assert!(
        core.proxies[left.index as usize]
            .expect("held")
            .fat
            .is_none()
    );
    assert_eq!(core.audit_error(), None);
}

/// A small deterministic generator in `-1..1`.
fn jitter(s: &mut u64) -> Real {
    *s = s
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*s >> 11) as Real / (1u64 << 52) as Real - 1.0
}

/// Every two balls whose surfaces (margins included) touch are a pair the toy has.
fn touching_pairs_are_held(toy: &Toy) {
    for (a, pa, _) in &toy.colliders {
        for (b, pb, _) in &toy.colliders {
            let (Part::Ball { body: x, .. }, Part::Ball { body: y, .. }) = (pa, pb) else {
                continue;
            };
            if a.index >= b.index {
                continue;
            }
            let (x, y) = (toy.body(*x).expect("a body"), toy.body(*y).expect("a body"));
            if (x.centre - y.centre).length() <= 1.02 {
                assert!(toy.pairs.contains(&(*a, *b)), "{a:?} and {b:?} touch");
            }
        }
    }
}

#[test]
fn a_restless_world_steps_and_a_calm_one_goes_back_to_kinetic() {
    // With the engine's boxes, and without (the balls of the holds about the bodies).
    for boxes in [true, false] {
        jostle_and_calm(boxes);
    }
}

fn jostle_and_calm(boxes: bool) {
    // 100 balls on the ground, a little more than a diameter apart.
    let xs: Vec<Real> = (0..100).map(|k| k as Real * 1.05).collect();
    let mut toy = Toy::new(&xs);
    toy.boxes = boxes;
    let mut core = BroadPhaseCore::new().with_audit();
    let mut s = 5;
    // Jostled: a fresh random push every step, so that no plan holds.
    for _ in 0..90 {
        for (_, b) in &mut toy.bodies {
            b.velocity.x = 2.0 * jitter(&mut s);
            b.velocity.z = 2.0 * jitter(&mut s);
        }
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
    }
    assert_eq!(core.structure_name(), "stepped", "{:?}", core.stats());
    // Calm: every ball stops where it is; the world goes back to its kinetic structure, the
    // pairs the engine has carried over. Fat boxes hold the calm world's pairs at once, and
    // a world whose pairs they hold prices a kinetic step only every 96 updates: it goes back
    // after two such prices running.
    for (_, b) in &mut toy.bodies {
        b.velocity = Vec3::ZERO;
    }
    for _ in 0..250 {
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
    }
    assert_eq!(core.structure_name(), "loose-grid", "{:?}", core.stats());
    assert!(core.stats().switches >= 1);
    // Jostled again: stepped again.
    for _ in 0..60 {
        for (_, b) in &mut toy.bodies {
            b.velocity.x = 2.0 * jitter(&mut s);
        }
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
    }
    assert_eq!(core.structure_name(), "stepped", "{:?}", core.stats());
    assert_eq!(core.audit_error(), None);
}

#[test]
fn a_world_flying_apart_stays_stepped() {
    // 100 balls in a row sliding apart on the ground at up to 2 units a second: every plan
    // holds, but the loose grid would re-anchor each ball every few steps.
    let xs: Vec<Real> = (0..100).map(|k| k as Real * 1.05).collect();
    let mut toy = Toy::new(&xs);
    toy.boxes = true;
    for (k, (_, b)) in toy.bodies.iter_mut().enumerate() {
        b.velocity.x = (k as Real - 50.0) * 0.04;
    }
    let mut core = BroadPhaseCore::new().with_audit();
    for _ in 0..90 {
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
    }
    assert_eq!(core.structure_name(), "stepped", "{:?}", core.stats());
    assert_eq!(core.stats().switches, 0, "{:?}", core.stats());
    assert_eq!(core.audit_error(), None);
}

#[test]
fn a_stepped_world_hands_over_what_a_kinetic_one_does_on_a_calm_world() {
    // The same falling, resting balls, stepped or not: the same touching pairs at the end.
    let xs: Vec<Real> = (0..20).map(|k| k as Real * 0.9).collect();
    let (mut a, mut b) = (Toy::new(&xs), Toy::new(&xs));
    a.boxes = true;
    b.boxes = true;
    let mut own = BroadPhaseCore::new().with_audit();
    let mut kinetic = BroadPhaseCore::new().with_loose_grid(true);
    for _ in 0..120 {
        a.step(&mut own);
        b.step(&mut kinetic);
        touching_pairs_are_held(&a);
        touching_pairs_are_held(&b);
    }
    let touching = |t: &Toy| -> Vec<(Key, Key)> {
        let mut p: Vec<_> = t.pairs.clone();
        p.sort_unstable();
        p
    };
    assert_eq!(touching(&a), touching(&b));
    assert_eq!(own.audit_error(), None);
}

#[test]
fn a_world_fallen_asleep_costs_nothing_a_step_and_a_woken_body_is_seen() {
    // 60 balls jostled on the ground, 1.05 apart, then all asleep.
    let xs: Vec<Real> = (0..60).map(|k| k as Real * 1.05).collect();
    let mut toy = Toy::new(&xs);
    toy.boxes = true;
    let mut core = BroadPhaseCore::new().with_audit();
    let mut s = 3;
    for _ in 0..30 {
        for (_, b) in &mut toy.bodies {
            b.velocity.x = jitter(&mut s);
        }
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
    }
    assert!(core.is_stepped(), "{:?}", core.stats());
    for (_, b) in &mut toy.bodies {
        (b.velocity, b.sleeping) = (Vec3::ZERO, true);
    }
    for step in 0..40 {
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
        // From the second call after the last move on, the calls find nothing to do.
        let quiet = core.stepped.as_ref().is_some_and(|st| st.quiet());
        assert_eq!(quiet, step >= 1, "step {step}: {:?}", core.stats());
    }
    assert!(
        core.is_stepped(),
        "a quiet world went kinetic: {:?}",
        core.stats()
    );
    // One ball wakes and rolls into its neighbour: the pair is seen at once.
    let (_, b) = &mut toy.bodies[10];
    (b.velocity, b.sleeping) = (Vec3::new(3.0, 0.0, 0.0), false);
    let (a, c) = (Key::new(11, 0), Key::new(12, 0));
    let mut met = false;
    for _ in 0..20 {
        toy.step(&mut core);
        touching_pairs_are_held(&toy);
        met |= toy.pairs.contains(&(a, c));
    }
    assert!(met, "the woken ball's pair was never handed over");
    assert_eq!(core.audit_error(), None);
}

/// Whether the pairs the toy has are exactly those of its colliders whose boxes overlap now.
fn pairs_of_boxes_now(toy: &Toy) -> bool {
    let mut want = Vec::new();
    for (k, (a, ..)) in toy.colliders.iter().enumerate() {
        for (b, ..) in &toy.colliders[k + 1..] {
            if let (Some(x), Some(y)) = (toy.bounds(*a), toy.bounds(*b))
                && x.overlaps(&y)
            {
                want.push(if a.index < b.index {
                    (*a, *b)
                } else {
                    (*b, *a)
                });
            }
        }
    }
    let mut have = toy.pairs.clone();
    want.sort_unstable();
    have.sort_unstable();
    want == have
}

#[test]
fn an_engine_that_tests_pairs_where_they_are_gets_the_pairs_of_boxes_overlapping_now() {
    // 100 balls on the ground 1.05 apart (boxes 0.03 apart): jostled (stepped), then calm
    // (kinetic) with one ball rolling into its neighbour. An engine that looks ahead over
    // the step is handed pairs before their boxes meet; one that tests pairs at its poses
    // now ([`Engine::ahead`] zero, as rapier) gets those of the boxes overlapping now.
    for at_poses in [true, false] {
        let xs: Vec<Real> = (0..100).map(|k| k as Real * 1.05).collect();
        let mut toy = Toy::new(&xs);
        (toy.boxes, toy.at_poses) = (true, at_poses);
        let mut core = BroadPhaseCore::new().with_audit();
        let (mut s, mut now, mut ahead) = (9, 0, 0);
        let mut modes = Vec::new();
        let mut step = |toy: &mut Toy, core: &mut BroadPhaseCore| {
            toy.step(core);
            touching_pairs_are_held(toy);
            if pairs_of_boxes_now(toy) {
                now += 1;
            } else {
                ahead += 1;
            }
            modes.push(core.structure_name());
        };
        for _ in 0..90 {
            for (_, b) in &mut toy.bodies {
                b.velocity.x = 2.0 * jitter(&mut s);
            }
            step(&mut toy, &mut core);
        }
        for (_, b) in &mut toy.bodies {
            b.velocity = Vec3::ZERO;
        }
        for _ in 0..250 {
            step(&mut toy, &mut core);
        }
        toy.bodies[40].1.velocity.x = 0.5;
        for _ in 0..30 {
            step(&mut toy, &mut core);
        }
        assert!(
            modes.contains(&"stepped") && modes.contains(&"loose-grid"),
            "{modes:?}"
        );
        if at_poses {
            assert_eq!(ahead, 0, "steps with pairs of boxes apart");
        } else {
            assert!(ahead > 10, "{ahead} steps looking ahead, {now} not");
        }
        assert_eq!(core.audit_error(), None);
    }
}
