//! Seed 002's table clearing (SPEC §3) in the simulator, judged by its physics: the
//! seed's scene, a packed grid (every grasp blocked at first) and one hard arrangement
//! of each wider family are cleared into the bin with fixed camera-noise seeds, without
//! the arm touching an object it is not acting on, and every decision is explained by
//! the run's own metrics.

use rayon::prelude::*;
use tabula_robot::robots::NamedRobot;
use tabula_sim::generate::{ClearSuite, clearing_scene};
use tabula_sim::judge::{self, ClearJudge, ClearSetup, ClearVerdict};
use tabula_sim::{Scene, SimWorld};
use tabula_tasks::clear::{ClearError, ClearParams, ClearReport, ClearRequest, clear};

fn run(scene_text: &str, seed: u64) -> (Result<ClearReport, ClearError>, ClearVerdict) {
    let scene = Scene::parse(scene_text, "test").unwrap();
    let world = SimWorld::from_scene(&scene, Default::default()).unwrap();
    let r = world.robot("wam").unwrap();
    let robot = NamedRobot::new(r.model.clone(), r.description.clone(), "wam");
    let setup = ClearSetup::of(&world, "bin").unwrap();
    let request = ClearRequest {
        arm: None,
        drop_point: setup.drop_point,
        drop_spread: setup.drop_spread,
        obstacles: setup.obstacles.clone(),
        max_actions: None,
    };
    let (report, verdict, _) = judge::run(
        world,
        "wam",
        seed,
        |w| ClearJudge::new(w, "wam", ("table", "bin")),
        |driver, hook| {
            let params = ClearParams::default();
            let out = clear(driver, &robot, &request, &params, &mut |d, e| {
                hook(d, e.judged())
            });
            (out, ())
        },
    )
    .unwrap();
    (report, verdict)
}

#[test]
fn the_seed_scene_and_a_packed_grid_are_cleared_into_the_bin() {
    let cases = [
        ("seed scene", clearing_scene(ClearSuite::Seed, 1), 1u64),
        ("packed grid 2", clearing_scene(ClearSuite::Packed, 2), 2),
    ];
    let results: Vec<_> = cases
        .par_iter()
        .map(|(name, text, seed)| (*name, run(text, *seed)))
        .collect();
    for (name, (report, verdict)) in results {
        let report = report.unwrap_or_else(|e| panic!("{name}: {e}"));
        eprintln!(
            "{name}: {} of {} in the bin, {} actions ({} pushes), decision median {:.1} ms; stop: {}",
            verdict.in_bin,
            verdict.objects,
            report.actions,
            report.pushes,
            report.decision_ms.median,
            report.stop
        );
        assert!(verdict.objects >= 4, "{name}: {verdict:?}");
        assert_eq!(verdict.in_bin, verdict.objects, "{name}: {verdict:?}");
        assert_eq!(verdict.left_on_table, 0, "{name}");
        assert!(
            verdict.collisions.is_empty(),
            "{name}: {:?}",
            verdict.collisions
        );
        assert_eq!(report.push_loops, 0, "{name}");
        assert_eq!(report.stop, "table clear", "{name}");
        assert!(report.left.is_empty(), "{name}: {:?}", report.left);
        // Every object took at most two actions.
        assert!(
            report.actions <= 2 * verdict.objects,
            "{name}: {} actions",
            report.actions
        );
        // The run's own accounting agrees with physics.
        assert_eq!(report.removed, verdict.in_bin, "{name}");
        assert!(
            report
                .frames
                .iter()
                .all(|f| f.decision_ms.is_finite() && f.decision_ms > 0.0),
            "{name}"
        );
    }
}

#[test]
fn what_no_grasp_fits_is_left_and_named_with_why() {
    // The seed scene and a 12 × 12 cm tray beside it: wider every way than the WAM's
    // 7 cm grip. Everything else goes to the bin; the loop ends saying the tray stays
    // and why, where it was last seen and how big.
    let tray = r#"
[[object]]
name = "tray"
shape = { box = [0.12, 0.12, 0.04] }
pose = { xyz = [0.50, 0.36, 0.741] }
mass = 0.3
color = [0.5, 0.5, 0.5]
"#;
    let scene = format!("{}{tray}", clearing_scene(ClearSuite::Seed, 1));
    let (report, verdict) = run(&scene, 1);
    let report = report.unwrap();
    assert_eq!(verdict.in_bin + 1, verdict.objects, "{verdict:?}");
    assert_eq!(report.stop, "nothing left that can be removed");
    assert_eq!(report.left.len(), 1, "{:?}", report.left);
    let left = &report.left[0];
    assert!(
        left.why.starts_with("no grasp of the gripper fits it"),
        "{left:?}"
    );
    // On the table (0.7 × 1 m about (0.62, 0), top at 0.72 m), wherever pushes left it.
    let [x, y, z] = left.position;
    assert!((x - 0.62).abs() < 0.35 && y.abs() < 0.5, "{left:?}");
    assert!((z - 0.74).abs() < 0.02, "{left:?}");
    let (long, short) = (
        left.size[0].max(left.size[1]),
        left.size[0].min(left.size[1]),
    );
    assert!(long < 0.14 && short > 0.10, "{left:?}");
}

