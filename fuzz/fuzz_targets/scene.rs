//! Any text as a scene file: a checked scene or a located error; a checked scene
//! builds a physics world (or a clear error) and steps — never a panic, never a NaN
//! pose. Run: `cargo +nightly fuzz run scene`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tabula_sim::{PhysicsParams, Scene, SimWorld};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(scene) = Scene::parse(&text, "fuzz.toml")
        && let Ok(mut world) = SimWorld::from_scene(&scene, PhysicsParams::default())
    {
        for _ in 0..10 {
            world.step();
        }
    }
});
