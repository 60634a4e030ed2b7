//! The collision tree, with per-node and with global lists, against the brute force on seeded
//! random plane scenes: elastic and pass-through, balls of sizes over two orders joining,
//! changing plans and leaving while the world runs. The log must be the brute force's bit for
//! bit, and the tree is audited after every event.

use kinetic_core::{BruteForce, FlightPlan, ObjectId, Response, Simulator, Vec3, WorldKind};
use kinetic_rolling::{ListLayout, RollingTree};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_ball(rng: &mut ChaCha8Rng, now: f64) -> (f64, FlightPlan) {
    let r = 0.05 * 20f64.powf(rng.random_range(0.0..1.0));
    let p = Vec3::new(
        rng.random_range(-8.0..8.0),
        rng.random_range(-8.0..8.0),
        0.0,
    );
    let v = Vec3::new(
        rng.random_range(-1.5..1.5),
        rng.random_range(-1.5..1.5),
        0.0,
    );
    (r, FlightPlan::linear(p, v).starting_at(now))
}

fn scenario(seed: u64, layout: ListLayout, response: Response) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let make = |s: Box<dyn kinetic_core::CandidateStructure>| {
        Simulator::with_structure(WorldKind::Plane, response, None, s).expect("a world")
    };
    let mut tree = make(Box::new(RollingTree::new(layout)));
    let mut brute = make(Box::new(BruteForce::new()));
    let mut ids: Vec<ObjectId> = Vec::new();
    let mut t = 0.0;
    for round in 0..6 {
        // Balls join (a batch at first, then one by one), without overlapping anyone.
        let want = if round == 0 { 40 } else { 4 };
        let mut added = 0;
        while added < want {
            let (r, plan) = random_ball(&mut rng, t);
            let p = plan.position_at(t);
            let clear = ids.iter().all(|&id| {
                let b = tree.body(id).expect("live");
                let q = b.plan.position_at(t);
                // Rolling balls touch when their tangency points are 2 sqrt(ra rb) apart.
                (p - q).length() > 2.0 * (r * b.shape.outer_radius()).sqrt() + 1e-6
            });
            if !clear {
                continue;
            }
            let a = tree.add_ball(r, plan).expect("add");
            assert_eq!(a, brute.add_ball(r, plan).expect("add"));
            ids.push(a);
            added += 1;
        }
        tree.validate().expect("valid after adding");
        t += 2.0;
        while tree.step(t).expect("step").is_some() {
            tree.validate().expect("valid after every event");
        }
        tree.advance_to(t).expect("advance");
        brute.advance_to(t).expect("advance");
        if response == Response::None {
            // A new plan for one ball, and one leaves.
            let id = ids[rng.random_range(0..ids.len())];
            let (_, plan) = random_ball(&mut rng, t);
            let plan = FlightPlan::linear(
                tree.body(id).unwrap().plan.position_at(t),
                plan.velocity_at(t),
            )
            .starting_at(t);
            tree.set_plan(id, plan).expect("replan");
            brute.set_plan(id, plan).expect("replan");
            let gone = ids.swap_remove(rng.random_range(0..ids.len()));
            tree.remove(gone).expect("remove");
            brute.remove(gone).expect("remove");
            tree.validate()
                .expect("valid after a new plan and a removal");
        }
    }
    let (a, b) = (tree.drain_events(), brute.drain_events());
    assert!(a.len() > 10, "a run with contacts: {}", a.len());
    assert_eq!(a.len(), b.len(), "seed {seed}, {layout:?}, {response:?}");
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            (x.a, x.b, x.kind, x.time.to_bits()),
            (y.a, y.b, y.kind, y.time.to_bits()),
            "seed {seed}, {layout:?}, {response:?}"
        );
    }
}

#[test]
fn the_tree_matches_the_brute_force_bit_for_bit() {
    for layout in [ListLayout::PerNode, ListLayout::Global] {
        for seed in 0..3 {
            scenario(seed, layout, Response::None);
            scenario(100 + seed, layout, Response::Elastic);
        }
    }
}
