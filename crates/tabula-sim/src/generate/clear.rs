//! The clearing suites: random, packed grids, settled piles and the wider families of
//! [`super::blocks`] in the clearing cell.

use super::blocks::{self, Area, Written};
use super::tabletop::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write;

/// The scene families of the clearing benchmark (SPEC §3, issue "Clearing a cluttered
/// table").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClearSuite {
    /// Seed 002's scene (`scenes/clutter.toml`); the seed only changes camera noise.
    Seed,
    /// 3–12 boxes and cylinders, some touching, some stacked.
    Random,
    /// A grid of boxes a few millimetres apart: every grasp is blocked at first.
    Packed,
    /// 20–30 graspable objects dropped onto the table from above (VPG-style).
    Pile,
    /// Blocks that are not boxes or cylinders — triangular prisms lying and standing,
    /// arches, half-cylinders, tiles on edge, bars — packed 1–4 mm apart or boxed in.
    Blocks,
    /// Boxes and cylinders in grids spaced anything from touching to a finger's width.
    Grid,
    /// Objects at the grip's limits: thin and tall, short and wide.
    Limits,
}

impl std::str::FromStr for ClearSuite {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "seed" => Ok(Self::Seed),
            "random" => Ok(Self::Random),
            "packed" => Ok(Self::Packed),
            "pile" => Ok(Self::Pile),
            "blocks" => Ok(Self::Blocks),
            "grid" => Ok(Self::Grid),
            "limits" => Ok(Self::Limits),
            other => Err(format!(
                "unknown suite `{other}`: seed, random, packed, pile, blocks, grid or limits"
            )),
        }
    }
}

/// A scene's objects: drawn by the tabletop generator's shapes, or written directly.
enum Objects {
    Placed(Vec<Placed>),
    Written(Vec<Written>),
}

/// The clearing cell: table centre and size, the region objects are put in (every point
/// of it reachable from above by the WAM on its stand), the bin.
pub const CLEAR_TABLE_CENTER: [f64; 2] = [0.62, 0.0];
pub const CLEAR_TABLE_SIZE: [f64; 2] = [0.7, 1.0];
pub const CLEAR_REGION_CENTER: [f64; 2] = [0.58, 0.0];
pub const CLEAR_REGION_HALF: [f64; 2] = [0.17, 0.25];
/// The bin's footprint centre and its height (m).
pub const CLEAR_BIN_CENTER: [f64; 2] = [0.0, 0.6];
pub const CLEAR_BIN_HEIGHT: f64 = 0.45;
/// The stand's footprint (m): a robot stands on it beside the table.
const CLEAR_STAND_SIDE: f64 = 0.3;

/// Where a robot of the user's stands in the clearing cell in place of the WAM: on the
/// stand at `xyz` (its top at `xyz.z`), starting at `joints`.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotMount {
    /// The robot's URDF or xacro file (absolute, or relative to where the scene is read).
    pub urdf: String,
    pub srdf: Option<String>,
    pub xacro_args: Vec<(String, String)>,
    pub xyz: [f64; 3],
    pub joints: std::collections::BTreeMap<String, f64>,
}

impl RobotMount {
    /// The scene's `[[robot]]` on its stand (a pedestal of its model: its planners
    /// know what it stands on, as a cell's URDF tells MoveIt).
    fn write(&self, s: &mut String) {
        let quoted = |v: &str| toml::Value::String(v.to_string()).to_string();
        let [x, y, z] = self.xyz;
        let _ = writeln!(
            s,
            "[[robot]]\nname = \"robot\"\nurdf = {}",
            quoted(&self.urdf)
        );
        if let Some(srdf) = &self.srdf {
            let _ = writeln!(s, "srdf = {}", quoted(srdf));
        }
        if !self.xacro_args.is_empty() {
            let args: Vec<String> = self
                .xacro_args
                .iter()
                .map(|(k, v)| format!("{} = {}", quoted(k), quoted(v)))
                .collect();
            let _ = writeln!(s, "xacro_args = {{ {} }}", args.join(", "));
        }
        let joints: Vec<String> = self
            .joints
            .iter()
            .map(|(k, v)| format!("{} = {v:?}", quoted(k)))
            .collect();
        let _ = writeln!(
            s,
            "pose = {{ xyz = [{x:?}, {y:?}, {z:?}] }}\npedestal = [{CLEAR_STAND_SIDE:?}, {CLEAR_STAND_SIDE:?}, {z:?}]\njoints = {{ {} }}\n",
            joints.join(", ")
        );
    }
}
/// Widest object across its narrower side: seed 002's gripper opens 7 cm.
const CLEAR_GRIP: f64 = 0.06;

