//! Seeded tabletop scenes (SPEC §3): a table in a room with boxes and cylinders on it,
//! some touching, some stacked, seen by a head-height Kinect-like camera that also sees
//! the floor and a wall. The perception benchmark and its test suite are made of these.

pub mod tidy;
pub use tidy::{TidyTask, tidy_task};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write;

/// What a generated scene contains.
#[derive(Debug, Clone, PartialEq)]
pub struct TabletopLayout {
    /// All objects, pairs included.
    pub objects: usize,
    /// Pairs placed side by side with a 1 mm gap.
    pub touching_pairs: usize,
    /// Pairs with one object resting on the other.
    pub stacked_pairs: usize,
    /// σ = noise_coefficient · z² (m).
    pub noise_coefficient: f64,
    /// Fraction of spurious returns.
    pub outlier_fraction: f64,
    /// Where the camera is; it looks at the table's centre, 0.17 m below the top.
    pub eye: [f64; 3],
}

impl TabletopLayout {
    /// The reference frame: 9 objects, two touching pairs, one stacked pair,
    /// Kinect noise and 0.5 % outliers.
    pub fn nine() -> Self {
        Self {
            objects: 9,
            touching_pairs: 2,
            stacked_pairs: 1,
            noise_coefficient: 0.0015,
            outlier_fraction: 0.005,
            eye: [0.0, 0.0, 1.6],
        }
    }

    /// A random layout with 3–12 objects, up to two touching pairs and one stack.
    pub fn random(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x7AB1_E70F);
        let objects = rng.random_range(3..=12usize);
        let touching_pairs = rng.random_range(0..=(objects / 2).min(2));
        let stacked_pairs = usize::from(objects >= 2 * touching_pairs + 2 && rng.random_bool(0.6));
        // From near the table to far back, where the floor is the biggest plane.
        let eye = [
            rng.random_range(-0.5..0.1),
            rng.random_range(-0.3..0.3),
            rng.random_range(1.4..1.8),
        ];
        Self {
            objects,
            touching_pairs,
            stacked_pairs,
            eye,
            ..Self::nine()
        }
    }
}

/// Table top height and extent (x, y) of the generated table.
pub const TABLE_TOP: f64 = 0.72;
const TABLE_CENTER: [f64; 2] = [0.95, 0.0];
const TABLE_SIZE: [f64; 2] = [0.8, 1.2];

#[derive(Debug, Clone, Copy)]
enum Shape {
    /// Full sizes.
    Box([f64; 3]),
    Cylinder {
        radius: f64,
        height: f64,
    },
}

impl Shape {
    fn height(&self) -> f64 {
        match *self {
            Shape::Box(s) => s[2],
            Shape::Cylinder { height, .. } => height,
        }
    }
    /// Radius of the footprint's bounding circle.
    fn reach(&self) -> f64 {
        match *self {
            Shape::Box(s) => 0.5 * s[0].hypot(s[1]),
            Shape::Cylinder { radius, .. } => radius,
        }
    }
    /// Radius of the bounding sphere about the centre.
    fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Box(s) => 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt(),
            Shape::Cylinder { radius, height } => radius.hypot(height / 2.0),
        }
    }
    /// Half extent along the object's own x axis.
    fn half_x(&self) -> f64 {
        match *self {
            Shape::Box(s) => s[0] / 2.0,
            Shape::Cylinder { radius, .. } => radius,
        }
    }
    /// The same shape made narrow enough, across its narrower side, for a gripper
    /// opening `width` (m).
    fn fit_grip(self, width: Option<f64>) -> Self {
        let Some(w) = width else { return self };
        match self {
            Shape::Box(mut s) => {
                let k = usize::from(s[1] < s[0]);
                s[k] = s[k].min(w);
                Shape::Box(s)
            }
            Shape::Cylinder { radius, height } => Shape::Cylinder {
                radius: radius.min(w / 2.0),
                height,
            },
        }
    }
    fn toml(&self) -> String {
        match *self {
            Shape::Box(s) => format!("{{ box = [{:.4}, {:.4}, {:.4}] }}", s[0], s[1], s[2]),
            Shape::Cylinder { radius, height } => {
                format!("{{ cylinder = {{ radius = {radius:.4}, height = {height:.4} }} }}")
            }
        }
    }
}

/// Graspable sizes (seed 002's gripper holds 3–7 cm).
fn random_shape(rng: &mut ChaCha8Rng) -> Shape {
    if rng.random_bool(0.6) {
        Shape::Box([
            rng.random_range(0.035..0.07),
            rng.random_range(0.035..0.09),
            rng.random_range(0.04..0.13),
        ])
    } else {
        Shape::Cylinder {
            radius: rng.random_range(0.018..0.035),
            height: rng.random_range(0.05..0.15),
        }
    }
}

