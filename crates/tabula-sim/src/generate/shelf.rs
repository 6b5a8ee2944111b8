//! Golem's shelf family: an object on a shelf board to be picked from the side.

use super::tabletop::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write;

/// A generated pick-and-place task for Golem-III (seed 001's integral test, SPEC §2.5):
/// the scene text, which object to move, where it is (approximately, as the seed gave
/// it) and where it goes.
#[derive(Debug, Clone)]
pub struct ShelfTask {
    pub scene: String,
    pub object: String,
    /// Approximate centre of the object (a centimetre of error, as a person gives it).
    pub pick: [f64; 3],
    /// The target: footprint centre on the target surface, z at the object's centre.
    pub place: [f64; 3],
    /// `shelf_right`, `shelf_left` or `table`: where the object goes.
    pub target: String,
}

/// A bookshelf facing the robot: centre, yaw, size, and the board the task uses.
struct Shelf {
    name: &'static str,
    center: [f64; 2],
    yaw: f64,
    width: f64,
    height: f64,
    /// Top of the middle board (of two sections).
    board_top: f64,
}

const SHELF_DEPTH: f64 = 0.35;
const BOARD: f64 = 0.02;

impl Shelf {
    /// World xy of a point `depth` m inside the open face, `lateral` m to its side.
    fn inside(&self, depth: f64, lateral: f64) -> [f64; 2] {
        let lx = SHELF_DEPTH / 2.0 - depth;
        let (s, c) = self.yaw.sin_cos();
        [
            self.center[0] + c * lx - s * lateral,
            self.center[1] + s * lx + c * lateral,
        ]
    }
}

/// Golem-III between two bookshelves that face it from the front-left and front-right,
/// with a table in front: shelf angles, distances, sizes and board heights, the table's
/// place and height, the object (a can or a box of graspable size, any yaw) and a second
/// object vary with `seed`. The object stands on a board of one shelf (which one
/// alternates with the seed's parity, so both arms are exercised); it goes to the table
/// or to the other shelf's board. Everything stays within the band Golem-III's arms
/// reach with a side grasp (boards near 1 m, shelves 0.85–1.0 m away).
pub fn golem_shelf_task(seed: u64) -> ShelfTask {
    // SPEC §3's advice for generated scenes: check them with IK. A draw whose pick or
    // place no arm reaches with a side grasp (any approach yaw, level or tilted down,
    // with a pre-grasp) is drawn again; the planner still has to find the motions.
    let golem = tabula_robot::robots::load("golem3").ok();
    let mut draw = 0u64;
    loop {
        let task = draw_shelf_task(seed, draw);
        // Furniture apart, and the target clear of every other piece of furniture.
        let apart = !task.footprints.iter().enumerate().any(|(i, a)| {
            task.footprints[i + 1..]
                .iter()
                .any(|b| footprints_overlap(a, b, 0.03))
        }) && task
            .footprints
            .iter()
            .filter(|f| f.name != task.task.target)
            .all(|f| !f.contains([task.task.place[0], task.task.place[1]], 0.08));
        let reachable = apart
            && golem
                .as_ref()
                .is_none_or(|g| side_grasp_reachable(g, &task));
        if reachable || draw >= 50 {
            return task.task;
        }
        draw += 1;
    }
}

/// A piece of furniture's footprint: centre, yaw, half sizes.
struct Footprint {
    name: String,
    center: [f64; 2],
    yaw: f64,
    half: [f64; 2],
}

impl Footprint {
    fn axes(&self) -> [[f64; 2]; 2] {
        let (s, c) = self.yaw.sin_cos();
        [[c, s], [-s, c]]
    }

    /// Whether `p` is within `margin` of the footprint.
    fn contains(&self, p: [f64; 2], margin: f64) -> bool {
        let d = [p[0] - self.center[0], p[1] - self.center[1]];
        self.axes()
            .iter()
            .zip(self.half)
            .all(|(a, h)| (d[0] * a[0] + d[1] * a[1]).abs() <= h + margin)
    }

    /// Half extent of the footprint projected on unit axis `n`.
    fn radius_along(&self, n: [f64; 2]) -> f64 {
        self.axes()
            .iter()
            .zip(self.half)
            .map(|(a, h)| h * (a[0] * n[0] + a[1] * n[1]).abs())
            .sum()
    }
}

/// Separating-axis test of two rectangles grown by `margin`.
fn footprints_overlap(a: &Footprint, b: &Footprint, margin: f64) -> bool {
    let d = [b.center[0] - a.center[0], b.center[1] - a.center[1]];
    a.axes().iter().chain(b.axes().iter()).all(|n| {
        (d[0] * n[0] + d[1] * n[1]).abs() <= a.radius_along(*n) + b.radius_along(*n) + margin
    })
}

