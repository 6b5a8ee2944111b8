//! Tidying (the fourth task, from the shared skills) in the simulator, judged by its
//! physics: a generated family task is tidied — every object of the table stands on
//! another table at the end, nothing that already stood there is disturbed — and bad
//! requests are typed errors before the robot moves.

use tabula_geom::Vec3;
use tabula_robot::robots::NamedRobot;
use tabula_sim::generate::tidy_task;
use tabula_sim::judge::tidy::TidyStart;
use tabula_sim::{Scene, SimDriver, SimWorld};
use tabula_tasks::task::{Task, unwatched};
use tabula_tasks::tidy::{Tidy, TidyParams, TidyRequest};

fn world_of(seed: u64) -> (SimWorld, NamedRobot) {
    let task = tidy_task(seed);
    let scene = Scene::parse(&task.scene, "tidy").unwrap();
    let mut world = SimWorld::from_scene(&scene, Default::default()).unwrap();
    world.settle();
    let r = world.robot("pr2").unwrap();
    let robot = NamedRobot::new(r.model.clone(), r.description.clone(), "pr2");
    (world, robot)
}

#[test]
fn a_generated_table_is_tidied_onto_another_and_nothing_there_is_knocked() {
    // Task 3: four objects, two other tables (one with something on it).
    let (world, robot) = world_of(3);
    let start = TidyStart::of(&world, "table").unwrap();
    let mut driver = SimDriver::new(world, "pr2", 3).unwrap();
    let report = Tidy::run(
        &mut driver,
        &robot,
        &TidyRequest::default(),
        &TidyParams::default(),
        &mut unwatched,
    )
    .unwrap();
    let mut world = driver.world;
    world.settle();
    let verdict = start.verdict(&world);
    assert_eq!(verdict.objects, 4, "{verdict:?}");
    assert!(verdict.moved >= 3, "{verdict:?} {report:?}");
    assert!(verdict.knocked.is_empty(), "{verdict:?}");
    assert_eq!(report.objects, 4);
    assert!(report.actions >= verdict.moved);
    // Every object that moved stands on a table other than the source.
    for (name, on) in &verdict.ended_on {
        assert_ne!(on.as_deref(), None, "{name} is nowhere at rest");
    }
}

#[test]
fn bad_requests_and_parameters_are_typed_errors() {
    let (world, robot) = world_of(1);
    let mut driver = SimDriver::new(world, "pr2", 1).unwrap();
    let unknown_arm = TidyRequest {
        arm: Some("tentacle".into()),
        ..TidyRequest::default()
    };
    let e = Tidy::run(
        &mut driver,
        &robot,
        &unknown_arm,
        &TidyParams::default(),
        &mut unwatched,
    )
    .unwrap_err();
    assert_eq!(e.kind(), "robot", "{e}");
    let nan = TidyRequest {
        from: Some(Vec3::new(f64::NAN, 0.0, 0.75)),
        ..TidyRequest::default()
    };
    let e = Tidy::run(
        &mut driver,
        &robot,
        &nan,
        &TidyParams::default(),
        &mut unwatched,
    )
    .unwrap_err();
    assert_eq!(e.kind(), "params", "{e}");
    let bad = TidyParams {
        max_attempts: 0,
        ..TidyParams::default()
    };
    let e = Tidy::run(
        &mut driver,
        &robot,
        &TidyRequest::default(),
        &bad,
        &mut unwatched,
    )
    .unwrap_err();
    assert_eq!(e.kind(), "params", "{e}");
}