/// A clearing scene of `suite` drawn by `seed` (TOML; same inputs, same text): the WAM
/// on a stand beside a table, the bin beside it, an overhead camera, the objects.
pub fn clearing_scene(suite: ClearSuite, seed: u64) -> String {
    clearing_scene_with(suite, seed, None)
}

/// [`clearing_scene`] with another robot on the stand (`mount`), the same objects.
pub fn clearing_scene_with(suite: ClearSuite, seed: u64, mount: Option<&RobotMount>) -> String {
    if suite == ClearSuite::Seed {
        return match mount {
            None => crate::builtin::CLUTTER.to_string(),
            Some(m) => seed_scene_with(m),
        };
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xC1EA_7AB1);
    let area = Area {
        center: CLEAR_REGION_CENTER,
        half: CLEAR_REGION_HALF,
        top: TABLE_TOP,
    };
    let placed = match suite {
        ClearSuite::Random => {
            let objects = rng.random_range(3..=12usize);
            let layout = TabletopLayout {
                objects,
                touching_pairs: rng.random_range(0..=(objects / 2).min(2)),
                stacked_pairs: usize::from(objects >= 4 && rng.random_bool(0.6)),
                ..TabletopLayout::nine()
            };
            let region = Region {
                center: CLEAR_REGION_CENTER,
                half: CLEAR_REGION_HALF,
                top: TABLE_TOP,
                gap: 0.03,
                grip: Some(CLEAR_GRIP),
            };
            Objects::Placed(place_groups(&mut rng, &layout, &region))
        }
        ClearSuite::Packed => Objects::Placed(packed_grid(&mut rng)),
        ClearSuite::Blocks => Objects::Written(blocks::blocks(&mut rng, &area)),
        ClearSuite::Grid => Objects::Written(blocks::spaced_grid(&mut rng, &area)),
        ClearSuite::Limits => Objects::Written(blocks::limits(&mut rng, &area)),
        _ => Objects::Placed(pile(&mut rng)),
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Generated by tabula_sim::generate::clearing_scene({suite:?}, {seed})\n\n[floor]\nsize = [8.0, 8.0]\n"
    );
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = {{ xyz = [{}, {}, 0.0] }}\nsize = [{}, {}, {TABLE_TOP}]\n",
        CLEAR_TABLE_CENTER[0], CLEAR_TABLE_CENTER[1], CLEAR_TABLE_SIZE[0], CLEAR_TABLE_SIZE[1]
    );
    if mount.is_none() {
        let _ = writeln!(
            s,
            "[[furniture]]\nname = \"stand\"\nkind = \"table\"\nsize = [{CLEAR_STAND_SIDE:?}, {CLEAR_STAND_SIDE:?}, 0.6]\n"
        );
    }
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"bin\"\nkind = \"bin\"\npose = {{ xyz = [{:?}, {:?}, 0.0] }}\nsize = [0.4, 0.4, {CLEAR_BIN_HEIGHT:?}]\n",
        CLEAR_BIN_CENTER[0], CLEAR_BIN_CENTER[1]
    );
    match placed {
        Objects::Placed(placed) => write_objects(&mut s, &mut rng, &placed),
        Objects::Written(written) => {
            for (i, (shape, xyz, rpy)) in written.iter().enumerate() {
                write_object(&mut s, &mut rng, i, shape, (*xyz, *rpy));
            }
        }
    }
    match mount {
        Some(m) => m.write(&mut s),
        None => s.push_str(WAM_ON_STAND),
    }
    let _ = writeln!(
        s,
        "\n[[camera]]\nname = \"overhead\"\nlook_at = {{ eye = [{0}, {1}, 1.75], target = [{0}, {1}, {TABLE_TOP}] }}",
        CLEAR_TABLE_CENTER[0], CLEAR_TABLE_CENTER[1]
    );
    if suite == ClearSuite::Pile {
        return settle_pile(&s, &mut rng).unwrap_or(s);
    }
    s
}