struct Placed {
    shape: Shape,
    xyz: [f64; 3],
    rpy: [f64; 3],
}

impl Placed {
    fn upright(shape: Shape, xyz: [f64; 3], yaw: f64) -> Self {
        Self {
            shape,
            xyz,
            rpy: [0.0, 0.0, yaw],
        }
    }
}

/// A scene file (TOML) for `layout`, placed by `seed`; same inputs, same text.
pub fn tabletop_scene(seed: u64, layout: &TabletopLayout) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let placed = place_groups(
        &mut rng,
        layout,
        TABLE_CENTER,
        [TABLE_SIZE[0] / 2.0 - 0.1, TABLE_SIZE[1] / 2.0 - 0.1],
        TABLE_TOP,
        0.03,
        None,
    );
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Generated by tabula_sim::generate::tabletop_scene(seed = {seed}, {layout:?})\n"
    );
    let _ = writeln!(s, "[floor]\nsize = [8.0, 8.0]\n");
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = {{ xyz = [{}, {}, 0.0] }}\nsize = [{}, {}, {TABLE_TOP}]\n",
        TABLE_CENTER[0], TABLE_CENTER[1], TABLE_SIZE[0], TABLE_SIZE[1]
    );
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"wall\"\nkind = \"wall\"\npose = {{ xyz = [2.4, 0.0, 0.0] }}\nsize = [0.1, 5.0, 2.5]\n"
    );
    write_objects(&mut s, &mut rng, &placed);
    let _ = writeln!(
        s,
        "[[camera]]\nname = \"head\"\nlook_at = {{ eye = [{:.3}, {:.3}, {:.3}], target = [{}, {}, {}] }}\nnoise_coefficient = {}\noutlier_fraction = {}",
        layout.eye[0],
        layout.eye[1],
        layout.eye[2],
        TABLE_CENTER[0],
        TABLE_CENTER[1],
        TABLE_TOP - 0.17,
        layout.noise_coefficient,
        layout.outlier_fraction
    );
    s
}

/// Objects as `[[object]]` tables named `object0`, `object1`, … with random colours.
fn write_objects(s: &mut String, rng: &mut ChaCha8Rng, placed: &[Placed]) {
    for (i, p) in placed.iter().enumerate() {
        let color = [
            rng.random_range(0.2..0.95),
            rng.random_range(0.2..0.95),
            rng.random_range(0.2..0.95),
        ];
        let _ = writeln!(
            s,
            "[[object]]\nname = \"object{i}\"\nshape = {}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [{:.4}, {:.4}, {:.4}] }}\ndensity = 400.0\ncolor = [{:.2}, {:.2}, {:.2}]\n",
            p.shape.toml(),
            p.xyz[0],
            p.xyz[1],
            p.xyz[2],
            p.rpy[0],
            p.rpy[1],
            p.rpy[2],
            color[0],
            color[1],
            color[2]
        );
    }
}

/// Singles, touching pairs (1 mm apart) and stacked pairs of `layout`, by rejection
/// sampling inside the rectangle `center ± half` on a surface at height `top`, groups at
/// least `gap` apart.
#[allow(clippy::too_many_arguments)]
fn place_groups(
    rng: &mut ChaCha8Rng,
    layout: &TabletopLayout,
    center: [f64; 2],
    half: [f64; 2],
    top: f64,
    gap: f64,
    grip: Option<f64>,
) -> Vec<Placed> {
    let mut placed: Vec<Placed> = Vec::new();
    // Footprints (centre, radius) already taken.
    let mut taken: Vec<([f64; 2], f64)> = Vec::new();
    let singles = layout
        .objects
        .saturating_sub(2 * (layout.touching_pairs + layout.stacked_pairs));
    let groups = (0..layout.touching_pairs)
        .map(|_| 1u8)
        .chain((0..layout.stacked_pairs).map(|_| 2u8))
        .chain((0..singles).map(|_| 0u8));
    for kind in groups {
        for _attempt in 0..200 {
            let yaw: f64 = rng.random_range(-1.5..1.5);
            let (dx, dy) = (yaw.cos(), yaw.sin());
            let mut parts: Vec<Placed> = Vec::new();
            match kind {
                0 => parts.push(Placed::upright(
                    random_shape(rng).fit_grip(grip),
                    [0.0; 3],
                    yaw,
                )),
                1 => {
                    let a = Shape::Box([
                        rng.random_range(0.035..0.07),
                        rng.random_range(0.04..0.09),
                        rng.random_range(0.04..0.13),
                    ])
                    .fit_grip(grip);
                    let b = random_shape(rng).fit_grip(grip);
                    let d = a.half_x() + b.half_x() + 0.001;
                    parts.push(Placed::upright(a, [-d / 2.0 * dx, -d / 2.0 * dy, 0.0], yaw));
                    parts.push(Placed::upright(b, [d / 2.0 * dx, d / 2.0 * dy, 0.0], yaw));
                }
                _ => {
                    let base = Shape::Box([
                        rng.random_range(0.06..0.08),
                        rng.random_range(0.06..0.09),
                        rng.random_range(0.04..0.09),
                    ])
                    .fit_grip(grip);
                    let top = if rng.random_bool(0.5) {
                        Shape::Box([
                            rng.random_range(0.035..0.05),
                            rng.random_range(0.035..0.05),
                            rng.random_range(0.03..0.08),
                        ])
                    } else {
                        Shape::Cylinder {
                            radius: rng.random_range(0.018..0.025),
                            height: rng.random_range(0.04..0.1),
                        }
                    };
                    let top_yaw = yaw + rng.random_range(-0.5..0.5);
                    parts.push(Placed::upright(base, [0.0; 3], yaw));
                    parts.push(Placed::upright(top, [0.0, 0.0, base.height()], top_yaw));
                }
            }
            let reach = parts
                .iter()
                .map(|p| p.xyz[0].hypot(p.xyz[1]) + p.shape.reach())
                .fold(0.0, f64::max);
            let c = [
                center[0] + rng.random_range(-1.0..1.0) * (half[0] - reach).max(0.0),
                center[1] + rng.random_range(-1.0..1.0) * (half[1] - reach).max(0.0),
            ];
            let free = taken
                .iter()
                .all(|(t, r)| (t[0] - c[0]).hypot(t[1] - c[1]) > r + reach + gap);
            if free {
                taken.push((c, reach));
                for mut p in parts {
                    p.xyz[0] += c[0];
                    p.xyz[1] += c[1];
                    p.xyz[2] += top + p.shape.height() / 2.0 + 0.001;
                    placed.push(p);
                }
                break;
            }
        }
    }
    placed
}

