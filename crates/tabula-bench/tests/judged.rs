//! The one judged run, through each task's entry: a placing run judged by physics as
//! the CLI runs it, and workcells the judges cannot judge refused by name.

use tabula_bench::clear::clear_in;
use tabula_bench::place::place_in;
use tabula_sim::{Scene, SimWorld};
use tabula_tasks::clear::ClearParams;
use tabula_tasks::place::{PlaceParams, PlaceRequest};

fn world(file: &str) -> SimWorld {
    let path = format!("{}/../../scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::load(std::path::Path::new(&path)).unwrap();
    SimWorld::from_scene(&scene, Default::default()).unwrap()
}

#[test]
fn the_seed_placement_is_judged_resting_on_the_table() {
    let request = PlaceRequest {
        arm: Some("right".into()),
        not_on: Vec::new(),
        near: None,
    };
    let params = PlaceParams::default();
    let mut started = false;
    let (run, world) = place_in(
        world("pr2_holding.toml"),
        None,
        (&request, &params),
        0,
        |_| started = true,
    )
    .unwrap();
    assert!(started, "on_start sees the driver before the task");
    assert!(run.success, "{:?}", run.verdict);
    assert_eq!(run.verdict.surface.as_deref(), Some("table"));
    assert!(run.verdict.released && run.verdict.orientation_error_deg < 5.0);
    assert!(world.held_objects("pr2").is_empty());
}

#[test]
fn judges_refuse_what_they_cannot_judge() {
    // Clearing's judge needs the bin; placing's needs something held.
    let params = ClearParams::default();
    let e = clear_in(world("pr2_holding.toml"), None, (&params, None), 0, |_| {})
        .err()
        .unwrap();
    assert!(e.to_string().contains("bin"), "{e}");
    let request = PlaceRequest::default();
    let e = place_in(
        world("clutter.toml"),
        None,
        (&request, &PlaceParams::default()),
        0,
        |_| {},
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("holds nothing"), "{e}");
    // A robot the scene does not have.
    let e = clear_in(
        world("clutter.toml"),
        Some("r2d2"),
        (&params, None),
        0,
        |_| {},
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("r2d2"), "{e}");
}

/// Issue 32's holdable grips: a drill held 20 cm from its origin, by an end (complex
/// 16), and a 16 cm box held 9 cm off its middle (simple 47) — both turned at random in
/// the hand — are each put down to rest as planned, and the grip leaves the true object
/// a resting face (the suite's rule). Two drills failed before: in complex 105 the parts
/// a finger's shadow cut off the scan stood in the air as obstacles and blocked every
/// path to the table; in complex 187 one stray range return 1.7 cm over the table was
/// taken for an object and blocked every spot.
#[test]
fn objects_held_off_their_middle_are_placed_to_rest() {
    use rayon::prelude::*;
    use tabula_bench::place::{Suite, task_of, trial};
    let dir = std::env::temp_dir().join(format!("tabula-grips-test-{}", std::process::id()));
    let cases = [
        (Suite::ComplexGrips, 16, "drill"),
        (Suite::SimpleGrips, 47, "box"),
        (Suite::ComplexGrips, 105, "drill"),
        (Suite::ComplexGrips, 187, "drill"),
    ];
    let rows: Vec<_> = cases
        .par_iter()
        .map(|&(suite, seed, _)| trial(seed, suite, &PlaceParams::default(), &dir).unwrap())
        .collect();
    for ((suite, seed, object), row) in cases.iter().zip(&rows) {
        let task = task_of(*seed, *suite, &dir).unwrap();
        assert!(task.scene.contains("grips = Anywhere"), "{suite:?} {seed}");
        assert_eq!(row.object, *object);
        assert_eq!(row.grip_allows_rest, Some(true), "{suite:?} {seed}");
        assert!(
            row.success,
            "{suite:?} {seed}: {:?}, {:.1}°, moved {:.1} mm",
            row.cause, row.orientation_error_deg, row.moved_after_release_mm
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The demo's tidying, watched at every physics step as its recording is: the approach
/// to the last object's table once met the other target table, which the search had not
/// looked at, and the object was given up ("blocked by `target1`"). Now the robot looks
/// at what stopped it, backs off and approaches with that seen.
#[test]
fn the_demo_tidying_watched_step_by_step_moves_every_object() {
    use tabula_bench::tidy::tidy_in;
    use tabula_tasks::tidy::{TidyParams, TidyRequest};
    let scene = Scene::parse(tabula_sim::builtin::TIDY, "scenes/tidy.toml").unwrap();
    let world = SimWorld::from_scene(&scene, Default::default()).unwrap();
    let (request, params) = (TidyRequest::default(), TidyParams::default());
    let (run, _) = tidy_in(world, (None, "table"), (&request, &params), 1, |driver| {
        driver.observe(|_| {})
    })
    .unwrap();
    assert_eq!(run.objects, 4);
    assert_eq!(run.moved, 4, "{:?}", run.failed);
    assert!(run.success, "{:?}", run.failed);
}