/// Seed 002's WAM on its stand, tucked (`scenes/clutter.toml`).
const WAM_ON_STAND: &str = "[[robot]]\nname = \"wam\"\nurdf = \"wam\"\npose = { xyz = [0.0, 0.0, 0.6] }\njoints = { wam_joint2 = -1.9, wam_joint4 = 2.6 }\n";

/// Seed 002's scene with `mount` in place of the WAM and its stand.
fn seed_scene_with(mount: &RobotMount) -> String {
    let stand = "[[furniture]]\nname = \"stand\"\nkind = \"table\"\npose = { xyz = [0.0, 0.0, 0.0] }\nsize = [0.3, 0.3, 0.6]\n";
    let text = crate::builtin::CLUTTER.replace(stand, "");
    let (objects, rest) = text.split_once("[[robot]]").unwrap_or((&text, ""));
    let camera = rest.find("[[camera]]").map_or("", |i| &rest[i..]);
    let mut s = objects.to_string();
    mount.write(&mut s);
    s.push_str(camera);
    s
}

/// Lets a pile fall and drops again, over the middle of the region, whatever bounced
/// out of the region the arm reaches (VPG resets objects that leave its workspace the
/// same way); what is still out after five rounds is taken away. The scene written is
/// the settled pile.
fn settle_pile(text: &str, rng: &mut ChaCha8Rng) -> Option<String> {
    let scene = crate::Scene::parse(text, "generated").ok()?;
    let mut world = crate::SimWorld::from_scene(&scene, crate::PhysicsParams::default()).ok()?;
    let inside = |p: tabula_geom::Vec3| {
        (p.x - CLEAR_REGION_CENTER[0]).abs() <= CLEAR_REGION_HALF[0] + 0.03
            && (p.y - CLEAR_REGION_CENTER[1]).abs() <= CLEAR_REGION_HALF[1] + 0.03
            && p.z > TABLE_TOP
    };
    for round in 0..=5 {
        world.settle();
        let out: Vec<String> = world
            .object_poses()
            .into_iter()
            .filter(|(_, p)| !inside(p.translation))
            .map(|(n, _)| n)
            .collect();
        if out.is_empty() {
            break;
        }
        for (k, name) in out.iter().enumerate() {
            if round == 5 {
                world.delete(name).ok()?;
                continue;
            }
            let x = CLEAR_REGION_CENTER[0] + rng.random_range(-0.08..0.08);
            let y = CLEAR_REGION_CENTER[1] + rng.random_range(-0.12..0.12);
            // Higher until it is clear of what is already in the air there.
            let dropped = (0..10).any(|up| {
                let z = TABLE_TOP + 0.3 + 0.1 * (k + up) as f64;
                world
                    .move_to(
                        name,
                        tabula_geom::Pose::from_translation(tabula_geom::Vec3::new(x, y, z)),
                    )
                    .is_ok()
            });
            if !dropped {
                world.delete(name).ok()?;
            }
        }
    }
    // A heavy pile can press two objects into each other deeper than a saved scene
    // may hold them: the one the loader refuses leaves the pile.
    for _ in 0..10 {
        let settled = world.to_scene().to_toml().ok()?;
        let reloaded = crate::Scene::parse(&settled, "settled")
            .ok()
            .map(|s| crate::SimWorld::from_scene(&s, crate::PhysicsParams::default()));
        match reloaded {
            Some(Ok(_)) => {
                return Some(format!(
                    "# Generated by tabula_sim::generate::clearing_scene(Pile, …), settled\n\n{settled}"
                ));
            }
            Some(Err(crate::SimError::Overlap { new, .. })) => {
                world.delete(&new).ok()?;
                world.settle();
            }
            _ => return None,
        }
    }
    None
}