/// A generated scene, settled by physics, and one frame of its camera.
pub struct GeneratedFrame {
    pub scene_toml: String,
    pub frame: crate::camera::DepthFrame,
    /// Label of the table's pixels.
    pub table_label: u32,
    /// Each object's name and label.
    pub object_labels: Vec<(String, u32)>,
    /// The settled world the frame shows.
    pub world: crate::SimWorld,
}

/// Builds, settles and photographs the scene of `tabletop_scene(seed, layout)`.
pub fn tabletop_frame(
    seed: u64,
    layout: &TabletopLayout,
) -> Result<GeneratedFrame, crate::SimError> {
    let scene_toml = tabletop_scene(seed, layout);
    let scene = crate::Scene::parse(&scene_toml, "generated")?;
    let mut world = crate::SimWorld::from_scene(&scene, crate::PhysicsParams::default())?;
    world.settle();
    let camera = crate::Camera::from_spec(&scene.cameras[0], &world)?;
    let frame = crate::camera::capture(&world, &camera, seed);
    let label = |name: &str| world.entity(name).map_or(0, |e| e as u32 + 1);
    let object_labels = world
        .object_poses()
        .into_iter()
        .map(|(n, _)| {
            let l = label(&n);
            (n, l)
        })
        .collect();
    Ok(GeneratedFrame {
        table_label: label("table"),
        object_labels,
        scene_toml,
        frame,
        world,
    })
}

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

