//! The tidying family: a PR2 before a table with 2–6 boxes and cans on it, and one or
//! two other surfaces around it (a table behind or beside it, some already holding
//! things that must stay standing) to put them on.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write;

/// A generated tidying task.
#[derive(Debug, Clone)]
pub struct TidyTask {
    pub scene: String,
    /// The furniture to clear.
    pub source: String,
    /// Objects on it at the start.
    pub objects: usize,
    /// The other surfaces (furniture names).
    pub targets: Vec<String>,
    /// Objects already standing on them.
    pub residents: usize,
}

/// The PR2 with its torso up, its head towards the table and its arms out to the
/// sides (a tucked arm's fingers cannot open against the torso).
const PR2: &str = "[[robot]]\nname = \"pr2\"\nurdf = \"pr2\"\njoints = { torso_lift_joint = 0.2, head_tilt_joint = 0.7, r_shoulder_pan_joint = -1.3, r_shoulder_lift_joint = 0.1, r_elbow_flex_joint = -1.6, r_wrist_flex_joint = -0.6, l_shoulder_pan_joint = 1.5, l_elbow_flex_joint = -2.0, l_wrist_flex_joint = -0.5 }\n\n[[camera]]\nname = \"head\"\nrobot = \"pr2\"\nlink = \"head_camera_optical_frame\"\n";

/// An object's shape line and height: a box or a can a top grasp of the PR2 takes.
fn object_shape(rng: &mut ChaCha8Rng) -> (String, f64) {
    let h = rng.random_range(0.06..0.14);
    if rng.random_bool(0.5) {
        let (a, b) = (rng.random_range(0.035..0.06), rng.random_range(0.035..0.08));
        (format!("{{ box = [{a:.4}, {b:.4}, {h:.4}] }}"), h)
    } else {
        let r = rng.random_range(0.018..0.03);
        (
            format!("{{ cylinder = {{ radius = {r:.4}, height = {h:.4} }} }}"),
            h,
        )
    }
}

/// `n` points in the box `lo`–`hi` (xy) at least `gap` apart (fewer if they do not fit).
fn spread(rng: &mut ChaCha8Rng, n: usize, lo: [f64; 2], hi: [f64; 2], gap: f64) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::new();
    for _ in 0..(200 * n) {
        if out.len() == n {
            break;
        }
        let p = [
            rng.random_range(lo[0]..hi[0]),
            rng.random_range(lo[1]..hi[1]),
        ];
        if out.iter().all(|q| (q[0] - p[0]).hypot(q[1] - p[1]) >= gap) {
            out.push(p);
        }
    }
    out
}

fn object(s: &mut String, name: &str, shape: &str, xy: [f64; 2], bottom: f64, h: f64, yaw: f64) {
    let _ = writeln!(
        s,
        "[[object]]\nname = \"{name}\"\nshape = {shape}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [0.0, 0.0, {yaw:.3}] }}\nmass = 0.12\n",
        xy[0],
        xy[1],
        bottom + h / 2.0 + 0.001
    );
}

fn table(s: &mut String, name: &str, centre: [f64; 2], size: [f64; 3], yaw: f64) {
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"{name}\"\nkind = \"table\"\npose = {{ xyz = [{:.3}, {:.3}, 0.0], rpy = [0.0, 0.0, {yaw:.3}] }}\nsize = [{:.3}, {:.3}, {:.3}]\n",
        centre[0], centre[1], size[0], size[1], size[2]
    );
}

