//! Time-stepped detection, the way most engines find contacts: at t = 0, dt, 2 dt, ... up to
//! the horizon, place every object where its flight plan puts it, find the pairs whose boxes
//! overlap with a sweep-and-prune along x, and test those pairs for overlap. A contact begins
//! at the first sample where a pair overlaps and ends at the first where it no longer does;
//! anything that starts and ends between two samples is missed.

use kinetic_collide::run::{RunError, shapes_of};
use kinetic_collide::scene::Scene;
use kinetic_core::kds::{Pose, signed_distance};
use kinetic_core::{ContactEvent, ContactKind, FlightPlan, ObjectId, Real, Shape, Vec3};
use rustc_hash::FxHashSet;
use std::time::Instant;

/// What a time-stepped run found.
#[derive(Clone, Debug)]
pub struct SteppedOutput {
    /// Contact begins and ends at sample times, in log order.
    pub events: Vec<ContactEvent>,
    /// Samples taken.
    pub samples: u64,
    /// Exact overlap tests run (pairs whose boxes overlapped).
    pub tests: u64,
    /// Wall-clock seconds.
    pub wall_seconds: f64,
}

/// Runs `scene` sampled every `dt` (the response is ignored: objects follow their plans).
pub fn run_stepped(scene: &Scene, dt: Real) -> Result<SteppedOutput, RunError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(RunError::Input(format!(
            "step {dt}: must be finite and > 0"
        )));
    }
    let start = Instant::now();
    let shapes = shapes_of(scene)?;
    let plans: Vec<FlightPlan> = scene
        .objects
        .iter()
        .map(|o| o.centre_plan(scene.world))
        .collect();
    let n = plans.len();
    let steps = (scene.horizon / dt).floor() as u64;
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut poses = vec![
        Pose {
            translation: Vec3::ZERO,
            rotation: kinetic_core::Quat::IDENTITY
        };
        n
    ];
    let mut lo = vec![Vec3::ZERO; n];
    let mut hi = vec![Vec3::ZERO; n];
    let mut active: Vec<u32> = Vec::new();
    let mut touching: FxHashSet<(u32, u32)> = FxHashSet::default();
    let mut now_touching: FxHashSet<(u32, u32)> = FxHashSet::default();
    let mut events = Vec::new();
    let mut tests = 0u64;
    for k in 0..=steps {
        let t = k as Real * dt;
        for i in 0..n {
            poses[i] = Pose::of_plan(&plans[i], t);
            let r = Vec3::splat(shapes[i].outer_radius());
            lo[i] = poses[i].translation - r;
            hi[i] = poses[i].translation + r;
        }
        // The previous order is nearly sorted: the stable sort runs in about linear time.
        order.sort_by(|&a, &b| lo[a as usize].x.total_cmp(&lo[b as usize].x));
        active.clear();
        now_touching.clear();
        for &i in &order {
            let iu = i as usize;
            active.retain(|&j| hi[j as usize].x >= lo[iu].x);
            for &j in &active {
                let ju = j as usize;
                let boxes_meet = hi[ju].y >= lo[iu].y
                    && hi[iu].y >= lo[ju].y
                    && hi[ju].z >= lo[iu].z
                    && hi[iu].z >= lo[ju].z;
                if !boxes_meet {
                    continue;
                }
                tests += 1;
                if overlapping(&shapes[iu], &poses[iu], &shapes[ju], &poses[ju]) {
                    now_touching.insert((i.min(j), i.max(j)));
                }
            }
            active.push(i);
        }
        log_changes(&touching, &now_touching, t, &mut events);
        std::mem::swap(&mut touching, &mut now_touching);
    }
    Ok(SteppedOutput {
        events,
        samples: steps + 1,
        tests,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

/// Logs the contacts that began (in `after`, not `before`) and ended (the other way) at `t`,
/// ordered by pair.
pub(crate) fn log_changes(
    before: &FxHashSet<(u32, u32)>,
    after: &FxHashSet<(u32, u32)>,
    t: Real,
    events: &mut Vec<ContactEvent>,
) {
    let mut changes: Vec<(u32, u32, ContactKind)> = after
        .iter()
        .filter(|p| !before.contains(p))
        .map(|&(a, b)| (a, b, ContactKind::Begin))
        .chain(
            before
                .iter()
                .filter(|p| !after.contains(p))
                .map(|&(a, b)| (a, b, ContactKind::End)),
        )
        .collect();
    changes.sort_unstable_by_key(|&(a, b, _)| (a, b));
    events.extend(changes.into_iter().map(|(a, b, kind)| ContactEvent {
        time: t,
        a: ObjectId(a),
        b: ObjectId(b),
        kind,
    }));
}

/// Whether two posed shapes touch or overlap.
fn overlapping(a: &Shape, pa: &Pose, b: &Shape, pb: &Pose) -> bool {
    signed_distance(a, pa, b, pb) <= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetic_collide::scene::SceneObject;
    use kinetic_core::{Response, WorldKind};

    fn two_balls(speed: f64) -> Scene {
        Scene {
            world: WorldKind::Free,
            horizon: 1.0,
            response: Response::None,
            walls: None,
            periodic: None,
            objects: vec![
                SceneObject::ball(0.5, Vec3::new(-2.0, 0.0, 0.0), Vec3::new(speed, 0.0, 0.0)),
                SceneObject::ball(0.5, Vec3::ZERO, Vec3::ZERO),
            ],
        }
    }

    #[test]
    fn a_slow_contact_is_seen_at_the_next_sample_and_a_fast_one_is_missed() {
        // Speed 2: touching from t = 0.5 to 1.5 (past the horizon): begins at the sample 0.5.
        let out = run_stepped(&two_balls(2.0), 0.1).unwrap();
        assert_eq!(out.events.len(), 1);
        assert!((out.events[0].time - 0.5).abs() < 1e-12);
        assert_eq!(out.events[0].kind, ContactKind::Begin);
        // Speed 40: overlapping for t in (1/40, 3/40), between the samples 0 and 0.1.
        let out = run_stepped(&two_balls(40.0), 0.1).unwrap();
        assert!(out.events.is_empty(), "{:?}", out.events);
        assert_eq!(out.samples, 11);
        assert!(run_stepped(&two_balls(1.0), 0.0).is_err());
    }
}