/// Boxes in a grid, 3–8 mm apart (less than a finger is thick), 2–3 rows of 2–4.
fn packed_grid(rng: &mut ChaCha8Rng) -> Vec<Placed> {
    let rows = rng.random_range(2..=3usize);
    let cols = rng.random_range(2..=4usize);
    let cell = [rng.random_range(0.04..0.06), rng.random_range(0.04..0.06)];
    let gap = rng.random_range(0.003..0.008);
    let yaw: f64 = rng.random_range(-0.8..0.8);
    let (s, c) = yaw.sin_cos();
    let reach = 0.5 * ((rows as f64) * (cell[0] + gap)).hypot((cols as f64) * (cell[1] + gap));
    let center = [
        CLEAR_REGION_CENTER[0]
            + rng.random_range(-1.0..1.0) * (CLEAR_REGION_HALF[0] - reach).max(0.0),
        CLEAR_REGION_CENTER[1]
            + rng.random_range(-1.0..1.0) * (CLEAR_REGION_HALF[1] - reach).max(0.0),
    ];
    let mut out = Vec::new();
    for r in 0..rows {
        for k in 0..cols {
            let size = [
                cell[0] - rng.random_range(0.0..0.005),
                cell[1] - rng.random_range(0.0..0.005),
                rng.random_range(0.05..0.11),
            ];
            let lx = (r as f64 - (rows as f64 - 1.0) / 2.0) * (cell[0] + gap);
            let ly = (k as f64 - (cols as f64 - 1.0) / 2.0) * (cell[1] + gap);
            out.push(Placed::upright(
                Shape::Box(size),
                [
                    center[0] + c * lx - s * ly,
                    center[1] + s * lx + c * ly,
                    TABLE_TOP + size[2] / 2.0 + 0.001,
                ],
                yaw,
            ));
        }
    }
    out
}

