//! The demo's jobs: the four tasks end to end in the simulator, each judged by its
//! physics, each with its report section, its JSON and its summary line.

use super::Tour;
use crate::report::{Report, Section, recorded};
use anyhow::Result;
use std::time::Instant;
use tabula_geom::Vec3;

/// A job's report section, its run as JSON, and its line in the summary.
pub type Job = (Section, serde_json::Value, String);

/// Seed 000's system (SPEC §1): the PR2 scans the cup it holds, finds how it rests,
/// finds the table and a free spot on it, drives up, puts it down; physics judges it.
pub fn placing(tour: &mut Tour, report: &mut Report) -> Result<Job> {
    use tabula_tasks::place::{PlaceParams, PlaceRequest};
    tell!(
        tour,
        "1. Placing an unknown object (seed 000): the PR2 and the cup in its hand\n"
    );
    let scene =
        tabula_sim::Scene::parse(tabula_sim::builtin::PR2_HOLDING, "scenes/pr2_holding.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let request = PlaceRequest {
        arm: Some("right".into()),
        not_on: Vec::new(),
        near: None,
    };
    let params = PlaceParams::default();
    let (out, _, recorded) = recorded(true, |start| {
        crate::place::place_in(world, None, (&request, &params), 1, start)
    })?;
    let wall = t0.elapsed().as_secs_f64();
    let r = &out.report;
    if let Some(m) = &r.model {
        tell!(
            tour,
            "  scanned: {} (the cup is 288 cm³)",
            crate::report::place::model_line(m)
        );
    }
    if let Some(p) = &out.stable_pose {
        tell!(
            tour,
            "  rests on the face with normal ({:.2}, {:.2}, {:.2}) in the hand: margin {:.0} mm, topples at {:.0}° ({} poses)",
            p.support_normal[0],
            p.support_normal[1],
            p.support_normal[2],
            p.margin_m * 1e3,
            p.topple_deg,
            r.poses_found
        );
    }
    if let (Some(s), Some(g)) = (&r.surface, r.base_goal) {
        tell!(
            tour,
            "  table found {:.2} m high; the base drove to ({:.2}, {:.2})",
            s.height,
            g[0],
            g[1]
        );
    }
    let line = format!(
        "{}: on {}, {:.1}° from the planned pose; decision {:.0} ms CPU, {wall:.1} s in all",
        if out.success { "placed" } else { "FAILED" },
        out.verdict.surface.as_deref().unwrap_or("nothing"),
        out.orientation_error_deg,
        out.decision_ms,
    );
    tell!(tour, "  {line}");
    tell!(
        tour,
        "\n  run it: cargo run --release -- place --scene pr2_holding --report DIR\n"
    );
    let mut section = crate::report::place::section(report, &out, &params, recorded.as_ref())?;
    section.text("Run it: cargo run --release -- place --scene pr2_holding --report DIR");
    Ok((section, serde_json::to_value(&out)?, line))
}