struct Drawn {
    task: ShelfTask,
    footprints: Vec<Footprint>,
    lift: f64,
    /// Tool heights (world) of a side grasp at the pick and at the place.
    pick_grasp_z: f64,
    place_grasp_z: f64,
}

/// Whether one arm has IK for a side grasp and its pre-grasp at both ends.
fn side_grasp_reachable(robot: &tabula_robot::robots::NamedRobot, d: &Drawn) -> bool {
    use tabula_geom::{Pose, Quat, Vec3};
    use tabula_robot::ik::{IkMode, NumericIkParams};
    let reach = |solver: &dyn tabula_robot::ik::IkSolver, xy: [f64; 2], z: f64| {
        let facing = xy[1].atan2(xy[0]);
        (-30..=30).any(|k| {
            let yaw = facing + k as f64 * 0.05;
            [0.0f64, 0.2, 0.4].iter().any(|&tilt| {
                let r = Quat::from_rotation_z(yaw) * Quat::from_rotation_y(tilt);
                let at = Vec3::new(xy[0], xy[1], z - d.lift);
                let approach = r * Vec3::X;
                let ok = |p: Vec3| {
                    solver
                        .solve(&Pose::from_parts(p, r), IkMode::Full, &[0.0; 6])
                        .is_ok()
                };
                ok(at) && (ok(at - approach * 0.1) || ok(at + Vec3::Z * 0.1))
            })
        })
    };
    robot.description.arms.iter().any(|arm| {
        arm.ik_solver(&robot.model, NumericIkParams::default())
            .is_ok_and(|solver| {
                reach(
                    solver.as_ref(),
                    [d.task.pick[0], d.task.pick[1]],
                    d.pick_grasp_z,
                ) && reach(
                    solver.as_ref(),
                    [d.task.place[0], d.task.place[1]],
                    d.place_grasp_z,
                )
            })
    })
}

/// A bookshelf of two sections at `side` (+1 left, −1 right) of the robot, facing it.
fn draw_shelf(name: &'static str, side: f64, rng: &mut ChaCha8Rng) -> Shelf {
    let angle = side * rng.random_range(40f64..58.0).to_radians();
    let distance = rng.random_range(0.92..1.0);
    let board_top = rng.random_range(0.97..1.06);
    // Two sections: the middle board's top is at (h − t)/2 + t, and the top board is
    // far above the head camera, which would see a board at its own height only
    // edge-on (not at all).
    let height = (board_top - BOARD) * 2.0 + BOARD;
    Shelf {
        name,
        center: [distance * angle.cos(), distance * angle.sin()],
        yaw: angle + std::f64::consts::PI,
        width: rng.random_range(0.7..0.9),
        height,
        board_top,
    }
}

/// The object to move: a can or a box.
fn draw_target_shape(rng: &mut ChaCha8Rng) -> Shape {
    if rng.random_bool(0.5) {
        Shape::Cylinder {
            radius: rng.random_range(0.028..0.036),
            height: rng.random_range(0.10..0.14),
        }
    } else {
        Shape::Box([
            rng.random_range(0.04..0.065),
            rng.random_range(0.04..0.065),
            rng.random_range(0.09..0.14),
        ])
    }
}