/// 20–30 graspable boxes and cylinders released from 5–30 cm above the table at random
/// orientations, over a small area so they land on and against each other; physics
/// makes the pile when the scene is settled.
fn pile(rng: &mut ChaCha8Rng) -> Vec<Placed> {
    let n = rng.random_range(20..=30usize);
    let mut out: Vec<Placed> = Vec::new();
    let mut height = TABLE_TOP + 0.05;
    for _ in 0..n {
        let shape = match random_shape(rng).fit_grip(Some(CLEAR_GRIP)) {
            // A dropped box rests on any face: graspable from above on every one when
            // two of its sides fit the grip (VPG's blocks are graspable however they
            // land). One side fitting leaves faces no top grasp can take.
            Shape::Box(s) => {
                let mut s = [s[0], s[1], s[2].min(0.08)];
                s.sort_by(f64::total_cmp);
                s[1] = s[1].min(CLEAR_GRIP);
                Shape::Box(s)
            }
            Shape::Cylinder { radius, height } => Shape::Cylinder {
                radius,
                height: height.min(0.09),
            },
        };
        let r = shape.bounding_radius();
        // Drop each where it does not overlap one already in the air at that level.
        let mut xyz = [0.0; 3];
        // Every failed try raises the drop level: a free spot is always found.
        for _ in 0..1000 {
            xyz = [
                CLEAR_REGION_CENTER[0] + rng.random_range(-0.12..0.12),
                CLEAR_REGION_CENTER[1] + rng.random_range(-0.18..0.18),
                height + r,
            ];
            let free = out.iter().all(|p| {
                let d = [p.xyz[0] - xyz[0], p.xyz[1] - xyz[1], p.xyz[2] - xyz[2]];
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
                    > r + p.shape.bounding_radius() + 0.005
            });
            if free {
                break;
            }
            height += 0.01;
        }
        out.push(Placed {
            shape,
            xyz,
            rpy: [
                rng.random_range(-3.1..3.1),
                rng.random_range(-3.1..3.1),
                rng.random_range(-3.1..3.1),
            ],
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mount() -> RobotMount {
        RobotMount {
            urdf: "/robots/my \"arm\".urdf".into(),
            srdf: Some("/robots/arm.srdf".into()),
            xacro_args: vec![("hand".into(), "true".into())],
            xyz: [0.06, 0.0, 0.7],
            joints: [("j1".to_string(), -0.5)].into_iter().collect(),
        }
    }

    /// Another robot takes the WAM's place on a pedestal of its height; the objects, the
    /// table, the bin and the camera stay as they are.
    #[test]
    fn a_mounted_robot_replaces_the_wam_and_its_stand() {
        let m = mount();
        for suite in [ClearSuite::Seed, ClearSuite::Random, ClearSuite::Grid] {
            let plain = crate::Scene::parse(&clearing_scene(suite, 3), "plain").unwrap();
            let text = clearing_scene_with(suite, 3, Some(&m));
            let scene = crate::Scene::parse(&text, "mounted").unwrap();
            let [robot] = scene.robots.as_slice() else {
                panic!("{suite:?}: {} robots", scene.robots.len())
            };
            assert_eq!(robot.urdf, m.urdf);
            assert_eq!(robot.srdf, m.srdf);
            assert_eq!(
                robot.xacro_args.get("hand").map(String::as_str),
                Some("true")
            );
            assert_eq!(robot.pose.xyz, m.xyz);
            assert_eq!(robot.joints, m.joints);
            // The stand is the robot's pedestal, down to the floor.
            assert_eq!(robot.pedestal, Some([0.3, 0.3, 0.7]));
            assert!(scene.furniture.iter().all(|f| f.name.get_ref() != "stand"));
            assert_eq!(scene.objects.len(), plain.objects.len());
            assert_eq!(scene.cameras.len(), plain.cameras.len());
            assert_eq!(scene.furniture.len(), plain.furniture.len() - 1);
        }
    }

    /// Without a mount the scene text is what it was before mounts existed (the
    /// benchmarks' rows stay comparable).
    #[test]
    fn the_wam_cell_is_written_as_before() {
        let text = clearing_scene(ClearSuite::Random, 5);
        let cell = "[[furniture]]\nname = \"stand\"\nkind = \"table\"\nsize = [0.3, 0.3, 0.6]\n\n\
                    [[furniture]]\nname = \"bin\"\nkind = \"bin\"\npose = { xyz = [0.0, 0.6, 0.0] }\n\
                    size = [0.4, 0.4, 0.45]\n\n[[object]]";
        assert!(text.contains(cell), "{text}");
        let tail = "joints = { wam_joint2 = -1.9, wam_joint4 = 2.6 }\n\n[[camera]]\nname = \"overhead\"\n\
                    look_at = { eye = [0.62, 0, 1.75], target = [0.62, 0, 0.72] }";
        assert!(text.ends_with(&format!("{tail}\n")), "{text}");
    }

    /// Every pile object can be taken from above however it lands: a box's two
    /// smaller sides fit the grip (any face it rests on has one of them), a cylinder's
    /// diameter does (standing or lying).
    #[test]
    fn pile_objects_fit_the_grip_on_every_face() {
        for seed in 0..20 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            for p in pile(&mut rng) {
                match p.shape {
                    Shape::Box(s) => {
                        let mut s = s;
                        s.sort_by(f64::total_cmp);
                        assert!(s[1] <= CLEAR_GRIP + 1e-12, "{s:?}");
                    }
                    Shape::Cylinder { radius, .. } => {
                        assert!(2.0 * radius <= CLEAR_GRIP + 1e-12, "{radius}")
                    }
                }
            }
        }
    }
}
