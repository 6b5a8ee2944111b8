//! Any bytes as a MoveIt planning scene and as a motion plan request: read back checked
//! or refused with an error, never a panic; a scene that reads goes into the WAM's
//! collision world and a request is resolved against it, both without a panic.
//! Run: `cargo +nightly fuzz run moveit`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;
use tabula_motion::moveit::{Limits, MotionRequest, PlanningScene};
use tabula_motion::{CollisionWorld, WorldParams};

fn world() -> &'static CollisionWorld {
    static WORLD: OnceLock<CollisionWorld> = OnceLock::new();
    WORLD.get_or_init(|| {
        let r = tabula_robot::robots::load("wam").expect("wam");
        let chain = tabula_robot::Chain::new(&r.model, &r.default_base, &r.default_tip).expect("chain");
        let params = WorldParams {
            acm_samples: 50,
            ..WorldParams::default()
        };
        CollisionWorld::new(r.model.clone(), chain, tabula_geom::Pose::IDENTITY, None, params).expect("world")
    })
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
        let mut w = world().clone();
        let _ = scene.apply(&mut w);
        let q = w.chain_values();
        let _ = w.first_collision(&q);
    }
    if let Ok(request) = MotionRequest::from_yaml(&text, &limits) {
        let mut w = world().clone();
        let _ = request.problem(&mut w);
    }
});