fn draw_shelf_task(seed: u64, draw: u64) -> Drawn {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5E1F_0001 ^ draw.wrapping_mul(0x9E37_79B9));
    let lift = rng.random_range(-0.08..-0.02);
    let shelf = |name: &'static str, side: f64, rng: &mut ChaCha8Rng| {
        let angle = side * rng.random_range(40f64..58.0).to_radians();
        let distance = rng.random_range(0.92..1.0);
        let board_top = rng.random_range(0.97..1.06);
        // Two sections: the middle board's top is at (h − t)/2 + t, and the top board
        // is far above the head camera, which would see a board at its own height only
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
    };
    let shelves = [
        shelf("shelf_right", -1.0, &mut rng),
        shelf("shelf_left", 1.0, &mut rng),
    ];
    let table_center = [rng.random_range(0.98..1.05), rng.random_range(-0.08..0.08)];
    let table_height = rng.random_range(0.9..0.97);
    let from = (seed % 2) as usize;
    let other = 1 - from;
    let object_shape = if rng.random_bool(0.5) {
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
    };
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

    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Generated by tabula_sim::generate::golem_shelf_task({seed}).\n\n[floor]\n"
    );
    for sh in &shelves {
        let _ = writeln!(
            s,
            "[[furniture]]\nname = \"{}\"\nkind = \"bookshelf\"\npose = {{ xyz = [{:.4}, {:.4}, 0.0], rpy = [0.0, 0.0, {:.4}] }}\nsize = [{SHELF_DEPTH}, {:.4}, {:.4}]\nshelves = 2\n",
            sh.name, sh.center[0], sh.center[1], sh.yaw, sh.width, sh.height
        );
    }
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = {{ xyz = [{:.4}, {:.4}, 0.0] }}\nsize = [0.5, 0.7, {table_height:.4}]\n",
        table_center[0], table_center[1]
    );
    let _ = writeln!(
        s,
        "[[object]]\nname = \"target\"\nshape = {}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [0.0, 0.0, {yaw:.4}] }}\nmass = 0.3\ncolor = [0.85, 0.15, 0.1]\n",
        object_shape.toml(),
        at[0],
        at[1],
        z
    );
    let _ = writeln!(
        s,
        "[[object]]\nname = \"other\"\nshape = {}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}] }}\nmass = 0.3\ncolor = [0.1, 0.5, 0.8]\n",
        other_shape.toml(),
        other_at[0],
        other_at[1],
        source.board_top + other_shape.height() / 2.0 + 1e-3
    );
    let _ = writeln!(
        s,
        "[[robot]]\nname = \"golem\"\nurdf = \"golem3\"\njoints = {{ torso_lift_joint = {lift:.4}, right_arm_joint4 = 0.3, left_arm_joint4 = 0.3 }}\n\n[[camera]]\nname = \"head\"\nrobot = \"golem\"\nlink = \"head_camera_optical_frame\""
    );
    let grasp_height = (h / 2.0).max(0.035);
    Drawn {
        task: ShelfTask {
            scene: s,
            object: "target".into(),
            pick,
            place,
            target,
        },
        footprints: shelves
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
            .collect(),
        lift,
        pick_grasp_z: source.board_top + grasp_height,
        place_grasp_z: place_surface + grasp_height,
    }
}

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
}

impl std::str::FromStr for ClearSuite {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "seed" => Ok(Self::Seed),
            "random" => Ok(Self::Random),
            "packed" => Ok(Self::Packed),
            "pile" => Ok(Self::Pile),
            other => Err(format!(
                "unknown suite `{other}`: seed, random, packed or pile"
            )),
        }
    }
}

/// The clearing cell: table centre and size, the region objects are put in (every point
/// of it reachable from above by the WAM on its stand), the bin.
pub const CLEAR_TABLE_CENTER: [f64; 2] = [0.62, 0.0];
const CLEAR_TABLE_SIZE: [f64; 2] = [0.7, 1.0];
const CLEAR_REGION_CENTER: [f64; 2] = [0.58, 0.0];
const CLEAR_REGION_HALF: [f64; 2] = [0.17, 0.25];
/// Widest object across its narrower side: seed 002's gripper opens 7 cm.
const CLEAR_GRIP: f64 = 0.06;

/// A clearing scene of `suite` drawn by `seed` (TOML; same inputs, same text): the WAM
/// on a stand beside a table, the bin beside it, an overhead camera, the objects.
pub fn clearing_scene(suite: ClearSuite, seed: u64) -> String {
    if suite == ClearSuite::Seed {
        return include_str!("../../../../scenes/clutter.toml").to_string();
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xC1EA_7AB1);
    let placed = match suite {
        ClearSuite::Random => {
            let objects = rng.random_range(3..=12usize);
            let layout = TabletopLayout {
                objects,
                touching_pairs: rng.random_range(0..=(objects / 2).min(2)),
                stacked_pairs: usize::from(objects >= 4 && rng.random_bool(0.6)),
                ..TabletopLayout::nine()
            };
            place_groups(
                &mut rng,
                &layout,
                CLEAR_REGION_CENTER,
                CLEAR_REGION_HALF,
                TABLE_TOP,
                0.03,
                Some(CLEAR_GRIP),
            )
        }
        ClearSuite::Packed => packed_grid(&mut rng),
        _ => pile(&mut rng),
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
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"stand\"\nkind = \"table\"\nsize = [0.3, 0.3, 0.6]\n\n[[furniture]]\nname = \"bin\"\nkind = \"bin\"\npose = {{ xyz = [0.0, 0.6, 0.0] }}\nsize = [0.4, 0.4, 0.45]\n"
    );
    write_objects(&mut s, &mut rng, &placed);
    let _ = writeln!(
        s,
        "[[robot]]\nname = \"wam\"\nurdf = \"wam\"\npose = {{ xyz = [0.0, 0.0, 0.6] }}\njoints = {{ wam_joint2 = -1.9, wam_joint4 = 2.6 }}\n\n[[camera]]\nname = \"overhead\"\nlook_at = {{ eye = [{0}, {1}, 1.75], target = [{0}, {1}, {TABLE_TOP}] }}",
        CLEAR_TABLE_CENTER[0], CLEAR_TABLE_CENTER[1]
    );
    if suite == ClearSuite::Pile {
        return settle_pile(&s, &mut rng).unwrap_or(s);
    }
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

/// Where the surface stands relative to the robot in a placing task.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaceLayout {
    Front,
    Side,
    Behind,
    Far,
}

