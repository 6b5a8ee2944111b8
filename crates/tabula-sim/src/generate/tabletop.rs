//! Seeded tabletop scenes and their frames (SPEC §3): boxes and cylinders on a table,
//! some touching, some stacked.

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
pub(super) const TABLE_CENTER: [f64; 2] = [0.95, 0.0];
pub(super) const TABLE_SIZE: [f64; 2] = [0.8, 1.2];

#[derive(Debug, Clone, Copy)]
pub(super) enum Shape {
    /// Full sizes.
    Box([f64; 3]),
    Cylinder {
        radius: f64,
        height: f64,
    },
}

impl Shape {
    pub(super) fn height(&self) -> f64 {
        match *self {
            Shape::Box(s) => s[2],
            Shape::Cylinder { height, .. } => height,
        }
    }
    /// Radius of the footprint's bounding circle.
    pub(super) fn reach(&self) -> f64 {
        match *self {
            Shape::Box(s) => 0.5 * s[0].hypot(s[1]),
            Shape::Cylinder { radius, .. } => radius,
        }
    }
    /// Radius of the bounding sphere about the centre.
    pub(super) fn bounding_radius(&self) -> f64 {
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
    pub(super) fn fit_grip(self, width: Option<f64>) -> Self {
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
    pub(super) fn toml(&self) -> String {
        match *self {
            Shape::Box(s) => format!("{{ box = [{:.4}, {:.4}, {:.4}] }}", s[0], s[1], s[2]),
            Shape::Cylinder { radius, height } => {
                format!("{{ cylinder = {{ radius = {radius:.4}, height = {height:.4} }} }}")
            }
        }
    }
}

/// Graspable sizes (seed 002's gripper holds 3–7 cm).
pub(super) fn random_shape(rng: &mut ChaCha8Rng) -> Shape {
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

pub(super) struct Placed {
    pub(super) shape: Shape,
    pub(super) xyz: [f64; 3],
    pub(super) rpy: [f64; 3],
}

impl Placed {
    pub(super) fn upright(shape: Shape, xyz: [f64; 3], yaw: f64) -> Self {
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
    let region = Region {
        center: TABLE_CENTER,
        half: [TABLE_SIZE[0] / 2.0 - 0.1, TABLE_SIZE[1] / 2.0 - 0.1],
        top: TABLE_TOP,
        gap: 0.03,
        grip: None,
    };
    let placed = place_groups(&mut rng, layout, &region);
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
pub(super) fn write_objects(s: &mut String, rng: &mut ChaCha8Rng, placed: &[Placed]) {
    for (i, p) in placed.iter().enumerate() {
        write_object(s, rng, i, &p.shape.toml(), (p.xyz, p.rpy));
    }
}

/// One `[[object]]` entry named `object{i}`, of shape `shape` (TOML), at `(xyz, rpy)`,
/// in a colour drawn from `rng`.
pub(super) fn write_object(
    s: &mut String,
    rng: &mut ChaCha8Rng,
    i: usize,
    shape: &str,
    (xyz, rpy): ([f64; 3], [f64; 3]),
) {
    let color = [
        rng.random_range(0.2..0.95),
        rng.random_range(0.2..0.95),
        rng.random_range(0.2..0.95),
    ];
    let _ = writeln!(
        s,
        "[[object]]\nname = \"object{i}\"\nshape = {shape}\npose = {{ xyz = [{:.4}, {:.4}, {:.4}], rpy = [{:.4}, {:.4}, {:.4}] }}\ndensity = 400.0\ncolor = [{:.2}, {:.2}, {:.2}]\n",
        xyz[0], xyz[1], xyz[2], rpy[0], rpy[1], rpy[2], color[0], color[1], color[2]
    );
}

/// Where a layout's groups go: inside the rectangle `center ± half` on a surface at
/// height `top`, groups at least `gap` apart, every object fitting `grip` if given.
#[derive(Clone, Copy)]
pub(super) struct Region {
    pub(super) center: [f64; 2],
    pub(super) half: [f64; 2],
    pub(super) top: f64,
    pub(super) gap: f64,
    pub(super) grip: Option<f64>,
}

/// Singles, touching pairs (1 mm apart) and stacked pairs of `layout`, by rejection
/// sampling inside `region`.
pub(super) fn place_groups(
    rng: &mut ChaCha8Rng,
    layout: &TabletopLayout,
    region: &Region,
) -> Vec<Placed> {
    let Region {
        center,
        half,
        top,
        gap,
        grip,
    } = *region;
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