/// A drawn shelf task's workcell and objects, as the scene file says them.
struct ShelfScene<'a> {
    seed: u64,
    shelves: &'a [Shelf; 2],
    table: ([f64; 2], f64),
    lift: f64,
    /// The target: its shape, position and yaw.
    target: (&'a Shape, [f64; 3], f64),
    /// The other object on the same board: its shape and position.
    other: (&'a Shape, [f64; 3]),
}

impl ShelfScene<'_> {
    fn toml(&self) -> String {
        let (seed, lift) = (self.seed, self.lift);
        let ([tx, ty], table_height) = self.table;
        let (shape, at, yaw) = self.target;
        let (other_shape, other_at) = self.other;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# Generated by tabula_sim::generate::golem_shelf_task({seed}).\n\n[floor]\n"
        );
        for sh in self.shelves {
            let _ = writeln!(
                s,
                "[[furniture]]\nname = \"{}\"\nkind = \"bookshelf\"\npose = {{ xyz = [{:.4}, {:.4}, 0.0], rpy = [0.0, 0.0, {:.4}] }}\nsize = [{SHELF_DEPTH}, {:.4}, {:.4}]\nshelves = 2\n",
                sh.name, sh.center[0], sh.center[1], sh.yaw, sh.width, sh.height
            );
        }
        let _ = writeln!(
            s,
            "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = {{ xyz = [{tx:.4}, {ty:.4}, 0.0] }}\nsize = [0.5, 0.7, {table_height:.4}]\n",
        );
        let _ = writeln!(
            s,
            "[[object]]\nname = \"target\"\nshape = {}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [0.0, 0.0, {yaw:.4}] }}\nmass = 0.3\ncolor = [0.85, 0.15, 0.1]\n",
            shape.toml(),
            at[0],
            at[1],
            at[2]
        );
        let _ = writeln!(
            s,
            "[[object]]\nname = \"other\"\nshape = {}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}] }}\nmass = 0.3\ncolor = [0.1, 0.5, 0.8]\n",
            other_shape.toml(),
            other_at[0],
            other_at[1],
            other_at[2]
        );
        let _ = writeln!(
            s,
            "[[robot]]\nname = \"golem\"\nurdf = \"golem3\"\njoints = {{ torso_lift_joint = {lift:.4}, right_arm_joint4 = 0.3, left_arm_joint4 = 0.3 }}\n\n[[camera]]\nname = \"head\"\nrobot = \"golem\"\nlink = \"head_camera_optical_frame\""
        );
        s
    }

    /// The shelves' and the table's footprints on the floor.
    fn footprints(&self) -> Vec<Footprint> {
        let (table_center, _) = self.table;
        self.shelves
            .iter()
            .map(|sh| Footprint {
                name: sh.name.to_string(),
                center: sh.center,
                yaw: sh.yaw,
                half: [SHELF_DEPTH / 2.0, sh.width / 2.0],
            })
            .chain(std::iter::once(Footprint {
                name: "table".into(),
                center: table_center,
                yaw: 0.0,
                half: [0.25, 0.35],
            }))
            .collect()
    }
}

fn draw_shelf_task(seed: u64, draw: u64) -> Drawn {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5E1F_0001 ^ draw.wrapping_mul(0x9E37_79B9));
    let lift = rng.random_range(-0.08..-0.02);
    let shelves = [
        draw_shelf("shelf_right", -1.0, &mut rng),
        draw_shelf("shelf_left", 1.0, &mut rng),
    ];
    let table_center = [rng.random_range(0.98..1.05), rng.random_range(-0.08..0.08)];
    let table_height = rng.random_range(0.9..0.97);
    let from = (seed % 2) as usize;
    let other = 1 - from;
    let object_shape = draw_target_shape(&mut rng);
    let yaw = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
    let depth = rng.random_range(0.075..0.10);
    let lateral = rng.random_range(-0.08..0.08);
    let source = &shelves[from];
    let at = source.inside(depth, lateral);
    let h = object_shape.height();
    let z = source.board_top + h / 2.0 + 1e-3;
    // A second object on the same board, at least 20 cm to the side.
    let side = if lateral > 0.0 { -1.0 } else { 1.0 };
    let other_at = source.inside(0.12, lateral + side * rng.random_range(0.2..0.26));
    let other_shape = random_shape(&mut rng);
    let to_table = rng.random_bool(0.5);
    let (place_xy, place_surface, target) = if to_table {
        let front = table_center[0] - 0.25;
        (
            [
                front + rng.random_range(0.07..0.11),
                table_center[1] + rng.random_range(-0.15..0.15),
            ],
            table_height,
            "table".to_string(),
        )
    } else {
        let t = &shelves[other];
        (
            t.inside(rng.random_range(0.075..0.10), rng.random_range(-0.08..0.08)),
            t.board_top,
            t.name.to_string(),
        )
    };
    let noise = |rng: &mut ChaCha8Rng| rng.random_range(-0.01..0.01);
    let pick = [
        at[0] + noise(&mut rng),
        at[1] + noise(&mut rng),
        z + noise(&mut rng),
    ];
    let place = [place_xy[0], place_xy[1], place_surface + h / 2.0];
    let scene = ShelfScene {
        seed,
        shelves: &shelves,
        table: (table_center, table_height),
        lift,
        target: (&object_shape, [at[0], at[1], z], yaw),
        other: (
            &other_shape,
            [
                other_at[0],
                other_at[1],
                source.board_top + other_shape.height() / 2.0 + 1e-3,
            ],
        ),
    };
    let grasp_height = (h / 2.0).max(0.035);
    Drawn {
        task: ShelfTask {
            scene: scene.toml(),
            object: "target".into(),
            pick,
            place,
            target,
        },
        footprints: scene.footprints(),
        lift,
        pick_grasp_z: source.board_top + grasp_height,
        place_grasp_z: place_surface + grasp_height,
    }
}
