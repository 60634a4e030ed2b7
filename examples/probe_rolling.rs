use kinetic_collide::run::{StructureName, run_scene};
use kinetic_collide::scenes::BallScene;
use kinetic_collide::{Response, WorldKind};
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let p = BallScene {
        n: args[0] as usize,
        r_min: args[1],
        r_max: args[2],
        side: args[3],
        speed: 1.0,
        acceleration: args[4],
        world: WorldKind::Plane,
        response: if args[5] > 0.0 {
            Response::Elastic
        } else {
            Response::None
        },
        walls: args[5] > 0.0,
        allow_overlap: args[5] == 0.0,
        horizon: args[6],
        seed: 1,
    };
    let scene = p.build();
    for s in [
        StructureName::BruteForce,
        StructureName::RollingTree,
        StructureName::RollingGlobalLists,
    ] {
        let out = run_scene(&scene, Some(s)).unwrap();
        println!(
            "{} events {:?} begins {} t {:.3} {:?}",
            s.as_str(),
            out.stats.events_by_kind,
            out.stats.begins,
            out.wall_seconds,
            out.structure_stats
        );
    }
}
