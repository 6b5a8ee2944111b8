//! Generated tabletop planning problems and the benchmark over them.

use crate::rrt::{PlanError, PlannerParams, rrt_connect};
use crate::world::{CollisionWorld, WorldParams};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::Chain;
use tabula_robot::robots::NamedRobot;

/// Height of the generated table top for a robot (the WAM's shoulder is at 0.35 m, the
/// PR2's at about 1.1 m).
pub fn table_height(robot: &NamedRobot) -> f64 {
    if robot.label == "wam" { 0.25 } else { 0.72 }
}

/// The robot alone, with its allowed collision matrix: clone it for every scene.
pub fn robot_world(
    robot: &NamedRobot,
    chain: Chain,
    mut params: WorldParams,
) -> Result<CollisionWorld, crate::WorldError> {
    if params.srdf.is_none() {
        params.srdf = robot.srdf.clone();
    }
    CollisionWorld::new(robot.model.clone(), chain, Pose::IDENTITY, None, params)
}

/// A seeded tabletop scene around `empty` (the robot alone): a table in front of the
/// robot (1.2 × 0.8 m), a shelf board above its far half, and 3–8 boxes on it.
pub fn tabletop_world(
    empty: &CollisionWorld,
    top: f64,
    seed: u64,
) -> Result<CollisionWorld, crate::WorldError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = empty.clone();
    let (cx, cy) = (0.75, 0.0);
    world.add_box(
        "table",
        Vec3::new(0.8, 1.2, 0.04),
        Pose::from_translation(Vec3::new(cx, cy, top - 0.02)),
    )?;
    world.add_box(
        "shelf",
        Vec3::new(0.35, 1.2, 0.02),
        Pose::from_translation(Vec3::new(cx + 0.2, cy, top + 0.45)),
    )?;
    let n = rng.random_range(3..=8);
    for i in 0..n {
        let size = Vec3::new(
            rng.random_range(0.04..0.12),
            rng.random_range(0.04..0.12),
            rng.random_range(0.05..0.25),
        );
        let at = Vec3::new(
            cx + rng.random_range(-0.35..0.35),
            cy + rng.random_range(-0.55..0.55),
            top + size.z / 2.0,
        );
        let yaw = rng.random_range(-3.0..3.0);
        world.add_box(
            &format!("box{i}"),
            size,
            Pose::from_parts(at, Quat::from_rotation_z(yaw)),
        )?;
    }
    Ok(world)
}

/// A valid configuration whose tool is over the table, between 5 and 35 cm above it.
pub fn reach_configuration(
    world: &CollisionWorld,
    rng: &mut ChaCha8Rng,
    top: f64,
) -> Option<Vec<f64>> {
    for _ in 0..20_000 {
        let q = world.chain.random_configuration(rng);
        let Ok(tip) = world.tip_pose(&q) else {
            continue;
        };
        let t = tip.translation;
        let over =
            (t.x - 0.75).abs() < 0.4 && t.y.abs() < 0.6 && t.z > top + 0.05 && t.z < top + 0.35;
        if over && world.is_valid(&q) {
            return Some(q);
        }
    }
    None
}

/// The outcome of one benchmark run.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MotionBenchReport {
    pub robot: String,
    pub problems: usize,
    pub solved: usize,
    pub success_rate: f64,
    pub time_ms_median: f64,
    pub time_ms_p95: f64,
    pub path_length_median: f64,
    pub checks_per_second: f64,
    pub validity_check_us_median: f64,
    /// One convex–convex contact query (box–box, box–cylinder at random poses), median.
    pub convex_query_us_median: f64,
    /// Planning time of every solved problem (ms), for distributions in reports.
    #[serde(skip)]
    pub time_ms_samples: Vec<f64>,
}

