//! A sleeping pile woken by a touch stays as it lay (see `waking.rs`).

use super::{PhysicsParams, SimWorld};
use crate::Scene;

/// A table with three 5 cm cubes stacked on it and a row of two beside the stack's
/// bottom cube, touching it: one island once asleep.
fn stack() -> String {
    let cube = |name: &str, x: f64, z: f64| {
        format!(
            "\n[[object]]\nname = \"{name}\"\nshape = {{ box = [0.05, 0.05, 0.05] }}\npose = {{ xyz = [{x}, 0.0, {z}] }}\n"
        )
    };
    let table = "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = { xyz = [0.0, 0.0, 0.0] }\nsize = [1.0, 1.0, 0.7]\n";
    [
        ("s0", 0.0, 0.725),
        ("s1", 0.0, 0.775),
        ("s2", 0.0, 0.825),
        ("r1", 0.05, 0.725),
        ("r2", 0.1, 0.725),
    ]
    .iter()
    .fold(table.to_string(), |text, &(n, x, z)| text + &cube(n, x, z))
}

/// A cube let go 1 cm above the top of the stack.
const DROPPED: &str = r#"
[[object]]
name = "dropped"
shape = { box = [0.03, 0.03, 0.03] }
pose = { xyz = [0.0, 0.0, 0.875] }
"#;

#[test]
fn a_touch_wakes_a_sleeping_pile_without_dropping_it() {
    let scene = Scene::parse(&stack(), "stack.toml").unwrap();
    let mut w = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    assert!(w.settle().all_asleep, "the stack never fell asleep");
    let names = ["s0", "s1", "r1", "r2"];
    let body = |w: &SimWorld, n: &str| w.entities[w.entity(n).unwrap()].body;
    let before: Vec<_> = names.iter().map(|n| w.pose(n).unwrap()).collect();
    let drop = Scene::parse(DROPPED, "drop.toml").unwrap();
    w.add_objects(&drop.objects).unwrap();
    let mut fastest = 0.0f64;
    let mut woke = false;
    for _ in 0..60 {
        w.step();
        for n in names {
            let b = &w.physics.bodies[body(&w, n)];
            woke |= !b.is_sleeping();
            fastest = fastest.max(b.linvel().length());
        }
    }
    assert!(woke, "the falling cube never woke the pile");
    // Unfixed, every cube of the island fell freely for the waking step: 9.81 · dt =
    // 8.2 cm/s. A 30 g cube landing at 44 cm/s on 375 g of cubes moves them far less.
    assert!(
        fastest < 0.02,
        "a resting cube moved at {fastest:.4} m/s when woken"
    );
    for (n, p) in names.iter().zip(&before) {
        let moved = (w.pose(n).unwrap().translation - p.translation).length();
        assert!(moved < 1e-3, "{n} moved {moved:.4} m when the pile woke");
    }
}
