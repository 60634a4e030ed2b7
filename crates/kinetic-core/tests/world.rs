//! The simulator with the brute-force reference: closed-form two- and three-ball cases,
//! `validate()` after every event.

use kinetic_core::{
    BruteForce, ContactEvent, ContactKind, FlightPlan, ObjectId, Response, Simulator, Vec3, Walls,
    WorldError, WorldKind,
};

fn world(kind: WorldKind, response: Response, walls: Option<Walls>) -> Simulator {
    Simulator::with_structure(kind, response, walls, Box::new(BruteForce::new())).unwrap()
}

/// Runs to `t`, validating after every event.
fn run(w: &mut Simulator, t: f64) -> Vec<ContactEvent> {
    w.validate().unwrap();
    while w.step(t).unwrap().is_some() {
        w.validate()
            .unwrap_or_else(|e| panic!("at {}: {e}", w.now()));
    }
    w.advance_to(t).unwrap();
    w.drain_events()
}

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

fn summary(events: &[ContactEvent]) -> Vec<(f64, u32, u32, ContactKind)> {
    events
        .iter()
        .map(|e| (e.time, e.a.0, e.b.0, e.kind))
        .collect()
}

#[test]
fn head_on() {
    let mut w = world(WorldKind::Free, Response::None, None);
    w.add_ball(1.0, FlightPlan::linear(v(-5.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(0.5, FlightPlan::linear(v(5.0, 0.0, 0.0), v(-2.0, 0.0, 0.0)))
        .unwrap();
    // Gap 10 - 1.5 closes at speed 3: begin at 8.5/3; centres pass and part at 11.5/3.
    let e = run(&mut w, 10.0);
    assert_eq!(e.len(), 2);
    assert!((e[0].time - 8.5 / 3.0).abs() < 1e-12 && e[0].kind == ContactKind::Begin);
    assert!((e[1].time - 11.5 / 3.0).abs() < 1e-12 && e[1].kind == ContactKind::End);
}

#[test]
fn glancing() {
    let mut w = world(WorldKind::Free, Response::None, None);
    // Offset 1.5 across, radii summing to 2: contact while |x| <= sqrt(4 - 2.25).
    w.add_ball(
        1.0,
        FlightPlan::linear(v(-10.0, 1.5, 0.0), v(1.0, 0.0, 0.0)),
    )
    .unwrap();
    w.add_ball(1.0, FlightPlan::at_rest(v(0.0, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 20.0);
    let half = (4.0f64 - 2.25).sqrt();
    assert_eq!(e.len(), 2);
    assert!((e[0].time - (10.0 - half)).abs() < 1e-12);
    assert!((e[1].time - (10.0 + half)).abs() < 1e-12);
}

#[test]
fn graze_is_begin_and_end_at_once() {
    let mut w = world(WorldKind::Free, Response::None, None);
    w.add_ball(0.5, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(0.5, FlightPlan::at_rest(v(5.0, 1.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 10.0);
    assert_eq!(
        summary(&e),
        vec![
            (5.0, 0, 1, ContactKind::Begin),
            (5.0, 0, 1, ContactKind::End)
        ]
    );
}

#[test]
fn near_miss_is_no_contact() {
    let mut w = world(WorldKind::Free, Response::None, None);
    w.add_ball(0.5, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(0.5, FlightPlan::at_rest(v(5.0, 1.0 + 1e-9, 0.0)))
        .unwrap();
    assert!(run(&mut w, 10.0).is_empty());
}

#[test]
fn overlapping_at_the_start() {
    let mut w = world(WorldKind::Free, Response::None, None);
    w.add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(1.0, FlightPlan::at_rest(v(1.0, 0.0, 0.0)))
        .unwrap();
    // Touching and static: begin at 0, never ends.
    w.add_ball(1.0, FlightPlan::at_rest(v(0.0, 10.0, 0.0)))
        .unwrap();
    w.add_ball(1.0, FlightPlan::at_rest(v(0.0, 12.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 10.0);
    assert_eq!(
        summary(&e),
        vec![
            (0.0, 0, 1, ContactKind::Begin),
            (0.0, 2, 3, ContactKind::Begin),
            (3.0, 0, 1, ContactKind::End)
        ]
    );
}

#[test]
fn accelerating_ball_catches_another() {
    let mut w = world(WorldKind::Free, Response::None, None);
    // x(t) = t^2 (acceleration 2) reaches 8 - 2 = 6 at t = sqrt(6); passes 10 at sqrt(10).
    w.add_ball(
        1.0,
        FlightPlan::accelerated(v(0.0, 0.0, 0.0), Vec3::ZERO, v(2.0, 0.0, 0.0)),
    )
    .unwrap();
    w.add_ball(1.0, FlightPlan::at_rest(v(8.0, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 5.0);
    assert_eq!(e.len(), 2);
    assert!((e[0].time - 6f64.sqrt()).abs() < 1e-12, "{}", e[0].time);
    assert!((e[1].time - 10f64.sqrt()).abs() < 1e-12, "{}", e[1].time);
}

#[test]
fn accelerating_pair_has_quartic_certificate() {
    let mut w = world(WorldKind::Free, Response::None, None);
    // Different accelerations along y; both at y = 1.75 when their x meet at t = 5.
    w.add_ball(
        0.5,
        FlightPlan::accelerated(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 0.14, 0.0)),
    )
    .unwrap();
    w.add_ball(
        0.5,
        FlightPlan::accelerated(v(10.0, 3.0, 0.0), v(-1.0, 0.0, 0.0), v(0.0, -0.1, 0.0)),
    )
    .unwrap();
    let e = run(&mut w, 20.0);
    assert_eq!(e.len(), 2);
    let (a, b) = (
        w.body(ObjectId(0)).unwrap().plan,
        w.body(ObjectId(1)).unwrap().plan,
    );
    for ev in &e {
        let d = (a.position_at(ev.time) - b.position_at(ev.time)).length();
        assert!((d - 1.0).abs() < 1e-9, "distance {d} at {}", ev.time);
    }
}

#[test]
fn plane_world_uses_tangency_points() {
    let mut w = world(WorldKind::Plane, Response::None, None);
    // Radii 1 and 4: contact when tangency points are 2 sqrt(4) = 4 apart (not 5).
    w.add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 7.0), v(1.0, 0.0, 3.0)))
        .unwrap();
    w.add_ball(4.0, FlightPlan::at_rest(v(10.0, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 20.0);
    assert_eq!(
        summary(&e),
        vec![
            (6.0, 0, 1, ContactKind::Begin),
            (14.0, 0, 1, ContactKind::End)
        ]
    );
}

#[test]
fn elastic_exchange_of_equal_balls() {
    let mut w = world(WorldKind::Free, Response::Elastic, None);
    let a = w
        .add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    let b = w
        .add_ball(1.0, FlightPlan::at_rest(v(5.0, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 10.0);
    assert_eq!(summary(&e), vec![(3.0, 0, 1, ContactKind::Begin)]);
    let (pa, pb) = (w.body(a).unwrap().plan, w.body(b).unwrap().plan);
    assert_eq!(pa.velocity_at(10.0), Vec3::ZERO);
    assert_eq!(pb.velocity_at(10.0), v(1.0, 0.0, 0.0));
    assert_eq!(pb.position_at(10.0), v(12.0, 0.0, 0.0));
}

#[test]
fn elastic_keeps_momentum_and_energy() {
    let mut w = world(WorldKind::Free, Response::Elastic, None);
    let a = w
        .add_ball(1.0, FlightPlan::linear(v(0.0, 0.3, 0.0), v(2.0, 0.0, 0.1)))
        .unwrap();
    let b = w
        .add_ball(2.0, FlightPlan::linear(v(8.0, 0.0, 0.0), v(-1.0, 0.2, 0.0)))
        .unwrap();
    let (ma, mb) = (1.0, 8.0);
    let momentum = |w: &Simulator| {
        let (pa, pb) = (w.body(a).unwrap().plan, w.body(b).unwrap().plan);
        let t = w.now();
        let (va, vb) = (pa.velocity_at(t), pb.velocity_at(t));
        (
            va * ma + vb * mb,
            0.5 * ma * va.length_squared() + 0.5 * mb * vb.length_squared(),
        )
    };
    let (p0, e0) = momentum(&w);
    let e = run(&mut w, 10.0);
    assert_eq!(e.len(), 1);
    let (p1, e1) = momentum(&w);
    assert!((p1 - p0).length() < 1e-12 && (e1 - e0).abs() < 1e-12 * e0);
    // They move apart afterwards.
    let (pa, pb) = (w.body(a).unwrap().plan, w.body(b).unwrap().plan);
    assert!((pa.position_at(10.0) - pb.position_at(10.0)).length() > 3.0);
}

#[test]
fn elastic_plane_impulse_along_tangency_points() {
    let mut w = world(WorldKind::Plane, Response::Elastic, None);
    let a = w
        .add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    let b = w
        .add_ball(1.0, FlightPlan::at_rest(v(5.0, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 10.0);
    // Equal radii: contact at tangency distance 2 (t = 3); velocities exchange along x.
    assert_eq!(summary(&e), vec![(3.0, 0, 1, ContactKind::Begin)]);
    assert_eq!(w.body(a).unwrap().plan.velocity_at(5.0), Vec3::ZERO);
    assert_eq!(w.body(b).unwrap().plan.velocity_at(5.0), v(1.0, 0.0, 0.0));
}

#[test]
fn overlapping_and_moving_apart_do_not_collide() {
    let mut w = world(WorldKind::Free, Response::Elastic, None);
    w.add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 0.0), v(-1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(1.0, FlightPlan::linear(v(1.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    assert!(run(&mut w, 10.0).is_empty());
    // Overlapping and approaching: a collision at t = 0.
    let mut w = world(WorldKind::Free, Response::Elastic, None);
    w.add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(1.0, FlightPlan::at_rest(v(1.0, 0.0, 0.0)))
        .unwrap();
    assert_eq!(
        summary(&run(&mut w, 10.0)),
        vec![(0.0, 0, 1, ContactKind::Begin)]
    );
}

#[test]
fn three_ball_newton_cradle() {
    let mut w = world(WorldKind::Free, Response::Elastic, None);
    let a = w
        .add_ball(1.0, FlightPlan::linear(v(-3.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    w.add_ball(1.0, FlightPlan::at_rest(v(0.0, 0.0, 0.0)))
        .unwrap();
    let c = w
        .add_ball(1.0, FlightPlan::at_rest(v(2.5, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 10.0);
    // a hits b at t = 1, b hits c at t = 1.5; a rests, c leaves at speed 1.
    assert_eq!(
        summary(&e),
        vec![
            (1.0, 0, 1, ContactKind::Begin),
            (1.5, 1, 2, ContactKind::Begin)
        ]
    );
    assert_eq!(w.body(a).unwrap().plan.velocity_at(10.0), Vec3::ZERO);
    assert_eq!(w.body(c).unwrap().plan.velocity_at(10.0), v(1.0, 0.0, 0.0));
}

#[test]
fn walls_bounce_and_are_counted() {
    let walls = Walls {
        min: v(0.0, 0.0, 0.0),
        max: v(10.0, 10.0, 10.0),
    };
    let mut w = world(WorldKind::Free, Response::Elastic, Some(walls));
    let a = w
        .add_ball(1.0, FlightPlan::linear(v(5.0, 5.0, 5.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    let e = run(&mut w, 20.0);
    assert!(e.is_empty());
    // Hits x = 9 at t = 4, x = 1 at t = 12, x = 9 again at t = 20.
    assert_eq!(w.stats().bounces, 3);
    assert!((w.body(a).unwrap().plan.position_at(20.0).x - 9.0).abs() < 1e-12);
    assert_eq!(
        w.add_ball(1.0, FlightPlan::at_rest(v(0.5, 5.0, 5.0))),
        Err(WorldError::OutsideWalls { object: 1 })
    );
}

#[test]
fn plan_change_and_removal_mid_run() {
    let mut w = world(WorldKind::Free, Response::None, None);
    let a = w
        .add_ball(1.0, FlightPlan::linear(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)))
        .unwrap();
    let b = w
        .add_ball(1.0, FlightPlan::at_rest(v(10.0, 0.0, 0.0)))
        .unwrap();
    run(&mut w, 2.0);
    // Stop a at x = 2: no contact any more.
    w.set_plan(a, FlightPlan::at_rest(v(2.0, 0.0, 0.0)).starting_at(2.0))
        .unwrap();
    assert!(run(&mut w, 20.0).is_empty());
    // Teleport a onto b: contact begins at once; removing b drops the pair.
    w.set_plan(a, FlightPlan::at_rest(v(10.5, 0.0, 0.0)).starting_at(20.0))
        .unwrap();
    assert_eq!(
        summary(&run(&mut w, 21.0)),
        vec![(20.0, 0, 1, ContactKind::Begin)]
    );
    w.remove(b).unwrap();
    assert_eq!(w.candidate_pairs(), 0);
    assert_eq!(w.remove(b).err(), Some(WorldError::UnknownObject(1)));
    let c = w
        .add_ball(
            1.0,
            FlightPlan::linear(v(30.0, 0.0, 0.0), v(-1.0, 0.0, 0.0)).starting_at(21.0),
        )
        .unwrap();
    let e = run(&mut w, 40.0);
    assert_eq!(c, ObjectId(2));
    assert_eq!(summary(&e)[0].1, 0);
    assert!((e[0].time - (21.0 + 30.0 - 10.5 - 2.0)).abs() < 1e-12);
}

#[test]
fn bad_input_is_a_typed_error() {
    let mut w = Simulator::new(WorldKind::Free);
    assert!(matches!(
        w.add_ball(-1.0, FlightPlan::at_rest(Vec3::ZERO)),
        Err(WorldError::InvalidRadius { .. })
    ));
    assert!(matches!(
        w.add_ball(1.0, FlightPlan::at_rest(v(f64::NAN, 0.0, 0.0))),
        Err(WorldError::NonFinitePlan { .. })
    ));
    w.advance_to(1.0).unwrap();
    assert!(matches!(
        w.advance_to(0.5),
        Err(WorldError::Backwards { .. })
    ));
    assert!(matches!(
        w.set_plan(ObjectId(9), FlightPlan::at_rest(Vec3::ZERO)),
        Err(WorldError::UnknownObject(9))
    ));
}

/// A structure that makes pair (0, 1) a candidate at one given time, for the case below.
#[derive(Debug)]
struct AddPairAt(f64, bool);

impl kinetic_core::CandidateStructure for AddPairAt {
    fn name(&self) -> &'static str {
        "add-pair-at"
    }
    fn insert(
        &mut self,
        _: u32,
        _: &kinetic_core::kds::Bodies,
        _: f64,
        _: &mut Vec<kinetic_core::kds::PairChange>,
    ) {
    }
    fn remove(
        &mut self,
        _: u32,
        _: &kinetic_core::kds::Bodies,
        _: f64,
        _: &mut Vec<kinetic_core::kds::PairChange>,
    ) {
    }
    fn replan(
        &mut self,
        _: u32,
        _: &kinetic_core::kds::Bodies,
        _: f64,
        _: &mut Vec<kinetic_core::kds::PairChange>,
    ) {
    }
    fn next_event_time(&self) -> f64 {
        if self.1 { f64::INFINITY } else { self.0 }
    }
    fn process_next_event(
        &mut self,
        _: &kinetic_core::kds::Bodies,
        changes: &mut Vec<kinetic_core::kds::PairChange>,
    ) -> &'static str {
        self.1 = true;
        changes.push(kinetic_core::kds::PairChange {
            a: 0,
            b: 1,
            delta: 1,
        });
        "add"
    }
    fn certificates(&self) -> usize {
        0
    }
    fn validate(&self, _: &kinetic_core::kds::Bodies, _: f64) -> Result<(), String> {
        Ok(())
    }
}

#[test]
fn contact_beginning_as_its_pair_is_added_is_not_lost_to_rounding() {
    // A structure adds the pair at the contact time (as a box event tied with the contact
    // does); the certificate's roots come from plans made at t = 0, the state from the gap
    // at the moment of adding, and the two round differently. The begin must be reported
    // once, at that moment, whichever way rounding goes.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    for trial in 0..2000 {
        let offset = Vec3::new(
            rng.random_range(-1e3..1e3),
            rng.random_range(-1e3..1e3),
            0.0,
        );
        let (r, d, v) = (
            rng.random_range(0.1..2.0),
            rng.random_range(5.0..50.0),
            rng.random_range(0.3..3.0),
        );
        let t_contact = (d - 2.0 * r) / v;
        let mut w = Simulator::with_structure(
            WorldKind::Free,
            Response::None,
            None,
            Box::new(AddPairAt(t_contact, false)),
        )
        .unwrap();
        w.add_ball(r, FlightPlan::linear(offset, Vec3::new(v, 0.0, 0.0)))
            .unwrap();
        w.add_ball(r, FlightPlan::at_rest(offset + Vec3::new(d, 0.0, 0.0)))
            .unwrap();
        // Halfway through the contact: one begin, no end yet.
        let events = run(&mut w, t_contact + 2.0 * r / v);
        assert!(!events.is_empty(), "trial {trial}: the contact was lost");
        assert_eq!(
            events[0].kind,
            ContactKind::Begin,
            "trial {trial}: {events:?}"
        );
        assert!(
            (events[0].time - t_contact).abs() < 1e-9,
            "trial {trial}: {events:?}"
        );
        assert_eq!(events.len(), 1, "trial {trial}: {events:?}");
    }
}
