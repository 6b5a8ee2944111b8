//! Physics that keeps every object (issue 32): 200 small objects dropped into four
//! piles, then the hand pressed down into each pile and swept through it. A kinematic
//! finger squeezing an object against the table must not push it through the table or
//! the floor, and the scene saved afterwards must load again.

use crate::common;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write as _;
use tabula_geom::Vec3;
use tabula_robot::Chain;
use tabula_robot::driver::JointTrajectory;
use tabula_sim::{PhysicsParams, Scene, SimWorld};

const TOP: f64 = 0.72;
const TABLE_CENTER: [f64; 2] = [0.62, 0.0];
const TABLE_HALF: [f64; 2] = [0.35, 0.5];
const PILES: [[f64; 2]; 4] = [[0.5, -0.15], [0.5, 0.15], [0.66, -0.12], [0.66, 0.12]];

/// The clearing cell (table, WAM on its stand) with 50 small objects of mixed shapes
/// in layers above each pile's centre, none overlapping at the start.
fn scene_text(seed: u64) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut s = format!(
        "[floor]\nsize = [8.0, 8.0]\n\n[[furniture]]\nname = \"table\"\nkind = \"table\"\n\
         pose = {{ xyz = [{}, {}, 0.0] }}\nsize = [{}, {}, {TOP}]\n\n[[furniture]]\n\
         name = \"stand\"\nkind = \"table\"\nsize = [0.3, 0.3, 0.6]\n\n[[robot]]\n\
         name = \"wam\"\nurdf = \"wam\"\npose = {{ xyz = [0.0, 0.0, 0.6] }}\n\
         joints = {{ wam_joint2 = -1.9, wam_joint4 = 2.6 }}\n",
        TABLE_CENTER[0],
        TABLE_CENTER[1],
        2.0 * TABLE_HALF[0],
        2.0 * TABLE_HALF[1]
    );
    for (p, c) in PILES.iter().enumerate() {
        for k in 0..50 {
            let a = rng.random_range(0.012..0.035);
            let b = rng.random_range(0.012..0.035);
            let shape = match rng.random_range(0..4) {
                0 => format!("{{ box = [{a}, {b}, {}] }}", rng.random_range(0.008..0.035)),
                1 => format!("{{ cylinder = {{ radius = {}, height = {b} }} }}", a / 2.0),
                2 => format!("{{ sphere = {{ radius = {} }} }}", a / 2.0),
                _ => format!("{{ box = [{a}, {b}, 0.006] }}"),
            };
            // Layers of 3 × 3, 6.5 cm apart, so the pile is 6 layers high.
            let (layer, cell) = (k / 9, k % 9);
            let xyz = [
                c[0] + 0.065 * ((cell / 3) as f64 - 1.0) + rng.random_range(-0.005..0.005),
                c[1] + 0.065 * ((cell % 3) as f64 - 1.0) + rng.random_range(-0.005..0.005),
                TOP + 0.04 + 0.065 * layer as f64,
            ];
            let rpy: [f64; 3] = std::array::from_fn(|_| rng.random_range(-3.1..3.1));
            let _ = write!(
                s,
                "\n[[object]]\nname = \"o{p}_{k}\"\nshape = {shape}\nmass = 0.02\n\
                 pose = {{ xyz = {xyz:?}, rpy = {rpy:?} }}\n"
            );
        }
    }
    s
}

/// The WAM's joints putting its tool at `xyz` (world; the WAM stands at z = 0.6)
/// pointing down, from `seed`.
fn ik(chain: &Chain, xyz: Vec3, seed: &[f64]) -> Vec<f64> {
    common::tool_down(chain, xyz - Vec3::new(0.0, 0.0, 0.6), seed)
}

/// A tool path through `points` (straight joint-space pieces between IK solutions,
/// 0.1 m/s), from joints `q`; returns the trajectory and the last joints.
fn path(chain: &Chain, q: &[f64], points: &[Vec3]) -> (JointTrajectory, Vec<f64>) {
    let mut positions = vec![q.to_vec()];
    let mut times = vec![0.0];
    let mut last = points[0];
    for &p in points {
        let next = ik(chain, p, positions.last().unwrap());
        times.push(times.last().unwrap() + ((p - last).length() / 0.1).max(0.3));
        positions.push(next);
        last = p;
    }
    let end = positions.last().unwrap().clone();
    let trajectory = JointTrajectory {
        joint_names: chain.joint_names.clone(),
        times,
        positions,
    };
    (trajectory, end)
}

fn inside_table_outline(p: Vec3) -> bool {
    (p.x - TABLE_CENTER[0]).abs() < TABLE_HALF[0] && (p.y - TABLE_CENTER[1]).abs() < TABLE_HALF[1]
}

#[test]
fn pressing_into_piles_loses_no_object() {
    let scene = Scene::parse(&scene_text(7), "piles.toml").unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    world.settle();
    let robot = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let mut q: Vec<f64> = chain
        .joint_names
        .iter()
        .map(|j| world.joint("wam", j).unwrap())
        .collect();
    for c in PILES {
        let above = Vec3::new(c[0], c[1], TOP + 0.25);
        // Down into the pile until the fingertips are in the table, then through it.
        let points = [
            above,
            Vec3::new(c[0], c[1], TOP - 0.01),
            Vec3::new(c[0] + 0.06, c[1], TOP - 0.01),
            Vec3::new(c[0] - 0.06, c[1] + 0.04, TOP - 0.01),
            above,
        ];
        let (trajectory, end) = path(&chain, &q, &points);
        world.follow_trajectory("wam", &trajectory).unwrap();
        q = end;
    }
    world.settle();
    let poses = world.object_poses();
    assert_eq!(poses.len(), 200);
    let mut off_table = 0;
    for (name, p) in &poses {
        let t = p.translation;
        let in_top = inside_table_outline(t) && t.z < TOP - 1e-3 && t.z > TOP - 0.04;
        if t.z < -1e-3 || in_top {
            eprintln!("lost {name} at {t:?}");
        }
    }
    for (name, p) in &poses {
        let t = p.translation;
        assert!(t.z > -1e-3, "{name} fell through the floor: {t:?}");
        let in_top = inside_table_outline(t) && t.z < TOP - 1e-3 && t.z > TOP - 0.04;
        assert!(!in_top, "{name} is inside the table top: {t:?}");
        if t.z < TOP - 0.04 {
            off_table += 1;
        }
    }
    eprintln!("{off_table} of 200 ended off the table");
    // Whatever the hand pressed together, the saved scene loads (objects pressed deeper
    // into each other than a scene may place them are saved apart: `world/saved.rs`).
    let saved = world.to_scene().to_toml().unwrap();
    let reloaded = Scene::parse(&saved, "saved.toml").unwrap();
    SimWorld::from_scene(&reloaded, PhysicsParams::default()).expect("the saved scene loads");
}
