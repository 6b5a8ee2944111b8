//! Seed 000's placing (SPEC §1) in the simulator, judged by its physics: the PR2 scans
//! the object it holds, finds how it rests, finds a table and a free spot on it, drives
//! up when it is out of reach, and puts the object down — with fixed camera-noise
//! seeds. The scan is checked against the true shape.

use rayon::prelude::*;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::robots::NamedRobot;
use tabula_sim::judge::{self, StablePlaceJudge, StablePlaceVerdict};
use tabula_sim::{Scene, SimWorld};
use tabula_tasks::place::{PlaceOutcome, PlaceParams, PlaceRequest, place};

fn run(scene_text: &str, arm: &str, seed: u64) -> (PlaceOutcome, StablePlaceVerdict) {
    let scene = Scene::parse(scene_text, "test").unwrap();
    let world = SimWorld::from_scene(&scene, Default::default()).unwrap();
    let r = world.robot("pr2").unwrap();
    let robot = NamedRobot::new(r.model.clone(), r.description.clone(), "pr2");
    let params = PlaceParams::default();
    let request = PlaceRequest {
        arm: Some(arm.into()),
        not_on: Vec::new(),
        near: None,
    };
    let judge = |w: &SimWorld| StablePlaceJudge::new(w, "pr2");
    let (outcome, verdict, _) = judge::run(world, "pr2", seed, judge, |driver, _| {
        let out = place(driver, &robot, &request, &params);
        let planned = out.report.planned_world_from_tool.map(|p| {
            Pose::from_parts(
                Vec3::new(p[0], p[1], p[2] - params.release_height),
                Quat::from_xyzw(p[3], p[4], p[5], p[6]),
            )
        });
        (out, planned)
    })
    .unwrap();
    (outcome, verdict)
}

#[test]
fn held_objects_are_scanned_and_placed_stably() {
    let dir = std::env::temp_dir().join(format!("tabula-placing-test-{}", std::process::id()));
    let generated = |seed: u64, simple: bool| {
        let t = tabula_sim::generate::place_task(seed, simple, &dir).unwrap();
        (
            format!("{} {:?} ({seed})", t.object, t.layout),
            t.scene,
            t.arm,
        )
    };
    let cases = vec![
        (
            "seed scene".to_string(),
            include_str!("../../../../scenes/pr2_holding.toml").to_string(),
            "right".to_string(),
        ),
        generated(3, true),
        generated(1, false),
        // A bottle whose scanned side looks like a face (it would roll off it).
        generated(86, false),
        {
            // A walled room with a ramp, a traffic cone and a sign drum about.
            let t = tabula_sim::generate::room_task(2, &dir).unwrap();
            (
                format!("room {} {:?} (2)", t.object, t.layout),
                t.scene,
                t.arm,
            )
        },
    ];
    let results: Vec<_> = cases
        .par_iter()
        .map(|(name, text, arm)| (name.clone(), run(text, arm, 7)))
        .collect();
    for (name, (out, v)) in &results {
        eprintln!(
            "{name}: error {:?}, on {:?}, {:.1}° from the plan, moved {:.1} mm after release, decision {:.0} ms",
            out.error,
            v.surface,
            v.orientation_error_deg,
            v.moved_after_release_m * 1e3,
            out.report.decision_ms
        );
        assert!(out.error.is_none(), "{name}: {:?}", out.error);
        assert!(v.success, "{name}: {v:?}");
        assert!(v.orientation_error_deg <= 5.0 && v.moved_after_release_m < 0.01);
        let s = out.report.stable_pose.as_ref().unwrap();
        assert!(s.topple_deg >= PlaceParams::default().min_topple_deg);
    }
    // The seed scene's cup (a 6 × 6 × 8 cm box held at its centre, axes along the
    // tool's): the scan's points lie on its surface and cover most of it.
    let (out, _) = &results[0].1;
    let model = &out.report.model_points;
    let half = Vec3::new(0.03, 0.03, 0.04);
    let to_surface = |p: &Vec3| {
        let q = p.abs() - half;
        if q.max_element() > 0.0 {
            q.max(Vec3::ZERO).length()
        } else {
            -q.max_element()
        }
    };
    let mean = model.iter().map(to_surface).sum::<f64>() / model.len() as f64;
    assert!(
        mean < 0.004,
        "scan points are {mean:.4} m from the cup's surface on average"
    );
    let volume = out.report.model.as_ref().unwrap().hull_volume_m3;
    assert!(
        (volume / 288e-6 - 1.0).abs() < 0.2,
        "hull volume {:.1} cm³ against 288 cm³",
        volume * 1e6
    );
    // Coverage: surface samples with a scan point within 1 cm.
    let (mut near, mut total, mut near_free, mut total_free) = (0usize, 0usize, 0usize, 0usize);
    let mut per_face = [0usize; 6];
    for i in 0..=12 {
        for j in 0..=12 {
            let (a, b) = (i as f64 / 12.0 * 2.0 - 1.0, j as f64 / 12.0 * 2.0 - 1.0);
            for (k, q) in [
                Vec3::new(a * half.x, b * half.y, half.z),
                Vec3::new(a * half.x, b * half.y, -half.z),
                Vec3::new(half.x, a * half.y, b * half.z),
                Vec3::new(-half.x, a * half.y, b * half.z),
                Vec3::new(a * half.x, half.y, b * half.z),
                Vec3::new(a * half.x, -half.y, b * half.z),
            ]
            .into_iter()
            .enumerate()
            {
                let seen = model.iter().any(|m| m.distance(q) < 0.01);
                per_face[k] += usize::from(seen);
                total += 1;
                near += usize::from(seen);
                if k < 4 {
                    total_free += 1;
                    near_free += usize::from(seen);
                }
            }
        }
    }
    eprintln!(
        "scan coverage: {near} of {total} samples, {near_free} of {total_free} off the fingers; per face (+z −z +x −x +y −y, of 169): {per_face:?}"
    );
    // Measured: the faces across the fingers (tool ±z) whole; the fingertip face (+x)
    // whole since the views toward the fingertips are taken with the hand held aside
    // (`scan_shifts`: out of the PR2's reach from the observation pose, they left it
    // about half seen); the palm face (−x) under half (the palm hides it), the finger
    // faces about 65 %. Pinned below those, so a scan that loses views fails here.
    assert!(per_face[0] >= 160 && per_face[1] >= 160, "{per_face:?}");
    assert!(per_face[2] >= 160, "the fingertip face: {per_face:?}");
    assert!(
        near_free as f64 >= 0.65 * total_free as f64,
        "{near_free} of {total_free}"
    );
    assert!(near as f64 >= 0.6 * total as f64, "{near} of {total}");
    let _ = std::fs::remove_dir_all(&dir);
}