/// Median time of one convex–convex contact query (the FCL-style primitive).
pub fn convex_query_us(seed: u64) -> f64 {
    use tabula_geom::parry::query;
    use tabula_geom::parry::shape::SharedShape;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let shapes = [
        SharedShape::cuboid(0.05, 0.08, 0.1),
        SharedShape::cylinder(0.1, 0.04),
        SharedShape::cuboid(0.2, 0.1, 0.02),
    ];
    let mut pairs = Vec::new();
    for i in 0..2000 {
        let r = |rng: &mut ChaCha8Rng| rng.random_range(-0.2..0.2);
        let p1 = Pose::from_parts(
            Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)),
            Quat::from_scaled_axis(Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 10.0),
        );
        let p2 = Pose::from_parts(
            Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)),
            Quat::from_scaled_axis(Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 10.0),
        );
        pairs.push((p1, p2, i % 3, (i + 1) % 3));
    }
    let mut times = Vec::with_capacity(pairs.len());
    for (p1, p2, a, b) in &pairs {
        let t0 = Instant::now();
        for _ in 0..10 {
            std::hint::black_box(
                query::contact(p1, shapes[*a].as_ref(), p2, shapes[*b].as_ref(), 0.0).ok(),
            );
        }
        times.push(t0.elapsed().as_secs_f64() * 1e6 / 10.0);
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Runs `problems` seeded tabletop reach problems.
pub fn run(
    robot: &NamedRobot,
    chain: &Chain,
    problems: usize,
    seed: u64,
    params: &PlannerParams,
) -> Result<MotionBenchReport, crate::WorldError> {
    let top = table_height(robot);
    let empty = robot_world(robot, chain.clone(), WorldParams::default())?;
    let mut times = Vec::new();
    let mut lengths = Vec::new();
    let mut solved = 0;
    let (mut checks, mut check_time) = (0u64, 0.0f64);
    let mut validity = Vec::new();
    let mut attempted = 0;
    for k in 0..problems as u64 {
        let world = tabletop_world(&empty, top, seed.wrapping_add(k))?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(k) ^ 0xA5A5);
        let (Some(start), Some(goal)) = (
            reach_configuration(&world, &mut rng, top),
            reach_configuration(&world, &mut rng, top),
        ) else {
            continue;
        };
        attempted += 1;
        // Time single validity checks on this scene.
        for _ in 0..20 {
            let q = world.chain.random_configuration(&mut rng);
            let t0 = Instant::now();
            std::hint::black_box(world.is_valid(&q));
            validity.push(t0.elapsed().as_secs_f64() * 1e6);
        }
        let before = world.checks();
        let t0 = Instant::now();
        let result = rrt_connect(
            &world,
            &start,
            &[goal],
            &PlannerParams {
                seed: k,
                ..params.clone()
            },
        );
        let elapsed = t0.elapsed().as_secs_f64();
        checks += world.checks() - before;
        check_time += elapsed;
        match result {
            Ok(path) => {
                solved += 1;
                times.push(elapsed * 1e3);
                lengths.push(path.length());
            }
            Err(PlanError::Timeout(_)) => {}
            Err(_) => {}
        }
    }
    let median = |v: &mut Vec<f64>, q: f64| {
        if v.is_empty() {
            return f64::NAN;
        }
        v.sort_by(f64::total_cmp);
        v[((v.len() - 1) as f64 * q).round() as usize]
    };
    let samples = times.clone();
    Ok(MotionBenchReport {
        time_ms_samples: samples,
        robot: robot.label.clone(),
        problems: attempted,
        solved,
        success_rate: solved as f64 / attempted.max(1) as f64,
        time_ms_median: median(&mut times.clone(), 0.5),
        time_ms_p95: median(&mut times, 0.95),
        path_length_median: median(&mut lengths, 0.5),
        checks_per_second: checks as f64 / check_time.max(1e-9),
        validity_check_us_median: median(&mut validity, 0.5),
        convex_query_us_median: convex_query_us(seed),
    })
}