/// The family's task `seed`. Same seed, same task.
pub fn tidy_task(seed: u64) -> TidyTask {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x71D7);
    let mut s = String::from("# A generated tidying task (tabula tidy).\n[floor]\n\n");
    // The table to clear, in front; objects where a top grasp reaches them.
    let (depth, width, height) = (
        rng.random_range(0.55..0.7),
        rng.random_range(0.9..1.2),
        rng.random_range(0.68..0.76),
    );
    let near = rng.random_range(0.5..0.56);
    table(
        &mut s,
        "table",
        [near + depth / 2.0, 0.0],
        [depth, width, height],
        0.0,
    );
    let n = rng.random_range(2..=6);
    let spots = spread(&mut rng, n, [near + 0.1, -0.3], [near + 0.24, 0.3], 0.11);
    for (k, xy) in spots.iter().enumerate() {
        let (shape, h) = object_shape(&mut rng);
        let yaw = rng.random_range(-0.8..0.8);
        object(&mut s, &format!("item{k}"), &shape, *xy, height, h, yaw);
    }
    // One or two other tables: behind, or beside (turned to face the robot).
    let mut targets = Vec::new();
    let mut residents = 0;
    let sides = if rng.random_bool(0.5) { 2 } else { 1 };
    let mut places = [0usize, 1, 2];
    let first = rng.random_range(0..3);
    places.swap(0, first);
    for (k, &where_) in places.iter().take(sides).enumerate() {
        let name = format!("target{k}");
        let (d, w, h) = (
            rng.random_range(0.5..0.7),
            rng.random_range(0.8..1.1),
            rng.random_range(0.6..0.78),
        );
        let gap = rng.random_range(1.0..1.4);
        let (centre, yaw) = match where_ {
            0 => ([-gap - d / 2.0, rng.random_range(-0.2..0.2)], 0.0),
            1 => (
                [rng.random_range(-0.2..0.2), gap + d / 2.0],
                std::f64::consts::FRAC_PI_2,
            ),
            _ => (
                [rng.random_range(-0.2..0.2), -gap - d / 2.0],
                std::f64::consts::FRAC_PI_2,
            ),
        };
        table(&mut s, &name, centre, [d, w, h], yaw);
        if rng.random_bool(0.5) {
            // Something already stands on it, off to one end.
            let (shape, oh) = object_shape(&mut rng);
            let along = if rng.random_bool(0.5) { 1.0 } else { -1.0 } * (w / 2.0 - 0.12);
            let (c, sn) = (yaw.cos(), yaw.sin());
            let xy = [centre[0] - sn * along, centre[1] + c * along];
            object(&mut s, &format!("resident{k}"), &shape, xy, h, oh, 0.0);
            residents += 1;
        }
        targets.push(name);
    }
    s.push_str(PR2);
    TidyTask {
        scene: s,
        source: "table".into(),
        objects: spots.len(),
        targets,
        residents,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::judge::tidy::TidyStart;
    use crate::{Scene, SimWorld};

    #[test]
    fn the_family_is_seeded_and_every_object_starts_on_the_table() {
        for seed in 1..=6 {
            let task = tidy_task(seed);
            assert_eq!(task.scene, tidy_task(seed).scene);
            assert!((2..=6).contains(&task.objects), "{}", task.objects);
            assert!((1..=2).contains(&task.targets.len()));
            let scene = Scene::parse(&task.scene, "tidy").unwrap();
            let mut world = SimWorld::from_scene(&scene, Default::default()).unwrap();
            world.settle();
            let start = TidyStart::of(&world, "table").unwrap();
            // Untouched, the judge sees every object still on the table, nothing moved.
            let v = start.verdict(&world);
            assert_eq!(v.objects, task.objects, "seed {seed}: {v:?}");
            assert_eq!(v.left, task.objects);
            assert_eq!(v.moved, 0);
            assert!(v.knocked.is_empty() && v.lost.is_empty(), "{v:?}");
        }
    }

    #[test]
    fn the_judge_counts_moves_knocks_and_losses() {
        let task = tidy_task(2);
        let scene = Scene::parse(&task.scene, "tidy").unwrap();
        let mut world = SimWorld::from_scene(&scene, Default::default()).unwrap();
        world.settle();
        let start = TidyStart::of(&world, "table").unwrap();
        assert!(TidyStart::of(&world, "no_such_table").is_err());
        // One object onto the first target, one onto the floor.
        let target = &task.targets[0];
        let t = world.entity_bounds(target).unwrap();
        let c = t.center();
        world
            .move_to(
                "item0",
                tabula_geom::Pose::from_translation(tabula_geom::Vec3::new(
                    c.x,
                    c.y,
                    t.maxs.z + 0.1,
                )),
            )
            .unwrap();
        world
            .move_to(
                "item1",
                tabula_geom::Pose::from_translation(tabula_geom::Vec3::new(0.0, -0.9, 0.2)),
            )
            .unwrap();
        world.settle();
        let v = start.verdict(&world);
        assert_eq!(v.moved, 1, "{v:?}");
        assert_eq!(v.lost, vec!["item1".to_string()]);
        assert_eq!(v.left, task.objects - 2);
    }
}
