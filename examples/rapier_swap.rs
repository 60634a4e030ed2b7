//! rapier 0.27 with the kinetic broad phase swapped in (one line): a rain of mixed balls and
//! boxes onto a ground, a few large rocks among them. Prints per-step statistics.
//!
//! `cargo run --release --example rapier_swap -- [N] [STEPS]` (default 2000 bodies, 300
//! steps at 60 Hz). Writes a PNG frame every 5 steps to `out/rapier_swap/` (colliders in
//! contact in red).

use kinetic_collide_cli::frames::{CONTACT, PALETTE, PLANE, render_series_from};
use kinetic_rapier::KineticBroadPhase;
use kinetic_render::{Camera, Instance, Snapshot};
use kinetic_scenes::rapier::{RapierScene, rain};
use rapier3d::prelude::*;

/// Steps between frames.
const FRAME_EVERY: usize = 5;

/// The colliders now, in rapier's y-up world; those with an active contact in red.
fn snapshot(colliders: &ColliderSet, narrow_phase: &NarrowPhase) -> Snapshot {
    let mut touching = std::collections::HashSet::new();
    for pair in narrow_phase
        .contact_pairs()
        .filter(|p| p.has_any_active_contact)
    {
        touching.insert(pair.collider1);
        touching.insert(pair.collider2);
    }
    let mut s = Snapshot::new(glam::Vec3::Y);
    for (handle, collider) in colliders.iter() {
        let pose = collider.position();
        let t = pose.translation.vector;
        let q = pose.rotation.coords;
        let (centre, rotation) = (
            glam::Vec3::new(t.x, t.y, t.z),
            glam::Quat::from_xyzw(q.x, q.y, q.z, q.w),
        );
        let colour = if collider.parent().is_none() {
            PLANE
        } else if touching.contains(&handle) {
            CONTACT
        } else {
            PALETTE[handle.into_raw_parts().0 as usize % PALETTE.len()]
        };
        if let Some(ball) = collider.shape().as_ball() {
            s.instances
                .push(Instance::ball(centre, ball.radius, colour));
        } else if let Some(cuboid) = collider.shape().as_cuboid() {
            let h = cuboid.half_extents;
            s.instances.push(Instance::cuboid(
                centre,
                rotation,
                glam::Vec3::new(h.x, h.y, h.z),
                colour,
            ));
        }
    }
    s
}

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
    let mut snapshots = Vec::new();
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
        if step % FRAME_EVERY == 0 {
            snapshots.push(snapshot(&colliders, &narrow_phase));
        }
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
    let dir = std::path::Path::new("out/rapier_swap");
    let (width, height) = (640, 480);
    // Frame the ground and as much air above it as it is wide (the rain starts far higher).
    let mut view = Snapshot::new(glam::Vec3::Y);
    for (_, ground) in colliders.iter().filter(|(_, c)| c.parent().is_none()) {
        let b = ground.compute_aabb();
        let (lo, hi) = (b.mins, b.maxs);
        let air = hi.y + (hi.x - lo.x) * 0.5;
        view.wire_box(
            glam::Vec3::new(lo.x, lo.y, lo.z),
            glam::Vec3::new(hi.x, air, hi.z),
            [0.0; 4],
        );
    }
    let camera = Camera::framing(&view, width as f32 / height as f32);
    let written = render_series_from(&snapshots, &camera, width, height, dir);
    match written {
        Ok(files) => println!("wrote {} frames to {}", files.len(), dir.display()),
        Err(e) => {
            eprintln!("frames not written: {e}");
            std::process::exit(1);
        }
    }
}