/// A generated placing task (seed 000): a PR2 holding an object in one gripper, a
/// table somewhere around it, maybe cluttered.
#[derive(Debug, Clone)]
pub struct PlaceTask {
    pub scene: String,
    /// The held object's catalogue name (`cube`, `mug`, …).
    pub object: String,
    pub simple: bool,
    pub layout: PlaceLayout,
    pub clutter: usize,
    pub arm: String,
    /// The table's centre (x, y), size (m) and yaw (rad) in the world.
    pub table_center: [f64; 2],
    pub table_size: [f64; 3],
    pub table_yaw: f64,
}

/// The placing suite's task `seed`: simple objects (cubes, boxes, cylinders of several
/// sizes, as primitives) or complex ones (the catalogue's meshes, written into
/// `mesh_dir` once and scaled), held in an odd grip (any angle about the closing axis,
/// the palm against the object's back), with a table in front, to a side, behind or far
/// away, cluttered half of the time. Same seed, same task.
pub fn place_task(
    seed: u64,
    simple: bool,
    mesh_dir: &std::path::Path,
) -> std::io::Result<PlaceTask> {
    use crate::objects::{ObjectMesh, catalogue, cuboid, lathe};
    use tabula_geom::Vec3;
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ if simple { 0x5117 } else { 0xC0A7 });
    // ---- The object: its shape line in the scene and its mesh (object frame).
    let (name, shape_toml, mesh): (String, String, ObjectMesh) = if simple {
        match rng.random_range(0..3) {
            0 => {
                let a = rng.random_range(0.04..0.07);
                let m = ObjectMesh::from_parts(
                    "cube",
                    true,
                    cuboid(Vec3::splat(-a / 2.0), Vec3::splat(a)),
                );
                (
                    "cube".into(),
                    format!("{{ box = [{a:.4}, {a:.4}, {a:.4}] }}"),
                    m,
                )
            }
            1 => {
                let s = [
                    rng.random_range(0.04..0.07),
                    rng.random_range(0.05..0.16),
                    rng.random_range(0.03..0.15),
                ];
                let m = ObjectMesh::from_parts(
                    "box",
                    true,
                    cuboid(-Vec3::from_array(s) / 2.0, Vec3::from_array(s)),
                );
                (
                    "box".into(),
                    format!("{{ box = [{:.4}, {:.4}, {:.4}] }}", s[0], s[1], s[2]),
                    m,
                )
            }
            _ => {
                let (r, h) = (rng.random_range(0.02..0.036), rng.random_range(0.05..0.16));
                let m = ObjectMesh::from_parts(
                    "cylinder",
                    true,
                    lathe(
                        &[(0.0, -h / 2.0), (r, -h / 2.0), (r, h / 2.0), (0.0, h / 2.0)],
                        32,
                    ),
                );
                (
                    "cylinder".into(),
                    format!("{{ cylinder = {{ radius = {r:.4}, height = {h:.4} }} }}"),
                    m,
                )
            }
        }
    } else {
        let complex: Vec<ObjectMesh> = catalogue().into_iter().filter(|o| !o.simple).collect();
        let o = complex[rng.random_range(0..complex.len())].clone();
        std::fs::create_dir_all(mesh_dir)?;
        let path = mesh_dir.join(format!("{}.obj", o.name));
        if !path.exists() {
            std::fs::write(&path, o.to_obj())?;
        }
        // Scaled so that a horizontal side fits the PR2's 9 cm opening: it can be
        // taken from above or the side, as it was picked up from a table.
        let (lo, hi) = tabula_geom::bounds(&o.vertices);
        let fit = 0.075 / (hi.x - lo.x).min(hi.y - lo.y).max(1e-3);
        let scale = rng.random_range(0.85..1.15f64).min(fit);
        let scaled = ObjectMesh::from_parts(
            &o.name,
            false,
            (
                o.vertices.iter().map(|v| *v * scale).collect(),
                o.triangles.clone(),
            ),
        );
        (
            o.name.clone(),
            format!(
                "{{ mesh = {{ path = \"{}\", scale = [{scale:.4}, {scale:.4}, {scale:.4}] }} }}",
                path.display()
            ),
            scaled,
        )
    };
    // ---- The grip: fingers closing along an object axis narrow enough, the approach
    // at any angle about it, the palm against the object's back.
    let (lo, hi) = tabula_geom::bounds(&mesh.vertices);
    let extent = hi - lo;
    let axes: Vec<Vec3> = [Vec3::X, Vec3::Y, Vec3::Z]
        .into_iter()
        .zip(extent.to_array())
        .filter(|(_, e)| *e <= 0.078)
        .map(|(a, _)| a)
        .collect();
    let axes = if axes.is_empty() { vec![Vec3::Z] } else { axes };
    // Candidates until the fingers, closing through the tool point, meet material on
    // both sides (an L's or a mug's bounding-box centre may be empty air), with the hand
    // above the object's base: it was picked up from a table, so the hand came from
    // above or the side, never from under it.
    let gripper = tabula_robot::robots::load("pr2")
        .ok()
        .and_then(|r| r.description.grippers.first().cloned());
    // The fingers: the part of the hand reaching furthest forward (tool frame, x the
    // approach): their span along the approach and their half height.
    let fingers = gripper.as_ref().and_then(|g| {
        g.self_filter_boxes
            .iter()
            .max_by(|a, b| {
                (a.center[0] + a.size[0] / 2.0).total_cmp(&(b.center[0] + b.size[0] / 2.0))
            })
            .map(|b| {
                (
                    b.center[0] - b.size[0] / 2.0,
                    b.center[0] + b.size[0] / 2.0,
                    b.size[2] / 2.0,
                )
            })
    });
    // The mesh's surface, sampled: where the fingers meet it.
    let surface: Vec<Vec3> = mesh
        .triangles
        .iter()
        .flat_map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            (0..=8).flat_map(move |i| {
                (0..=8 - i).map(move |j| {
                    let (s, t) = (i as f64 / 8.0, j as f64 / 8.0);
                    a + (b - a) * s + (c - a) * t
                })
            })
        })
        .collect();
    let hand: Vec<Vec3> = gripper
        .map(|g| {
            g.self_filter_boxes
                .iter()
                .flat_map(|b| {
                    (0..8).map(move |i| {
                        Vec3::from_array(b.center)
                            + Vec3::from_array(b.size) / 2.0
                                * Vec3::new(
                                    if i & 1 == 0 { -1.0 } else { 1.0 },
                                    if i & 2 == 0 { -1.0 } else { 1.0 },
                                    if i & 4 == 0 { -1.0 } else { 1.0 },
                                )
                    })
                })
                .collect()
        })
        .unwrap_or_default();
    let mut grip = None;
    for attempt in 0..400 {
        let closing = axes[rng.random_range(0..axes.len())];
        let (u, v) = (
            closing.any_orthonormal_vector(),
            closing.cross(closing.any_orthonormal_vector()),
        );
        let theta = rng.random_range(0.0..std::f64::consts::TAU);
        let approach = u * theta.cos() + v * theta.sin();
        let mut origin = if attempt == 0 {
            (lo + hi) / 2.0
        } else {
            lo + extent
                * Vec3::new(
                    rng.random_range(0.2..0.8),
                    rng.random_range(0.2..0.8),
                    rng.random_range(0.2..0.8),
                )
        };
        let reach = |origin: Vec3, d: Vec3| {
            mesh.vertices
                .iter()
                .map(|p| (*p - origin).dot(d))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let behind = reach(origin, -approach);
        if behind > 0.035 {
            origin -= approach * (behind - 0.035);
        }
        // Seated on the finger pads: the object reaches past the fingertips (2.25 cm
        // beyond the tool frame on a PR2) where it can, as a closed grasp holds it.
        let front = reach(origin, approach);
        let third = approach.cross(closing);
        // Centred between the fingers, as closing parallel fingers push it: the middle
        // of what lies between the pads along the closing axis (else one finger would
        // close into the object until the other touched).
        let centred = |o: Vec3| -> Vec3 {
            let Some((back, tip, half)) = fingers else {
                return o;
            };
            let (lo, hi) = surface
                .iter()
                .filter(|p| {
                    let d = **p - o;
                    (back..=tip).contains(&d.dot(approach)) && d.dot(third).abs() <= half
                })
                .map(|p| (*p - o).dot(closing))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                    (a.min(c), b.max(c))
                });
            if lo.is_finite() && hi.is_finite() {
                o + closing * (lo + hi) / 2.0
            } else {
                o
            }
        };
        let (origin, seated) = (
            centred(origin),
            centred(origin + approach * (front - 0.03).min(0.0)),
        );
        let rotation = tabula_geom::Mat3::from_cols(approach, closing, third);
        // The hand clear of the table the object stood on (a flat box taken from above
        // cannot also be seated deep on the pads: then it is held nearer the tips).
        let clear = |o: Vec3| hand.iter().all(|h| (o + rotation * *h).z >= lo.z + 0.004);
        let chosen = [seated, origin]
            .into_iter()
            .find(|o| clear(*o) && ray_hits(&mesh, *o, closing) && ray_hits(&mesh, *o, -closing));
        if let Some(o) = chosen {
            grip = Some((o, approach, closing));
            break;
        }
    }
    // Never seen in the suite; a plain grip from the side if nothing else was found.
    let (origin, approach, closing) = grip.unwrap_or((
        (lo + hi) / 2.0,
        Vec3::Z.cross(axes[0]).normalize_or(Vec3::X),
        axes[0],
    ));
    let object_from_tool = tabula_geom::Pose::from_parts(
        origin,
        tabula_geom::Quat::from_mat3(&tabula_geom::Mat3::from_cols(
            approach,
            closing,
            approach.cross(closing),
        )),
    );
    let tool_from_object = object_from_tool.inverse();
    let rpy = tabula_geom::rpy_from_quat(tool_from_object.rotation);
    let t = tool_from_object.translation;
    // ---- The arm holding it, the other one out to the side.
    let right = rng.random_bool(0.5);
    let (arm, side) = if right { ("right", 'r') } else { ("left", 'l') };
    let other = if right { 'l' } else { 'r' };
    let sign = if right { 1.0 } else { -1.0 };
    // ---- The table.
    let layout = match rng.random_range(0..4) {
        0 => PlaceLayout::Front,
        1 => PlaceLayout::Side,
        2 => PlaceLayout::Behind,
        _ => PlaceLayout::Far,
    };
    let size = [
        rng.random_range(0.5..0.9),
        rng.random_range(0.7..1.4),
        rng.random_range(0.6..0.9),
    ];
    let yaw_jitter = rng.random_range(-0.35..0.35);
    let (center, yaw) = match layout {
        PlaceLayout::Front => (
            [
                0.85 + size[0] / 2.0 + rng.random_range(0.0..0.6),
                rng.random_range(-0.4..0.4),
            ],
            yaw_jitter,
        ),
        PlaceLayout::Side => {
            let s = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            (
                [
                    rng.random_range(-0.3..0.5),
                    s * (0.75 + size[0] / 2.0 + rng.random_range(0.0..0.6)),
                ],
                std::f64::consts::FRAC_PI_2 + yaw_jitter,
            )
        }
        PlaceLayout::Behind => (
            [
                -(0.75 + size[0] / 2.0 + rng.random_range(0.0..0.6)),
                rng.random_range(-0.4..0.4),
            ],
            yaw_jitter,
        ),
        PlaceLayout::Far => (
            [
                2.3 + size[0] / 2.0 + rng.random_range(0.0..0.5),
                rng.random_range(-0.5..0.5),
            ],
            yaw_jitter,
        ),
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Generated by tabula_sim::generate::place_task(seed = {seed}, simple = {simple}): {name} in the {arm} gripper, table {layout:?}\n"
    );
    let _ = writeln!(s, "[floor]\nsize = [10.0, 10.0]\n");
    let _ = writeln!(
        s,
        "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = {{ xyz = [{:.3}, {:.3}, 0.0], rpy = [0.0, 0.0, {yaw:.4}] }}\nsize = [{:.3}, {:.3}, {:.3}]\n",
        center[0], center[1], size[0], size[1], size[2]
    );
    // Clutter half of the time: a few objects standing on the table.
    let clutter = if rng.random_bool(0.5) {
        rng.random_range(2..7)
    } else {
        0
    };
    let mut placed: Vec<([f64; 2], f64)> = Vec::new();
    for _ in 0..clutter * 20 {
        if placed.len() >= clutter {
            break;
        }
        let shape = random_shape(&mut rng);
        let r = shape.reach();
        let local = [
            rng.random_range(-(size[0] / 2.0 - r - 0.03)..(size[0] / 2.0 - r - 0.03)),
            rng.random_range(-(size[1] / 2.0 - r - 0.03)..(size[1] / 2.0 - r - 0.03)),
        ];
        let (sy, cy) = yaw.sin_cos();
        let xy = [
            center[0] + cy * local[0] - sy * local[1],
            center[1] + sy * local[0] + cy * local[1],
        ];
        if placed
            .iter()
            .any(|(p, pr)| ((p[0] - xy[0]).powi(2) + (p[1] - xy[1]).powi(2)).sqrt() < r + pr + 0.12)
        {
            continue;
        }
        let i = placed.len();
        placed.push((xy, r));
        let _ = writeln!(
            s,
            "[[object]]\nname = \"clutter{i}\"\nshape = {}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [0.0, 0.0, {:.3}] }}\ndensity = 400.0\ncolor = [0.3, 0.5, 0.8]\n",
            shape.toml(),
            xy[0],
            xy[1],
            size[2] + shape.height() / 2.0,
            rng.random_range(0.0..3.0)
        );
    }
    let _ = writeln!(
        s,
        "[[object]]\nname = \"held\"\nshape = {shape_toml}\npose = {{ xyz = [0.5, 0.0, 1.0] }}\ndensity = 500.0\ncolor = [0.9, 0.6, 0.2]\n"
    );
    let _ = writeln!(
        s,
        "[[robot]]\nname = \"pr2\"\nurdf = \"pr2\"\njoints = {{ torso_lift_joint = 0.2, head_tilt_joint = 0.5, {side}_shoulder_pan_joint = {:.2}, {side}_shoulder_lift_joint = 0.2, {side}_elbow_flex_joint = -1.0, {side}_wrist_flex_joint = -0.6, {other}_shoulder_pan_joint = {:.2}, {other}_elbow_flex_joint = -2.0, {other}_wrist_flex_joint = -0.5 }}\nhold = {{ object = \"held\", tool_link = \"{side}_gripper_tool_frame\", finger_joint = \"{side}_gripper_l_finger_joint\", fingers = [\"{side}_gripper_l_finger_link\", \"{side}_gripper_r_finger_link\"], palm = \"{side}_gripper_palm_link\", tool_from_object = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [{:.4}, {:.4}, {:.4}] }} }}\n",
        -0.3 * sign,
        1.5 * sign,
        t.x,
        t.y,
        t.z,
        rpy[0],
        rpy[1],
        rpy[2]
    );
    let _ = writeln!(
        s,
        "[[camera]]\nname = \"head\"\nrobot = \"pr2\"\nlink = \"head_camera_optical_frame\"\n"
    );
    Ok(PlaceTask {
        scene: s,
        object: name,
        simple,
        layout,
        clutter: placed.len(),
        arm: arm.into(),
        table_center: center,
        table_size: size,
        table_yaw: yaw,
    })
}