#[test]
fn the_packed_grid_needs_pushes_before_any_grasp() {
    // What the suite promises: at first no object of a packed grid can be grasped.
    let (report, _) = run(&clearing_scene(ClearSuite::Packed, 2), 2);
    let report = report.unwrap();
    let first = report.log.first().expect("an action");
    assert!(first.action.starts_with("push"), "{:?}", first);
}

/// The families built beyond the seed's generator (issue 32), one hard arrangement
/// each: a 3 × 3 grid of blocks that are not boxes (prisms, arches, half-cylinders,
/// tiles on edge, bars) packed 1–4 mm apart, a grid of boxes and cylinders, and objects
/// at the grip's limits (flat discs and boxes 1.5–3 cm tall, thin tall ones), and a
/// block as long as the hand is wide. Every object ends in the bin, none off the table.
#[test]
fn a_block_grid_a_box_grid_and_objects_at_the_grip_limits_are_cleared() {
    let cases = [
        ("blocks 17", ClearSuite::Blocks, 17u64, 9usize),
        // A lying prism 7.07 cm long beside two others: held by its ends in the 7 cm
        // hand, it left the open hand outside the bin (`TopGrasps::snug_room`).
        ("blocks 105", ClearSuite::Blocks, 105, 5),
        ("grid 7", ClearSuite::Grid, 7, 9),
        ("limits 1", ClearSuite::Limits, 1, 8),
    ];
    // Plain threads: each run waits on its own perception pool (see
    // `tabula_bench::trials`).
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = cases
            .iter()
            .map(|&(name, suite, seed, n)| {
                s.spawn(move || (name, n, run(&clearing_scene(suite, seed), seed)))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (name, n, (report, verdict)) in results {
        let report = report.unwrap_or_else(|e| panic!("{name}: {e}"));
        eprintln!(
            "{name}: {} of {} in the bin, {} actions ({} pushes, {} failed grasps); stop: {}",
            verdict.in_bin,
            verdict.objects,
            report.actions,
            report.pushes,
            report.failed_grasps,
            report.stop
        );
        assert_eq!(verdict.objects, n, "{name}: every object counted");
        assert_eq!(verdict.in_bin, n, "{name}: {verdict:?}");
        assert_eq!(verdict.off_table, 0, "{name}");
        assert!(
            report.actions as f64 <= 1.6 * n as f64,
            "{name}: {} actions for {n} objects",
            report.actions
        );
    }
}

/// Blocks seen as one segment, parted by a split push: a tile on edge against a
/// standing triangular prism, tops 2.8 mm apart, seen as one 9 × 4 cm segment whose
/// grasp across the middle closes on the seam (blocks seed 183: one end pushed
/// sideways); a bar beside an arch seen as one 13 × 10 cm blob no grasp fits (blocks
/// seed 127: one side slid along the seam). Every block ends in the bin.
#[test]
fn blocks_seen_as_one_are_parted_by_a_split_push() {
    let cases = [(183u64, 4usize), (127, 9)];
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = cases
            .iter()
            .map(|&(seed, n)| {
                s.spawn(move || {
                    (
                        seed,
                        n,
                        run(&clearing_scene(ClearSuite::Blocks, seed), seed),
                    )
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (seed, n, (report, verdict)) in results {
        let report = report.unwrap_or_else(|e| panic!("blocks {seed}: {e}"));
        let splits = report
            .frames
            .iter()
            .filter(|f| f.plan.first().is_some_and(|p| p.contains("[split")))
            .count();
        assert!(splits >= 1, "blocks {seed}: {:?}", report.log);
        assert_eq!(
            (verdict.in_bin, verdict.objects),
            (n, n),
            "blocks {seed}: {verdict:?}"
        );
        assert_eq!(verdict.off_table, 0, "blocks {seed}");
    }
}

#[test]
fn what_rides_on_a_lifted_object_is_carried_level_into_the_bin() {
    // Piles 3 and 49: an object resting on the one grasped, seen merged with it, comes
    // up with it. Carried with the hand tilted (56° on the median carry before) it slid
    // off and was flung over the table's edge; carried level, both land in the bin.
    for seed in [3u64, 49] {
        let (report, verdict) = run(&clearing_scene(ClearSuite::Pile, seed), seed);
        report.unwrap();
        assert_eq!(
            (verdict.in_bin, verdict.off_table),
            (verdict.objects, 0),
            "pile {seed}: {verdict:?}"
        );
    }
}
