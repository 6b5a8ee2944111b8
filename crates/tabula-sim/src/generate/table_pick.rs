//! Pick and place on the clearing cell's table by a robot mounted there
//! (`bench pick-place --robot`): one of a random table's objects that stands alone is
//! taken to a free spot of the same table, given by coordinates as seed 001's test
//! gives them.

use super::clear::{
    CLEAR_REGION_CENTER, CLEAR_REGION_HALF, ClearSuite, RobotMount, clearing_scene_with,
};
use super::shelf::ShelfTask;
use super::tabletop::TABLE_TOP;
use crate::scene::{ObjectSpec, Scene, ShapeSpec};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Room between the picked object's footprint and a neighbour's, at the start and at
/// the target (m): the open fingers need it.
const ALONE: f64 = 0.04;
/// The target is at least this far from where the object stands (m).
const MIN_MOVE: f64 = 0.12;
/// The pick point is off the object's centre by up to this along x and y (m), as a
/// person gives it.
const PICK_ERROR: f64 = 0.01;
/// Scenes drawn before giving up on a seed.
const MAX_DRAWS: u64 = 50;

/// Task `seed` of the family, with `mount` on the stand; `None` when no draw has an
/// object standing alone and a free spot for it.
pub fn table_pick_place_task(seed: u64, mount: &RobotMount) -> Option<ShelfTask> {
    (0..MAX_DRAWS).find_map(|draw| {
        let scene_seed = seed.wrapping_add(draw.wrapping_mul(1_000_003));
        let text = clearing_scene_with(ClearSuite::Random, scene_seed, Some(mount));
        let scene = Scene::parse(&text, "generated").ok()?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x7AB1_E9C4 ^ draw);
        let feet: Vec<Option<Foot>> = scene.objects.iter().map(Foot::of).collect();
        let mut order: Vec<usize> = (0..feet.len()).collect();
        // A random object first, the rest in order.
        if !order.is_empty() {
            let first = rng.random_range(0..order.len());
            order.rotate_left(first);
        }
        order.into_iter().find_map(|i| {
            let foot = feet[i].as_ref()?;
            let others: Vec<&Foot> = feet
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .filter_map(|(_, f)| f.as_ref())
                .collect();
            let alone = others.iter().all(|o| foot.apart(o.at, o.radius) >= ALONE);
            if !alone || !foot.standing {
                return None;
            }
            let place = free_spot(&mut rng, foot, &others)?;
            let noise = |rng: &mut ChaCha8Rng| rng.random_range(-PICK_ERROR..=PICK_ERROR);
            Some(ShelfTask {
                scene: text.clone(),
                object: scene.objects[i].name.get_ref().clone(),
                pick: [
                    foot.at[0] + noise(&mut rng),
                    foot.at[1] + noise(&mut rng),
                    TABLE_TOP + foot.height / 2.0,
                ],
                place: [place[0], place[1], TABLE_TOP + foot.height / 2.0],
                target: "table".into(),
            })
        })
    })
}

/// An object's footprint as a disc: centre, radius, height, and whether it stands
/// upright on the table (boxes and cylinders only).
struct Foot {
    at: [f64; 2],
    radius: f64,
    height: f64,
    standing: bool,
}

impl Foot {
    fn of(o: &ObjectSpec) -> Option<Self> {
        let (radius, height) = match &o.shape {
            ShapeSpec::Box(s) => (s[0].hypot(s[1]) / 2.0, s[2]),
            ShapeSpec::Cylinder { radius, height } => (*radius, *height),
            _ => return None,
        };
        let [x, y, z] = o.pose.xyz;
        let upright = o.pose.rpy[0].abs() < 1e-6 && o.pose.rpy[1].abs() < 1e-6;
        let on_table = (z - height / 2.0 - TABLE_TOP).abs() < 0.005;
        Some(Self {
            at: [x, y],
            radius,
            height,
            standing: upright && on_table,
        })
    }

    /// Gap between this footprint and a disc at `at` of `radius` (m).
    fn apart(&self, at: [f64; 2], radius: f64) -> f64 {
        (self.at[0] - at[0]).hypot(self.at[1] - at[1]) - self.radius - radius
    }
}

/// A spot of the region where `foot` fits with room from every other object, away from
/// where it stands.
fn free_spot(rng: &mut ChaCha8Rng, foot: &Foot, others: &[&Foot]) -> Option<[f64; 2]> {
    let half = [
        CLEAR_REGION_HALF[0] - foot.radius,
        CLEAR_REGION_HALF[1] - foot.radius,
    ];
    if half[0] <= 0.0 || half[1] <= 0.0 {
        return None;
    }
    (0..200).find_map(|_| {
        let p = [
            CLEAR_REGION_CENTER[0] + rng.random_range(-half[0]..=half[0]),
            CLEAR_REGION_CENTER[1] + rng.random_range(-half[1]..=half[1]),
        ];
        let moved = (p[0] - foot.at[0]).hypot(p[1] - foot.at[1]) >= MIN_MOVE;
        let room = others
            .iter()
            .all(|o| (p[0] - o.at[0]).hypot(p[1] - o.at[1]) - foot.radius - o.radius >= ALONE);
        (moved && room).then_some(p)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every task picks an object standing alone on the table and takes it to a spot of
    /// the region with room around it.
    #[test]
    fn tasks_pick_a_lone_standing_object_and_a_free_spot() {
        let mount = RobotMount {
            urdf: "wam".into(),
            srdf: None,
            xacro_args: Vec::new(),
            xyz: [0.0, 0.0, 0.6],
            joints: Default::default(),
        };
        for seed in 1..=20 {
            let task = table_pick_place_task(seed, &mount).expect("a task");
            let scene = Scene::parse(&task.scene, "t").unwrap();
            let o = scene
                .objects
                .iter()
                .find(|o| *o.name.get_ref() == task.object)
                .unwrap();
            let foot = Foot::of(o).unwrap();
            assert!(foot.standing);
            assert!((task.pick[0] - foot.at[0]).abs() <= PICK_ERROR + 1e-12);
            let moved = (task.place[0] - foot.at[0]).hypot(task.place[1] - foot.at[1]);
            assert!(moved >= MIN_MOVE);
            for other in scene.objects.iter().filter(|x| x.name != o.name) {
                let f = Foot::of(other).unwrap();
                assert!(foot.apart(f.at, f.radius) >= ALONE - 1e-12);
                let at_target = Foot {
                    at: [task.place[0], task.place[1]],
                    ..foot
                };
                assert!(at_target.apart(f.at, f.radius) >= ALONE - 1e-12);
            }
        }
    }
}
