//! Unit tests of clearing's geometry, tracking and parameters.

use super::execute::drop_offset;
use super::fallback::penetration;
use super::predicates::{TableView, descent_poses};
use super::track::{split_merged, track};
use super::*;
use crate::skills::grasp::{GraspTarget, NarrowPartGrasps};
use crate::skills::hand::extent_along;
use crate::skills::{GraspPlanner, Hand};
use tabula_geom::polygon::{convex_hull_2d, min_area_rectangle};
use tabula_geom::{Vec2, Vec3};

/// A box standing at `center` (world xy) on the table at z 0.72 (or on `bottom`),
/// seen as points on its top and sides every 5 mm.
fn seen_box(id: usize, center: Vec2, size: Vec2, height: f64, bottom: f64) -> SeenObject {
    let mut points = Vec::new();
    let (nx, ny) = ((size.x / 0.005) as i32, (size.y / 0.005) as i32);
    for i in 0..=nx {
        for j in 0..=ny {
            let x = center.x - size.x / 2.0 + i as f64 * 0.005;
            let y = center.y - size.y / 2.0 + j as f64 * 0.005;
            points.push(Vec3::new(x, y, bottom + height));
            if i == 0 || j == 0 || i == nx || j == ny {
                for k in 1..(height / 0.005) as i32 {
                    points.push(Vec3::new(x, y, bottom + k as f64 * 0.005));
                }
            }
        }
    }
    seen_points(id, points, bottom)
}

/// The object `points` (world) make standing at `bottom`, as the predicates see it.
fn seen_points(id: usize, points: Vec<Vec3>, bottom: f64) -> SeenObject {
    let flat: Vec<Vec2> = points.iter().map(|q| q.truncate()).collect();
    let footprint: Vec<Vec2> = convex_hull_2d(&flat).iter().map(|&i| flat[i]).collect();
    let rect = min_area_rectangle(&footprint).unwrap();
    let mut hull_points = points.clone();
    hull_points.extend(footprint.iter().map(|p| Vec3::new(p.x, p.y, bottom)));
    let hull = SharedShape::convex_hull(&hull_points).unwrap();
    let aabb = hull.compute_aabb(&Pose::IDENTITY);
    let top = points.iter().map(|p| p.z).fold(bottom, f64::max);
    SeenObject {
        id,
        points,
        footprint,
        rect,
        bottom,
        top,
        hull,
        aabb,
    }
}

/// A 6 cm box, a 4 cm box on it, and a tall box 30 cm away on its own.
fn box_on_box_and_lone() -> Vec<SeenObject> {
    vec![
        seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.06, 0.06), 0.05, 0.72),
        seen_box(1, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.04), 0.04, 0.77),
        seen_box(2, Vec2::new(0.6, 0.3), Vec2::new(0.05, 0.05), 0.08, 0.72),
    ]
}

fn table() -> Table {
    Table {
        z: 0.72,
        up: Vec3::Z,
        outline: vec![
            Vec2::new(0.3, -0.5),
            Vec2::new(0.9, -0.5),
            Vec2::new(0.9, 0.5),
            Vec2::new(0.3, 0.5),
        ],
    }
}

