//! rapier 0.27 with the kinetic broad phase swapped in (one line): a rain of mixed balls and
//! boxes onto a ground, a few large rocks among them. Prints per-step statistics.
//!
//! `cargo run --release --example rapier_swap -- [N] [STEPS]` (default 2000 bodies, 300
//! steps at 60 Hz). PNG frames come with the renderer (issue 6), not built yet.

use kinetic_rapier::KineticBroadPhase;
use kinetic_rapier::scenes::{RapierScene, rain};
use rapier3d::prelude::*;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(2000);
    let steps: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(300);
    let RapierScene {
        mut bodies,
        mut colliders,
        gravity,
    } = rain(n, (n / 400).max(3), 7);

    // The one line: the kinetic broad phase instead of `DefaultBroadPhase::new()`.
    let mut broad_phase = KineticBroadPhase::default();

    let mut pipeline = PhysicsPipeline::new();
    let params = IntegrationParameters::default();
    let (mut islands, mut narrow_phase) = (IslandManager::new(), NarrowPhase::new());
    let (mut joints, mut multibody_joints) = (ImpulseJointSet::new(), MultibodyJointSet::new());
    let mut ccd = CCDSolver::new();
    println!("{n} bodies, {steps} steps at 60 Hz");
    println!("step  structure  pairs  touching  events  re-plans  inserts  added  deleted");
    for step in 0..steps {
        pipeline.step(
            &gravity,
            &params,
            &mut islands,
            &mut broad_phase,
            &mut narrow_phase,
            &mut bodies,
            &mut colliders,
            &mut joints,
            &mut multibody_joints,
            &mut ccd,
            &(),
            &(),
        );
        if step % 30 == 29 || step + 1 == steps {
            let (s, l) = (broad_phase.stats(), broad_phase.last_step());
            let touching = narrow_phase
                .contact_pairs()
                .filter(|p| p.has_any_active_contact)
                .count();
            println!(
                "{:4}  {:9}  {:5}  {:8}  {:6}  {:8}  {:7}  {:5}  {:7}",
                step + 1,
                broad_phase.structure_name(),
                s.pairs,
                touching,
                l.events,
                l.replans,
                l.inserts,
                l.added,
                l.deleted
            );
        }
    }
    let s = broad_phase.stats();
    println!(
        "whole run: {} events, {} re-plans, {} AddPair, {} DeletePair",
        s.events, s.replans, s.added, s.deleted
    );
    println!("frames: none yet (the renderer is issue 6)");
}
