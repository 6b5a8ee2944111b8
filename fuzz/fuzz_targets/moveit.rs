//! Any bytes as a MoveIt planning scene and as a motion plan request: read back checked
//! or refused with an error, never a panic; a scene that reads goes into the WAM's
//! collision world and a request is resolved against it, both without a panic.
//! Run: `cargo +nightly fuzz run moveit`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tabula_motion::moveit::{Limits, MotionRequest, PlanningScene};
use tabula_motion::{CollisionWorld, WorldParams};

thread_local! {
    /// The WAM's world, built once (a collision world is not shared between threads).
    static WORLD: CollisionWorld = {
        let r = tabula_robot::robots::load("wam").expect("wam");
        let chain = tabula_robot::Chain::new(&r.model, &r.default_base, &r.default_tip).expect("chain");
        let params = WorldParams {
            acm_samples: 50,
            ..WorldParams::default()
        };
        CollisionWorld::new(r.model.clone(), chain, tabula_geom::Pose::IDENTITY, None, params).expect("world")
    };
}

fn world() -> CollisionWorld {
    WORLD.with(CollisionWorld::clone)
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let limits = Limits {
        objects: 200,
        parts: 1000,
        mesh_vertices: 2000,
        ..Limits::default()
    };
    if let Ok(scene) = PlanningScene::from_yaml(&text, &limits) {
        let mut w = world();
        let _ = scene.apply(&mut w);
        let q = w.chain_values();
        let _ = w.first_collision(&q);
    }
    if let Ok(request) = MotionRequest::from_yaml(&text, &limits) {
        let mut w = world();
        let _ = request.problem(&mut w);
    }
});