/// What `ask` finds in `objects` on [`table`].
fn on_table<R>(
    objects: &[SeenObject],
    hand: &Hand,
    params: &ClearParams,
    ask: impl FnOnce(TableView<'_>) -> R,
) -> R {
    let table = table();
    ask(TableView {
        objects,
        table: &table,
        hand,
        params,
    })
}

/// The predicates of `objects` on [`table`].
fn predicates(
    objects: &[SeenObject],
    hand: &Hand,
    params: &ClearParams,
    chain: bool,
) -> predicates::Geometry {
    on_table(objects, hand, params, |v| v.predicates(chain))
}

fn grasps_of(
    o: &SeenObject,
    hand: &Hand,
    params: &ClearParams,
) -> Vec<crate::skills::GraspCandidate> {
    params
        .grasp_planner()
        .candidates(&o.grasp_target(), hand, Vec3::Z)
}

fn hand() -> Hand {
    let robot = tabula_robot::robots::load("wam").unwrap();
    let g = robot.description.grippers[0].clone();
    Hand::new(&robot, &g).unwrap()
}

#[test]
fn the_hand_model_comes_from_the_urdf() {
    let h = hand();
    // The WAM's fingers: 6 cm long, tips 2.25 cm beyond the tool frame.
    assert!((h.finger_length - 0.06).abs() < 1e-9, "{}", h.finger_length);
    // The palm box ends where the fingers start: all of them reach beyond it.
    assert!((h.beyond_palm - 0.06).abs() < 1e-9, "{}", h.beyond_palm);
    assert!((h.tip - 0.0225).abs() < 1e-9, "{}", h.tip);
    assert_eq!(h.open_width, 0.07);
}

#[test]
fn a_can_held_up_by_the_edge_of_a_box_is_on_that_box_only() {
    let base = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.06, 0.06), 0.05, 0.72);
    // Lying against the box, 1 cm of its 10 cm over the box's top: most of it is over
    // the table, yet only the box holds it up.
    let leaning = seen_box(1, Vec2::new(0.67, 0.0), Vec2::new(0.1, 0.05), 0.05, 0.77);
    let beside = seen_box(2, Vec2::new(0.6, 0.1), Vec2::new(0.05, 0.05), 0.05, 0.72);
    // In the air at the same height, 3 cm from the box: held by nothing seen.
    let apart = seen_box(3, Vec2::new(0.5, -0.1), Vec2::new(0.04, 0.04), 0.04, 0.77);
    let objects = vec![base, leaning, beside, apart];
    assert_eq!(on_pairs(&objects, 0.72, &|_| true), vec![(1, 0)]);
    // One no grasp fits is on nothing: what holds it up may still be taken.
    assert!(on_pairs(&objects, 0.72, &|_| false).is_empty());
}

#[test]
fn a_box_on_a_box_is_on_it_and_blocks_nothing_else() {
    let objects = box_on_box_and_lone();
    assert_eq!(on_pairs(&objects, 0.72, &|_| false), vec![(1, 0)]);
    let g = predicates(&objects, &hand(), &ClearParams::default(), false);
    // The lone box is free in every way; nothing blocks grasping the top one.
    assert!(
        g.block_grasp
            .iter()
            .all(|&(a, b)| a != 2 && b != 2 && b != 1)
    );
    assert!(
        g.block_push
            .iter()
            .flatten()
            .all(|&(a, b)| a != 2 && b != 2)
    );
    assert!(g.grasps.iter().all(Option::is_some));
}

#[test]
fn touching_boxes_block_the_grasp_across_them_and_the_push_into_each_other() {
    // Two boxes side by side along x, 2 mm apart, the right one 3 cm lower. Closing
    // across `a` at full depth puts a finger in the gap; held only 2 cm deep, the
    // fingertips pass over `b`.
    let a = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.075), 0.08, 0.72);
    let b = seen_box(1, Vec2::new(0.647, 0.0), Vec2::new(0.05, 0.05), 0.05, 0.72);
    let objects = vec![a, b];
    let g = predicates(&objects, &hand(), &ClearParams::default(), false);
    assert!(!g.block_grasp.contains(&(1, 0)), "{:?}", g.block_grasp);
    let full_depth_only = ClearParams {
        shallow_grip: 1.0,
        ..ClearParams::default()
    };
    let g = predicates(&objects, &hand(), &full_depth_only, false);
    assert!(g.block_grasp.contains(&(1, 0)), "{:?}", g.block_grasp);
    // Pushing `a` into `b` is blocked; along y it slides past `b` (grazing is
    // allowed, the palm passes above the lower box) until its grasp is free.
    let into_b = (0..4).find(|&k| g.pushes[0][k].direction.x > 0.9).unwrap();
    let along = (0..4).find(|&k| g.pushes[0][k].direction.y > 0.9).unwrap();
    assert!(g.block_push[into_b].contains(&(1, 0)));
    assert!(!g.block_push[along].contains(&(1, 0)), "{:?}", g.block_push);
    let p = &g.pushes[0][along];
    assert!(p.length > 0.05 && p.length < 0.12, "{}", p.length);
}