/// The placing suite's task `seed` with a simple object, in a room: walls all round and
/// three things a surface search must not take for a surface — ramps (a 60° face),
/// traffic cones, sign drums (a tapered top) — anywhere off the robot's way to the
/// table (SPEC §1.3's rejections, as in `scenes/surfaces.toml`). Same seed, same room.
pub fn room_task(seed: u64, mesh_dir: &std::path::Path) -> std::io::Result<PlaceTask> {
    let mut task = place_task(seed, true, mesh_dir)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x200A);
    let s = &mut task.scene;
    let (x0, x1, half_width): (f64, f64, f64) = (-2.9, 4.3, 3.0);
    for (name, xy, size) in [
        ("wall_front", [x1, 0.0], [0.1, 2.0 * half_width, 2.5]),
        ("wall_back", [x0, 0.0], [0.1, 2.0 * half_width, 2.5]),
        (
            "wall_left",
            [(x0 + x1) / 2.0, half_width],
            [x1 - x0, 0.1, 2.5],
        ),
        (
            "wall_right",
            [(x0 + x1) / 2.0, -half_width],
            [x1 - x0, 0.1, 2.5],
        ),
    ] {
        let _ = writeln!(
            s,
            "[[furniture]]\nname = \"{name}\"\nkind = \"wall\"\npose = {{ xyz = [{:.3}, {:.3}, 0.0] }}\nsize = [{:.3}, {:.3}, {:.3}]\n",
            xy[0], xy[1], size[0], size[1], size[2]
        );
    }
    let [tx, ty] = task.table_center;
    let table_reach = 0.5 * (task.table_size[0].hypot(task.table_size[1])) + 0.5;
    // Distance from (x, y) to the robot's way to the table (the segment origin → table).
    let off_way = |x: f64, y: f64| {
        let len2 = tx * tx + ty * ty;
        let t = ((x * tx + y * ty) / len2.max(1e-9)).clamp(0.0, 1.0);
        (x - t * tx).hypot(y - t * ty)
    };
    let mut placed: Vec<[f64; 2]> = Vec::new();
    for attempt in 0..400 {
        if placed.len() >= 3 {
            break;
        }
        let (x, y): (f64, f64) = (
            rng.random_range(x0 + 0.5..x1 - 0.5),
            rng.random_range(-half_width + 0.5..half_width - 0.5),
        );
        if x.hypot(y) < 1.3
            || (x - tx).hypot(y - ty) < table_reach
            || off_way(x, y) < 0.8
            || placed.iter().any(|p| (p[0] - x).hypot(p[1] - y) < 0.8)
        {
            continue;
        }
        let kind = ["ramp", "traffic_cone", "sign_drum"][placed.len() % 3];
        let extra = if kind == "ramp" {
            "size = [0.4, 0.6, 0.1]\nangle_deg = 120.0\n"
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "[[furniture]]\nname = \"{kind}_{attempt}\"\nkind = \"{kind}\"\npose = {{ xyz = [{x:.3}, {y:.3}, 0.0], rpy = [0.0, 0.0, {:.3}] }}\n{extra}",
            rng.random_range(0.0..std::f64::consts::TAU)
        );
        placed.push([x, y]);
    }
    Ok(task)
}

/// Whether the ray from `o` along `d` crosses a triangle of the mesh (Möller–Trumbore).
fn ray_hits(mesh: &crate::objects::ObjectMesh, o: tabula_geom::Vec3, d: tabula_geom::Vec3) -> bool {
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            return false;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
