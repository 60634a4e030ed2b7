use kinetic_rapier::KineticBroadPhase;
use kinetic_rapier::scenes::rain;
use rapier3d::prelude::*;

fn run(bp: &mut dyn BroadPhase, n: usize, steps: usize) -> Vec<f64> {
    let s = rain(n, n / 500, 1);
    let (mut bodies, mut colliders, gravity) = (s.bodies, s.colliders, s.gravity);
    let mut pipeline = PhysicsPipeline::new();
    pipeline.counters.enable();
    let params = IntegrationParameters::default();
    let (mut islands, mut narrow) = (IslandManager::new(), NarrowPhase::new());
    let (mut joints, mut multibody) = (ImpulseJointSet::new(), MultibodyJointSet::new());
    let mut ccd = CCDSolver::new();
    let mut out = Vec::new();
    for _ in 0..steps {
        pipeline.step(
            &gravity,
            &params,
            &mut islands,
            bp,
            &mut narrow,
            &mut bodies,
            &mut colliders,
            &mut joints,
            &mut multibody,
            &mut ccd,
            &(),
            &(),
        );
        out.push(pipeline.counters.broad_phase_time_ms());
    }
    out
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10000);
    let steps: usize = std::env::var("STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(120);
    let d = if std::env::var_os("NODEF").is_some() {
        vec![0.0; steps]
    } else {
        run(&mut DefaultBroadPhase::new(), n, steps)
    };
    let mut k = KineticBroadPhase::default();
    let mut kk = Vec::new();
    {
        let s = rain(n, n / 500, 1);
        let (mut bodies, mut colliders, gravity) = (s.bodies, s.colliders, s.gravity);
        let mut pipeline = PhysicsPipeline::new();
        pipeline.counters.enable();
        let params = IntegrationParameters::default();
        let (mut islands, mut narrow) = (IslandManager::new(), NarrowPhase::new());
        let (mut joints, mut multibody) = (ImpulseJointSet::new(), MultibodyJointSet::new());
        let mut ccd = CCDSolver::new();
        for _ in 0..steps {
            pipeline.step(
                &gravity,
                &params,
                &mut islands,
                &mut k,
                &mut narrow,
                &mut bodies,
                &mut colliders,
                &mut joints,
                &mut multibody,
                &mut ccd,
                &(),
                &(),
            );
            let st = k.last_step();
            kk.push((
                pipeline.counters.broad_phase_time_ms(),
                st,
                k.stats().candidates,
                k.stats().pairs,
            ));
        }
    }
    let (mut sd, mut sk) = (0.0, 0.0);
    for (i, (dd, (kt, st, c, p))) in d.iter().zip(&kk).enumerate() {
        sd += dd;
        sk += kt;
        if i % 4 == 0 {
            println!(
                "{i:3} def {dd:6.2} kin {kt:6.2}  ev {:5} rp {:5} ins {:4} add {:4} del {:4} cand {c:7} pairs {p:6}",
                st.events, st.replans, st.inserts, st.added, st.deleted
            );
        }
    }
    println!("total def {sd:.1} kin {sk:.1}");
}