#[test]
fn a_push_of_a_blocker_goes_until_the_grasp_it_blocked_is_free() {
    // `a` is held only across x (7.5 cm along y); `b`, as tall, stands 2 mm beside it
    // on +x, in the way of the finger on that side. The domain's push of `b` deletes
    // `block_grasp b a`: a push along y must move `b` past that finger, not only as far
    // as `b`'s own grasp needs (its first step).
    let (h, params) = (hand(), ClearParams::default());
    let a = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.075), 0.08, 0.72);
    let b = seen_box(1, Vec2::new(0.647, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72);
    let objects = vec![a, b];
    let g = predicates(&objects, &h, &params, false);
    assert!(g.block_grasp.contains(&(1, 0)), "{:?}", g.block_grasp);
    let along = (0..4).find(|&k| g.pushes[1][k].direction.y > 0.9).unwrap();
    let p = &g.pushes[1][along];
    let by = p.direction3() * (p.length - params.push_margin);
    let moved = vec![objects[0].clone(), translated(&objects[1], by, true)];
    let after = predicates(&moved, &h, &params, false);
    assert!(
        !after.block_grasp.contains(&(1, 0)),
        "{} m: {:?}",
        p.length,
        after.block_grasp
    );
    // As far as that takes and no farther: one step less still blocks it.
    let short = p.direction3() * (p.length - params.push_margin - params.push_resolution);
    let moved = vec![objects[0].clone(), translated(&objects[1], short, true)];
    let before = predicates(&moved, &h, &params, false);
    assert!(before.block_grasp.contains(&(1, 0)), "{} m", p.length);
}

#[test]
fn a_blob_too_wide_is_grasped_by_its_narrow_part() {
    // Two boxes segmentation could not tell apart: 4 × 7.5 cm beside 5 × 5 cm.
    let a = seen_box(0, Vec2::new(0.60, 0.0), Vec2::new(0.04, 0.075), 0.09, 0.72);
    let b = seen_box(0, Vec2::new(0.6455, 0.0), Vec2::new(0.05, 0.05), 0.09, 0.72);
    let mut points = a.points.clone();
    points.extend(b.points);
    let flat: Vec<Vec2> = points.iter().map(|q| q.truncate()).collect();
    let footprint: Vec<Vec2> = convex_hull_2d(&flat).iter().map(|&i| flat[i]).collect();
    let blob = SeenObject {
        rect: min_area_rectangle(&footprint).unwrap(),
        footprint,
        points,
        ..a
    };
    let h = hand();
    assert!(blob.rect.size.x.min(blob.rect.size.y) > h.open_width);
    let planner = ClearParams::default().grasp_planner();
    let target: GraspTarget<'_> = blob.grasp_target();
    let parts = NarrowPartGrasps { top: planner.0 }.parts(&target, &h);
    assert!(!parts.is_empty());
    // The narrowest part is the square box's.
    assert!((parts[0].at.x - 0.645).abs() < 0.015, "{:?}", parts[0]);
    // Too wide to take whole: the planner falls back to the parts.
    assert!(planner.0.candidates(&target, &h, Vec3::Z).is_empty());
    assert_eq!(
        grasps_of(&blob, &h, &ClearParams::default()).len(),
        parts.len()
    );
}