/// Seed 002's system (SPEC §3): the WAM clears the seed's cluttered table into the bin,
/// replanning after every action, and physics counts what ended in the bin.
pub fn clearing(tour: &mut Tour, report: &mut Report) -> Result<Job> {
    use tabula_sim::generate::{ClearSuite, clearing_scene};
    tell!(
        tour,
        "2. Clearing a cluttered table (seed 002): the WAM, grasps and pushes into the bin\n"
    );
    let scene =
        tabula_sim::Scene::parse(&clearing_scene(ClearSuite::Seed, 1), "scenes/clutter.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let params = tabula_tasks::clear::ClearParams::default();
    let (out, _, recorded) = recorded(true, |start| {
        crate::clear::clear_in(world, None, (&params, None), 1, start)
    })?;
    let wall = t0.elapsed().as_secs_f64();
    let r = &out.report;
    let v = &out.verdict;
    for a in &r.log {
        tell!(
            tour,
            "  frame {:>2}: {:<10} at ({:.3}, {:.3})  {}",
            a.frame,
            a.action,
            a.position[0],
            a.position[1],
            if a.ok { "ok" } else { "failed" }
        );
    }
    let line = format!(
        "{} of {} objects in the bin in {} actions ({} grasps, {} pushes), {} collisions; decision median {:.1} ms CPU, {wall:.1} s in all",
        v.in_bin, v.objects, r.actions, r.grasps, r.pushes, out.collisions, r.decision_ms.median
    );
    tell!(tour, "  {line}");
    tell!(
        tour,
        "  decision per frame (CPU, frame in → action chosen): perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1} ms (medians); the seed needed ≈ 4.5 s",
        r.perception_ms,
        r.predicates_ms,
        r.planning_ms,
        r.ik_ms
    );
    tell!(
        tour,
        "\n  run it: cargo run --release -- clear --scene clutter --report DIR\n"
    );
    let mut section = crate::report::clear::section(report, &out, recorded.as_ref())?;
    section.text("Run it: cargo run --release -- clear --scene clutter --report DIR");
    Ok((section, serde_json::to_value(&out)?, line))
}

/// The fourth task, from the other three's skills: the PR2 takes every object off a
/// table and stands each on another table it finds; physics judges it.
pub fn tidying(tour: &mut Tour, report: &mut Report) -> Result<Job> {
    use tabula_tasks::tidy::{TidyParams, TidyRequest};
    tell!(
        tour,
        "4. Tidying a table: the PR2 moves everything onto another table it finds\n"
    );
    let scene = tabula_sim::Scene::parse(tabula_sim::builtin::TIDY, "scenes/tidy.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let (request, params) = (TidyRequest::default(), TidyParams::default());
    let (out, _, recorded) = recorded(true, |start| {
        crate::tidy::tidy_in(world, (None, "table"), (&request, &params), 1, start)
    })?;
    let wall = t0.elapsed().as_secs_f64();
    for f in &out.failed {
        tell!(
            tour,
            "  failed at ({:.2}, {:.2}): {} — {}",
            f.object[0],
            f.object[1],
            f.reason,
            f.message
        );
    }
    let line = format!(
        "{} of {} objects moved to another table in {} actions, {} knocked over; decision median {:.0} ms CPU, {wall:.1} s in all",
        out.moved,
        out.objects,
        out.actions,
        out.verdict.knocked.len(),
        out.decision_ms.median
    );
    tell!(tour, "  {line}");
    tell!(
        tour,
        "\n  run it: cargo run --release -- tidy --scene tidy --report DIR\n"
    );
    let mut section = crate::report::tidy::section(report, &out, recorded.as_ref())?;
    section.text("Run it: cargo run --release -- tidy --scene tidy --report DIR");
    Ok((section, serde_json::to_value(&out)?, line))
}

/// Seed 001's integral test (SPEC §2.5): Golem-III looks at a can on a shelf board,
/// plans every motion, carries it to the table, and physics judges the result.
pub fn pick_place(tour: &mut Tour, report: &mut Report) -> Result<Job> {
    use tabula_tasks::pick_place::{PickPlaceParams, PickPlaceRequest};
    tell!(
        tour,
        "3. Pick and place by coordinates (seed 001's integral test): Golem-III, shelf → table\n"
    );
    let scene = tabula_sim::Scene::parse(
        tabula_sim::builtin::GOLEM_SHELVES,
        "scenes/golem_shelves.toml",
    )?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let request = PickPlaceRequest {
        arm: None,
        pick: Vec3::new(0.556, -0.663, 1.07),
        place: Vec3::new(0.82, -0.2, 1.01),
    };
    let t0 = Instant::now();
    let params = PickPlaceParams::default();
    let (out, _, recorded) = recorded(true, |start| {
        crate::pick_place::pick_place_in(world, None, (&request, &params), 1, start)
    })?;
    let wall = t0.elapsed().as_secs_f64();
    let r = &out.report;
    if let Some(o) = &r.object {
        tell!(
            tour,
            "  seen: {:.0} × {:.0} × {:.0} mm at ({:.3}, {:.3}, {:.3}), {} points",
            o.size[0] * 1e3,
            o.size[1] * 1e3,
            o.size[2] * 1e3,
            o.position[0],
            o.position[1],
            o.position[2],
            o.points
        );
    }
    let v = &out.verdict;
    let line = format!(
        "{} with the {} arm ({} grasp): {:.1} cm from the target, tilted {:.1}°; decision {:.0} ms CPU, {wall:.1} s in all{}",
        if out.success { "placed" } else { "FAILED" },
        r.arm.as_deref().unwrap_or("-"),
        r.grasp
            .map_or("-".into(), |g| format!("{g:?}").to_lowercase()),
        v.target_error * 100.0,
        v.tilt.to_degrees(),
        r.decision_cpu_ms,
        out.error_message
            .as_ref()
            .map_or(String::new(), |e| format!("; {e}"))
    );
    tell!(tour, "  {line}");
    let command = "cargo run --release -- pick-place --scene golem_shelves --pick 0.556 -0.663 1.07 --place 0.82 -0.2 1.01 --report DIR";
    tell!(tour, "\n  run it: {command}\n");
    let mut section = crate::report::pick_place::section(report, &out, recorded.as_ref())?;
    section.text(format!("Run it: {command}"));
    Ok((section, serde_json::to_value(&out)?, line))
}
