//! MotionBenchMaker's Panda: one problem of each of the seven sets (data/mbm/panda),
//! planned as `tabula motion bench --mbm` plans them — every one solved, every path
//! collision-free on the exact meshes between its waypoints, the same path twice.

use std::path::PathBuf;
use tabula_geom::Pose;
use tabula_motion::mbm::{self, Outcome, ProblemResult};
use tabula_motion::moveit::Limits;
use tabula_motion::{CollisionWorld, PlannerParams, WorldParams};
use tabula_robot::robots::{self, NamedRobot};

fn fixture() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/mbm/panda")
}

fn panda() -> NamedRobot {
    robots::load(fixture().join("panda.urdf").to_str().expect("utf-8 path")).expect("panda loads")
}

fn empty_world(robot: &NamedRobot, group: &str) -> Result<CollisionWorld, String> {
    let arm = robot.description.arm(group).map_err(|e| e.to_string())?;
    let chain = arm.chain(&robot.model).map_err(|e| e.to_string())?;
    let params = WorldParams {
        srdf: robot.srdf.clone(),
        ..WorldParams::default()
    };
    CollisionWorld::new(robot.model.clone(), chain, Pose::IDENTITY, None, params)
        .map_err(|e| e.to_string())
}

fn run(robot: &NamedRobot) -> Vec<ProblemResult> {
    let problems =
        mbm::load(&fixture().join("problems"), &Limits::default()).expect("problems load");
    assert_eq!(problems.len(), 7, "one problem per set");
    // A generous limit: under a loaded test machine a wall-clock limit would make the
    // outcome depend on the load; the search itself is seeded.
    let params = PlannerParams {
        timeout_s: 60.0,
        ..PlannerParams::default()
    };
    mbm::run(&problems, &params, |g| empty_world(robot, g), |_| {})
}

#[test]
fn one_problem_of_every_set_is_solved_with_exactly_collision_free_paths() {
    let robot = panda();
    assert!(robot.srdf.is_some(), "panda.srdf beside the URDF is read");
    let problems =
        mbm::load(&fixture().join("problems"), &Limits::default()).expect("problems load");
    let results = run(&robot);
    let sets: Vec<&str> = results.iter().map(|r| r.set.as_str()).collect();
    assert_eq!(
        sets,
        [
            "bookshelf_small_panda",
            "bookshelf_tall_panda",
            "bookshelf_thin_panda",
            "box_panda",
            "cage_panda",
            "table_pick_panda",
            "table_under_pick_panda"
        ]
    );
    for (r, p) in results.iter().zip(&problems) {
        let Outcome::Solved { path, plan_us, .. } = &r.outcome else {
            panic!("{} {:04}: {:?}", r.set, r.index, r.outcome);
        };
        assert!(*plan_us > 0.0);
        assert_eq!(r.joint_names.len(), 7);
        // The scene's world, checked on the exact meshes (no padding) every 2 mm of motion.
        let mut world = empty_world(&robot, &p.request.group).expect("world");
        p.scene.apply(&mut world).expect("scene applies");
        let problem = p.request.problem(&mut world).expect("request fits");
        assert_eq!(path.first(), Some(&problem.start));
        assert_eq!(path.last(), problem.joint_goals.first());
        assert_eq!(
            crate::first_touch(&world, path, 0.002),
            None,
            "{} {:04}: the path touches something (edge, configuration)",
            r.set,
            r.index
        );
    }
}

#[test]
fn the_benchmark_is_deterministic() {
    let robot = panda();
    let paths = |results: Vec<ProblemResult>| -> Vec<Vec<Vec<f64>>> {
        results
            .into_iter()
            .map(|r| match r.outcome {
                Outcome::Solved { path, .. } => path,
                other => panic!("{other:?}"),
            })
            .collect()
    };
    assert_eq!(paths(run(&robot)), paths(run(&robot)));
}

#[test]
fn the_scene_matrix_and_objects_reach_the_world() {
    let robot = panda();
    let problems =
        mbm::load(&fixture().join("problems/box_panda"), &Limits::default()).expect("set loads");
    assert_eq!(problems.len(), 1);
    let p = &problems[0];
    let mut world = empty_world(&robot, "panda_arm").expect("world");
    let notes = p.scene.apply(&mut world).expect("scene applies");
    let mut names = world.object_names();
    names.sort();
    assert_eq!(
        names,
        [
            "Can1",
            "base",
            "side_back",
            "side_cap",
            "side_front",
            "side_left",
            "side_right"
        ]
    );
    // MBM's matrix allows the hand against link 5 … 7 and the fingers, as the SRDF does.
    let allowed = world.allowed_pairs();
    let pair = |a: &str, b: &str| {
        allowed.contains(&(a.to_string(), b.to_string()))
            || allowed.contains(&(b.to_string(), a.to_string()))
    };
    assert!(pair("panda_hand", "panda_link6"));
    assert!(!pair("panda_link0", "panda_link5"));
    // The fingers are fixed joints in this URDF: their values are noted, not refused.
    assert!(
        notes.iter().any(|n| n.contains("panda_finger_joint1")),
        "{notes:?}"
    );
}