#[test]
fn tracks_follow_objects_and_pushes_where_they_went() {
    let mut tracks = Vec::new();
    let mut first = vec![
        seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
        seen_box(0, Vec2::new(0.6, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
    ];
    track(&mut first, &mut tracks, 0.06, 0.35);
    assert_eq!((first[0].id, first[1].id), (0, 1));
    // Object 1 was pushed 10 cm along +x; object 0 did not move.
    tracks[1].expected = Vec2::new(0.7, 0.2);
    let mut next = vec![
        seen_box(0, Vec2::new(0.705, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
        seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
        seen_box(0, Vec2::new(0.4, -0.3), Vec2::new(0.05, 0.05), 0.08, 0.72),
    ];
    track(&mut next, &mut tracks, 0.06, 0.35);
    assert_eq!((next[0].id, next[1].id, next[2].id), (1, 0, 2));
}

/// Two boxes pushed together are seen as one 10 × 5 cm segment: it is split where the
/// two tracks expect them, while a stack (tracks at one place) and boxes not moved by a
/// push are left as seen.
#[test]
fn a_segment_two_pushed_boxes_merged_into_is_split_between_them() {
    let mut tracks = Vec::new();
    let mut first = vec![
        seen_box(0, Vec2::new(0.60, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
        seen_box(0, Vec2::new(0.66, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
    ];
    track(&mut first, &mut tracks, 0.06, 0.35);
    let merged = || {
        vec![seen_box(
            0,
            Vec2::new(0.55, 0.0),
            Vec2::new(0.10, 0.05),
            0.08,
            0.72,
        )]
    };
    // Not moved by a push: what is seen stays one object.
    let mut seen = merged();
    split_merged(&mut seen, &tracks);
    assert_eq!(seen.len(), 1);
    // Pushed 8 cm along −x together (the second shoved along by the first).
    for (t, x) in tracks.iter_mut().zip([0.525, 0.575]) {
        t.expected = Vec2::new(x, 0.0);
        t.pushed_together = true;
    }
    let mut seen = merged();
    split_merged(&mut seen, &tracks);
    assert_eq!(seen.len(), 2, "split in two");
    let mut xs: Vec<f64> = seen.iter().map(|o| o.rect.center.x).collect();
    xs.sort_by(f64::total_cmp);
    assert!(
        (xs[0] - 0.525).abs() < 0.005 && (xs[1] - 0.575).abs() < 0.005,
        "{xs:?}"
    );
    assert!(seen.iter().all(|o| o.rect.size.max_element() < 0.055));
    // A stack: both expected at the same place.
    for t in tracks.iter_mut() {
        t.expected = Vec2::new(0.55, 0.0);
    }
    let mut seen = merged();
    split_merged(&mut seen, &tracks);
    assert_eq!(seen.len(), 1);
}

/// How far the open hand reaches into a neighbour: nothing when it is clear, about
/// the overlap when a finger comes down a few millimetres into it.
#[test]
fn penetration_measures_how_far_the_fingers_reach_into_a_neighbour() {
    let h = hand();
    let target = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.04), 0.08, 0.72);
    let params = ClearParams::default();
    let g = grasps_of(&target, &h, &params).remove(0);
    let shapes = h.open_for(g.width).1;
    let poses = descent_poses(&g.poses[0], Vec3::Z, params.pregrasp);
    // Neighbours beside it along the closing axis, nearer and nearer: clear, then
    // reached into by as much as they come nearer.
    let closing = (g.poses[0].rotation * h.closing).truncate().normalize();
    let (_, outer) = extent_along(shapes, h.closing);
    let beside = |gap: f64| {
        let c = target.rect.center + closing * (outer + gap + 0.02);
        seen_box(1, c, Vec2::new(0.04, 0.04), 0.08, 0.72)
    };
    assert_eq!(penetration(shapes, &poses, &beside(0.01)), 0.0);
    let (near, nearer) = (
        penetration(shapes, &poses, &beside(-0.01)),
        penetration(shapes, &poses, &beside(-0.02)),
    );
    assert!(near > 0.0);
    assert!((nearer - near - 0.01).abs() < 1e-3, "{near} {nearer}");
}

/// A push that moved its object less than a third of its length jammed: that way is
/// ruled out; one that went most of the way is not.
#[test]
fn a_jammed_push_is_not_tried_that_way_again() {
    let params = ClearParams::default();
    let mut tracks = Vec::new();
    let mut first = vec![
        seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
        seen_box(0, Vec2::new(0.6, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
    ];
    track(&mut first, &mut tracks, 0.06, params.push_jam_share);
    // Both pushed 6 cm along +x: the first moves 1 cm, the second 5 cm.
    for (t, o) in tracks.iter_mut().zip(&first) {
        t.pushes.push(Vec2::X);
        t.expected = o.rect.center + Vec2::X * 0.06;
        t.pending = Some((Vec2::X, 0.06, o.rect.center));
    }
    let mut next = vec![
        seen_box(0, Vec2::new(0.61, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
        seen_box(0, Vec2::new(0.65, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
    ];
    track(&mut next, &mut tracks, 0.06, params.push_jam_share);
    assert_eq!((next[0].id, next[1].id), (0, 1));
    assert!(tracks[0].rules_out(Vec2::X, &params));
    assert!(!tracks[1].rules_out(Vec2::X, &params));
    assert!(tracks.iter().all(|t| t.pending.is_none()));
}

#[test]
fn drops_go_around_the_bin() {
    let spots: Vec<Vec3> = (0..9).map(|k| drop_offset(k, 0.1)).collect();
    assert_eq!(spots[0], Vec3::ZERO);
    for (i, a) in spots.iter().enumerate() {
        assert!(a.x.abs() <= 0.1 && a.y.abs() <= 0.1);
        assert!(spots[i + 1..].iter().all(|b| b != a));
    }
    assert_eq!(drop_offset(9, 0.1), spots[0]);
}

#[test]
fn params_load_from_toml_with_the_seed_defaults_elsewhere() {
    let p: ClearParams =
        toml::from_str("push_distance = 0.05\n[tabletop]\nmin_object_points = 150\n").unwrap();
    assert_eq!(p.push_distance, 0.05);
    assert_eq!(p.tabletop.min_object_points, 150);
    assert_eq!(p.push_max_length, 0.6);
    assert_eq!(p.push_resolution, 0.03);
    assert_eq!(p.pregrasp, 0.10);
    assert_eq!(p.lift, 0.20);
    assert!(toml::from_str::<ClearParams>("nope = 1").is_err());
    let q: ClearParams = toml::from_str("[at_risk]\nheld_up = 0.02\n").unwrap();
    assert_eq!((q.at_risk.held_up, q.at_risk.lean_slope), (0.02, 0.18));
    assert!(p.validate().is_ok());
    for bad in [
        "push_resolution = 0.0",
        "push_max_length = inf",
        "clearance = nan",
        "decimate = 0",
        "chain_push_factors = [-1.0]",
        "[at_risk]\nlean_slope = -0.1",
        "[at_risk]\nperched = nan",
    ] {
        let q: ClearParams = toml::from_str(bad).unwrap();
        assert_eq!(q.validate().unwrap_err().kind(), "params", "{bad}");
    }
}

/// A can of radius 2 cm lying along x from `x0` to `x1` (world), its axis rising from
/// `z0` to `z1` (world z of the axis), seen as points on its upper half every 5 mm.
fn seen_lying_can(id: usize, (x0, x1): (f64, f64), (z0, z1): (f64, f64)) -> SeenObject {
    let r = 0.02;
    let mut points = Vec::new();
    let n = ((x1 - x0) / 0.005) as i32;
    for i in 0..=n {
        let s = i as f64 / n as f64;
        let (x, z) = (x0 + s * (x1 - x0), z0 + s * (z1 - z0));
        for k in 0..=8 {
            let a = std::f64::consts::PI * k as f64 / 8.0;
            points.push(Vec3::new(x, 0.3 + r * a.cos(), z + r * a.sin()));
        }
    }
    seen_points(id, points, 0.72)
}

#[test]
fn objects_held_up_or_leaning_are_at_risk_and_flat_ones_are_not() {
    let at_risk = |o: &SeenObject, z| super::AtRisk::default().of(o, z);
    let flat_box = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.1), 0.05, 0.72);
    let on_top = seen_box(1, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.04), 0.04, 0.77);
    let lying = seen_lying_can(2, (0.5, 0.6), (0.74, 0.74));
    // One end on the table, the other on a 4 cm box: 22° up.
    let leaning = seen_lying_can(3, (0.5, 0.6), (0.74, 0.78));
    // A 4 mm rise over 10 cm is a can on an uneven pile, not a lean.
    let nearly = seen_lying_can(4, (0.5, 0.6), (0.74, 0.744));
    assert_eq!(at_risk(&flat_box, 0.72), 0.0);
    assert!((at_risk(&on_top, 0.72) - 0.05).abs() < 1e-9);
    assert_eq!(at_risk(&lying, 0.72), 0.0);
    assert!(at_risk(&leaning, 0.72) > 0.02);
    assert_eq!(at_risk(&nearly, 0.72), 0.0);
}

#[test]
fn the_plan_takes_what_is_held_up_first_where_it_can_go_now() {
    use super::first::first_step;
    use tabula_pddl::PlanStep;
    let objects = box_on_box_and_lone();
    let g = predicates(&objects, &hand(), &ClearParams::default(), false);
    let step = |a: &str, i: usize| PlanStep {
        action: a.into(),
        args: vec![format!("o{i}")],
    };
    let index_of = |s: &PlanStep| s.args[0][1..].parse::<usize>().ok();
    let urgency_of = |i: usize| urgency(&objects, i);
    // The planner's order took the lone box first: the box held up goes before it.
    let plan = [step("grasp", 2), step("grasp", 1), step("grasp", 0)];
    assert_eq!(first_step(&plan, &g, urgency_of, index_of), 1);
    // Nothing at risk that can go now: the plan's own order.
    let plan = [step("grasp", 2), step("grasp", 0)];
    assert_eq!(first_step(&plan, &g, urgency_of, index_of), 0);
    let plan = [step("push_dir1", 2), step("grasp", 2)];
    assert_eq!(first_step(&plan, &g, urgency_of, index_of), 0);
}

/// How urgent lifting `objects[i]` is on the test table (as the decision has it).
fn urgency(objects: &[SeenObject], i: usize) -> super::first::Urgency {
    let at_risk = super::AtRisk::default();
    super::first::Urgency {
        props_up: (objects.iter().enumerate())
            .any(|(j, a)| j != i && at_risk.props_up(&objects[i], a, 0.72)),
        risk: at_risk.of(&objects[i], 0.72),
    }
}

#[test]
fn what_a_leaning_can_rests_on_is_lifted_after_what_props_nothing_up() {
    use super::first::first_step;
    use tabula_pddl::PlanStep;
    // A 4 cm box with a can leaning on it from the table (its end on the box's
    // edge), and a lone box away from both.
    let objects = vec![
        seen_box(0, Vec2::new(0.65, 0.3), Vec2::new(0.06, 0.05), 0.04, 0.72),
        seen_lying_can(1, (0.5, 0.625), (0.74, 0.78)),
        seen_box(2, Vec2::new(0.3, -0.2), Vec2::new(0.05, 0.05), 0.05, 0.72),
    ];
    let props = |i: usize| urgency(&objects, i).props_up;
    assert_eq!((props(0), props(1), props(2)), (true, false, false));
    let mut g = predicates(&objects, &hand(), &ClearParams::default(), false);
    // (Whatever the hand's clearance says, all three can go now here.)
    g.block_grasp.clear();
    let step = |i: usize| PlanStep {
        action: "grasp".into(),
        args: vec![format!("o{i}")],
    };
    let index_of = |s: &PlanStep| s.args[0][1..].parse::<usize>().ok();
    let urgency_of = |i: usize| urgency(&objects, i);
    // The can first (it is at risk), the box under it last.
    let plan = [step(0), step(2), step(1)];
    assert_eq!(first_step(&plan, &g, urgency_of, index_of), 2);
    let plan = [step(0), step(2)];
    assert_eq!(first_step(&plan, &g, urgency_of, index_of), 1);
    // Only the box can go: it goes.
    assert_eq!(first_step(&[step(0)], &g, urgency_of, index_of), 0);
    // Pushing the box would drop the can as well as lifting it.
    let push = PlanStep {
        action: "push_dir1".into(),
        args: vec!["o0".into()],
    };
    assert_eq!(first_step(&[push, step(2)], &g, urgency_of, index_of), 1);
    // Nothing leans on a box of the same height beside it.
    let level = [
        objects[0].clone(),
        seen_box(3, Vec2::new(0.71, 0.3), Vec2::new(0.06, 0.05), 0.04, 0.72),
    ];
    assert!(!urgency(&level, 0).props_up && !urgency(&level, 1).props_up);
}

/// The split pushes of the first of `objects` on [`table`].
fn split_pushes(
    objects: &[SeenObject],
    hand: &Hand,
    params: &ClearParams,
) -> Vec<(usize, push::Push)> {
    on_table(objects, hand, params, |v| v.split_pushes(0))
}

#[test]
fn a_strip_longer_than_the_hand_is_split_at_either_end_where_the_way_is_free() {
    let (h, params) = (hand(), ClearParams::default());
    // Two tiles on edge end to end seen as one 9.5 × 1.7 cm strip (blocks seed 154),
    // and a box beside one end of it on the +y side.
    let strip = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.095, 0.017), 0.048, 0.72);
    let beside = seen_box(1, Vec2::new(0.625, 0.05), Vec2::new(0.04, 0.04), 0.05, 0.72);
    let splits = split_pushes(&[strip, beside], &h, &params);
    // The -x end either way across the strip; at the +x end the box is in the way of
    // one push and stands where the fingers would start the other.
    let starts: Vec<Vec3> = splits.iter().map(|s| s.1.start.translation).collect();
    assert_eq!(splits.len(), 2, "{starts:?}");
    assert!(starts.iter().all(|s| s.x < 0.6), "{starts:?}");
    for (_, p) in &splits {
        assert!(
            p.split && p.direction.x.abs() < 1e-6,
            "across the strip: {:?}",
            p.direction
        );
        // The fingers start at one end, not the middle, beside the strip.
        let start = p.start.translation;
        assert!((start.x - 0.6).abs() > 0.015, "at an end: {start:?}");
        assert!(start.y * p.direction.y < 0.0, "behind the strip: {start:?}");
        // Past the end's own width (its points span 1.5 cm) and the gap.
        assert!(p.length >= 0.015 + params.split_gap - 1e-6, "{}", p.length);
    }
    // Nothing the open hand spans is split: a 6 cm box.
    let short = vec![seen_box(
        0,
        Vec2::new(0.6, 0.0),
        Vec2::new(0.06, 0.03),
        0.05,
        0.72,
    )];
    assert!(split_pushes(&short, &h, &params).is_empty());
}

#[test]
fn a_segment_too_wide_both_ways_is_split_along_its_length() {
    let (h, params) = (hand(), ClearParams::default());
    // A bar beside an arch seen as one 10 × 13 cm blob (blocks seed 127): each holds
    // across its own 5 cm, so they lie side by side across the blob, and an end push
    // would move both. One side slides along the seam instead, past its own length.
    let blob = vec![seen_box(
        0,
        Vec2::new(0.6, 0.0),
        Vec2::new(0.1, 0.13),
        0.036,
        0.72,
    )];
    let splits = split_pushes(&blob, &h, &params);
    assert_eq!(splits.len(), 4);
    for (_, p) in &splits {
        assert!(
            p.direction.y.abs() > 0.999,
            "along the seam: {:?}",
            p.direction
        );
        let off = p.start.translation.x - 0.6;
        assert!(off.abs() > 0.015, "one side: {:?}", p.start);
        assert!(p.length >= 0.125 + params.split_gap - 1e-6, "{}", p.length);
    }
}
