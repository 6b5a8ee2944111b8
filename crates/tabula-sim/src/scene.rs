//! Scene files (TOML): floor, furniture, objects, robots and cameras.
//!
//! Errors name the file, the line and the key: TOML syntax and type errors carry
//! toml's own line and column; semantic errors (a negative size, an unknown robot) are
//! located at the entry's `name` key.

use serde::{Deserialize, Serialize};
use std::path::Path;
use tabula_geom::input::{Format, read_text};
use toml::Spanned;

/// A pose in the world: position (m) and URDF roll-pitch-yaw (rad).
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    #[serde(default)]
    pub xyz: [f64; 3],
    #[serde(default)]
    pub rpy: [f64; 3],
}

/// The shape of an object, in its own frame (cylinders, cones and capsules along z,
/// centred on the origin).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// Full edge lengths x y z (m).
    Box([f64; 3]),
    Cylinder {
        radius: f64,
        height: f64,
    },
    Sphere {
        radius: f64,
    },
    Cone {
        radius: f64,
        height: f64,
    },
    /// `height` is the cylindrical part, without the caps.
    Capsule {
        radius: f64,
        height: f64,
    },
    /// The polygon `outline` (x y, m; convex or not, either way round) drawn in the
    /// object's x–y plane and extruded `length` along z, centred on z = 0: wedges,
    /// triangular prisms, arches, half-cylinders, L- and T-blocks. Exact convex pieces,
    /// so an arch's notch stays open.
    Prism {
        outline: Vec<[f64; 2]>,
        length: f64,
    },
    /// An OBJ or STL file (relative to the scene file), as its convex hull.
    Mesh {
        path: String,
        #[serde(default = "unit_scale")]
        scale: [f64; 3],
    },
}

fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}

/// A movable object.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    pub name: Spanned<String>,
    pub shape: ShapeSpec,
    #[serde(default)]
    pub pose: PoseSpec,
    /// kg; if absent, `density` is used.
    pub mass: Option<f64>,
    /// kg/m³ (default 600, wood-like).
    pub density: Option<f64>,
    #[serde(default = "default_friction")]
    pub friction: f64,
    #[serde(default = "default_object_color")]
    pub color: [f64; 3],
}

fn default_friction() -> f64 {
    0.8
}

fn default_object_color() -> [f64; 3] {
    [0.8, 0.3, 0.2]
}

/// Kinds of furniture, built from boxes, cylinders and wedges; all fixed.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FurnitureKind {
    Table,
    Bookshelf,
    Cabinet,
    Drum,
    /// A wedge whose top face makes `angle_deg` with the floor's upward normal side
    /// (SPEC §1.3's 120° ramp: the surface is 60° from horizontal).
    Ramp,
    TrafficCone,
    SignDrum,
    Wall,
    Bin,
}

/// A piece of furniture.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FurnitureSpec {
    pub name: Spanned<String>,
    pub kind: FurnitureKind,
    #[serde(default)]
    pub pose: PoseSpec,
    /// Outer size x y z (m); each kind has a sensible default.
    pub size: Option<[f64; 3]>,
    /// Ramp angle between the ramp surface and the floor, measured over the ramp (deg).
    pub angle_deg: Option<f64>,
    /// Shelves of a bookshelf.
    pub shelves: Option<u32>,
    pub color: Option<[f64; 3]>,
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// A robot from a URDF at a base pose with initial joint values.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    pub name: Spanned<String>,
    /// `golem3`, `wam`, `pr2` or a URDF path relative to the scene file.
    pub urdf: String,
    #[serde(default)]
    pub pose: PoseSpec,
    #[serde(default)]
    pub joints: std::collections::BTreeMap<String, f64>,
    /// An object the robot starts holding in a gripper.
    pub hold: Option<HoldSpec>,
    /// xacro arguments when `urdf` is a .xacro file (`{ ur_type = "ur5e" }`).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub xacro_args: std::collections::BTreeMap<String, String>,
    /// The robot's MoveIt SRDF, relative to the scene file (default: the `.srdf`
    /// beside the URDF, if any).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub srdf: Option<String>,
    /// What the robot stands on, as part of its model (x, y, height; m): a solid box
    /// centred under its root, top at the root — furniture to the world, link
    /// `pedestal` to the robot's planners, as a cell's URDF has it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pedestal: Option<[f64; 3]>,
}

impl RobotSpec {
    /// The robot this entry names: a built-in name, or a URDF/xacro file relative to
    /// the scene's folder `base_dir`, with the entry's xacro arguments and SRDF on top
    /// of the process's loading options (`--package-path`, `--xacro-arg`).
    pub fn load(
        &self,
        base_dir: Option<&std::path::Path>,
    ) -> Result<tabula_robot::robots::NamedRobot, tabula_robot::RobotError> {
        let relative = |p: &str| match base_dir {
            Some(d) if std::path::Path::new(p).is_relative() => d.join(p),
            _ => std::path::PathBuf::from(p),
        };
        let source = match std::path::Path::new(&self.urdf).extension() {
            Some(_) => relative(&self.urdf).display().to_string(),
            None => self.urdf.clone(),
        };
        let mut options = tabula_robot::robots::default_options().clone();
        options
            .xacro_args
            .extend(self.xacro_args.iter().map(|(k, v)| (k.clone(), v.clone())));
        if let Some(s) = &self.srdf {
            options.srdf = Some(relative(s));
        }
        let mut robot = tabula_robot::robots::load_with(&source, &options)?;
        if let Some(size) = self.pedestal {
            robot.model.add_pedestal(size)?;
        }
        Ok(robot)
    }
}

/// A held object: placed at `tool_link` and gripped by closing `finger_joint`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HoldSpec {
    pub object: String,
    pub tool_link: String,
    pub finger_joint: String,
    pub fingers: [String; 2],
    pub palm: String,
    /// How the object is held: its pose in the tool frame (at an angle, off centre).
    /// Without it the object's origin is at the tool frame.
    pub tool_from_object: Option<PoseSpec>,
}

/// Where a camera looks from.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LookAt {
    pub eye: [f64; 3],
    pub target: [f64; 3],
}

/// A depth camera (Kinect-like defaults, SPEC §5).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    pub name: Spanned<String>,
    /// Fixed in the world, looking from `eye` at `target` …
    pub look_at: Option<LookAt>,
    /// … or mounted on a robot link (its optical frame: z forward, x right, y down).
    pub robot: Option<String>,
    pub link: Option<String>,
    #[serde(default = "default_width")]
    pub width: usize,
    #[serde(default = "default_height")]
    pub height: usize,
    #[serde(default = "default_hfov")]
    pub hfov_deg: f64,
    #[serde(default = "default_vfov")]
    pub vfov_deg: f64,
    #[serde(default = "default_min_range")]
    pub min_range: f64,
    #[serde(default = "default_max_range")]
    pub max_range: f64,
    /// σ = noise_coefficient · z² (m); 0.0015 ≈ a Kinect.
    #[serde(default = "default_noise")]
    pub noise_coefficient: f64,
    /// Fraction of spurious returns (0 = none).
    #[serde(default)]
    pub outlier_fraction: f64,
}

fn default_width() -> usize {
    640
}
fn default_height() -> usize {
    480
}
fn default_hfov() -> f64 {
    57.0
}
fn default_vfov() -> f64 {
    43.0
}
fn default_min_range() -> f64 {
    0.5
}
fn default_max_range() -> f64 {
    4.0
}
fn default_noise() -> f64 {
    0.0015
}

/// The floor: a horizontal slab whose top is z = 0.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FloorSpec {
    #[serde(default = "default_floor")]
    pub size: [f64; 2],
    #[serde(default = "default_floor_color")]
    pub color: [f64; 3],
}

fn default_floor() -> [f64; 2] {
    [12.0, 12.0]
}
fn default_floor_color() -> [f64; 3] {
    [0.55, 0.55, 0.5]
}

/// A whole scene file.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub floor: Option<FloorSpec>,
    #[serde(default)]
    pub furniture: Vec<FurnitureSpec>,
    #[serde(default, rename = "object")]
    pub objects: Vec<ObjectSpec>,
    #[serde(default, rename = "robot")]
    pub robots: Vec<RobotSpec>,
    #[serde(default, rename = "camera")]
    pub cameras: Vec<CameraSpec>,
    /// Folder that relative paths in the scene resolve against.
    #[serde(skip)]
    pub base_dir: Option<std::path::PathBuf>,
}

/// The range of sizes (m) a body may have: below a tenth of a millimetre or above
/// 100 m the contact solver's tolerances (millimetres) and a 1/240 s step no longer
/// describe a rigid body on a table.
pub const MIN_SIZE: f64 = 1e-4;
pub const MAX_SIZE: f64 = 100.0;
/// The farthest a body may be from the origin along any axis (m): beyond a
/// kilometre a tabletop scene has lost a unit or a sign, and contact tolerances of a
/// millimetre lose their meaning in the coordinates' precision long before 1e300.
pub const MAX_COORDINATE: f64 = 1000.0;
/// Masses (kg) and densities (kg/m³) the solver handles beside a robot arm of ~10 kg:
/// mass ratios beyond ~1e6 make stacked contacts explode or sink.
pub const MIN_MASS: f64 = 1e-4;
pub const MAX_MASS: f64 = 1e4;
pub const MIN_DENSITY: f64 = 1.0;
pub const MAX_DENSITY: f64 = 1e5;

/// A scene file that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{message}", if file.is_empty() { String::new() } else { format!("{file}:{line}: ") })]
pub struct SceneError {
    pub file: String,
    pub line: usize,
    /// The key the problem is at, e.g. `object.box1.shape`.
    pub key: String,
    pub message: String,
}

fn line_of(text: &str, byte: usize) -> usize {
    text[..byte.min(text.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

impl Scene {
    /// The scene as TOML text that [`Scene::parse`] reads back.
    pub fn to_toml(&self) -> Result<String, String> {
        toml::to_string(self).map_err(|e| e.to_string())
    }

    /// Reads and checks a scene file; a name that is no file but a built-in scene's
    /// (`clutter`, [`crate::builtin`]) loads that scene.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let shown = path.display().to_string();
        if !path.exists()
            && let Some(b) = crate::builtin::scene(&shown)
        {
            return Self::parse(b.text, &format!("{} (built-in)", b.name));
        }
        let text = read_text(path, Format::Scene).map_err(|e| SceneError {
            file: String::new(),
            line: 0,
            key: String::new(),
            message: if path.exists() {
                e.to_string()
            } else {
                format!("{e} (built-in scenes: {})", crate::builtin::names())
            },
        })?;
        let mut scene = Self::parse(&text, &path.display().to_string())?;
        scene.base_dir = path.parent().map(Path::to_path_buf);
        Ok(scene)
    }

    /// Parses and checks scene text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Self, SceneError> {
        tabula_geom::input::check_toml_numbers(text).map_err(|message| SceneError {
            file: file.to_string(),
            line: 0,
            key: String::new(),
            message,
        })?;
        let scene: Scene = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(0, |s| line_of(text, s.start));
            SceneError {
                file: file.to_string(),
                line,
                key: String::new(),
                message: e.message().trim().to_string(),
            }
        })?;
        scene.check(text, file)?;
        Ok(scene)
    }

    fn check(&self, text: &str, file: &str) -> Result<(), SceneError> {
        let err = |name: &Spanned<String>, key: String, message: String| SceneError {
            file: file.to_string(),
            line: line_of(text, name.span().start),
            key,
            message,
        };
        self.check_names()
            .map_err(|(name, key, m)| err(name, key, m))?;
        self.check_floor().map_err(|message| SceneError {
            file: file.to_string(),
            line: 0,
            key: "floor.size".into(),
            message,
        })?;
        let entries = self
            .objects
            .iter()
            .map(|o| (&o.name, "object", check_object(o)))
            .chain(
                self.furniture
                    .iter()
                    .map(|f| (&f.name, "furniture", check_furniture(f))),
            )
            .chain(
                self.robots
                    .iter()
                    .map(|r| (&r.name, "robot", check_robot(r))),
            )
            .chain(
                self.cameras
                    .iter()
                    .map(|c| (&c.name, "camera", check_camera(c))),
            );
        for (name, table, checked) in entries {
            if let Err((field, message)) = checked {
                let key = match field {
                    "" => format!("{table}.{}", name.get_ref()),
                    field => format!("{table}.{}.{field}", name.get_ref()),
                };
                return Err(err(name, key, message));
            }
        }
        Ok(())
    }

    /// Every name is given and used once, across all tables.
    #[allow(clippy::type_complexity)]
    fn check_names(&self) -> Result<(), (&Spanned<String>, String, String)> {
        let mut names = std::collections::HashSet::new();
        let all_names = self
            .objects
            .iter()
            .map(|o| (&o.name, "object"))
            .chain(self.furniture.iter().map(|f| (&f.name, "furniture")))
            .chain(self.robots.iter().map(|r| (&r.name, "robot")))
            .chain(self.cameras.iter().map(|c| (&c.name, "camera")));
        for (name, table) in all_names {
            if name.get_ref().is_empty() {
                let message = "name must not be empty".into();
                return Err((name, format!("{table}.name"), message));
            }
            if !names.insert(name.get_ref().clone()) {
                let message = format!("`{}` is used twice", name.get_ref());
                return Err((name, format!("{table}.name"), message));
            }
        }
        Ok(())
    }

    fn check_floor(&self) -> Result<(), String> {
        if let Some(floor) = &self.floor
            && floor
                .size
                .iter()
                .any(|d| !(MIN_SIZE..=10.0 * MAX_COORDINATE).contains(d))
        {
            return Err(format!(
                "floor sizes must be between {MIN_SIZE} and {} m",
                10.0 * MAX_COORDINATE
            ));
        }
        Ok(())
    }
}

/// A field's check failed: the field (empty for the entry itself) and why.
type FieldError = (&'static str, String);

fn finite_pose(p: &PoseSpec) -> bool {
    p.xyz
        .iter()
        .all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE)
        && p.rpy.iter().all(|v| v.is_finite())
}

const POSE_MESSAGE: &str = "pose values must be finite, positions within ±1000 m";

fn check_object(o: &ObjectSpec) -> Result<(), FieldError> {
    if !finite_pose(&o.pose) {
        return Err(("pose", POSE_MESSAGE.into()));
    }
    let dims: Vec<f64> = match &o.shape {
        ShapeSpec::Box(s) => s.to_vec(),
        ShapeSpec::Cylinder { radius, height } | ShapeSpec::Cone { radius, height } => {
            vec![*radius, *height]
        }
        ShapeSpec::Capsule { radius, height } => vec![*radius, height + 1e-9],
        ShapeSpec::Sphere { radius } => vec![*radius],
        ShapeSpec::Mesh { scale, .. } => scale.to_vec(),
        ShapeSpec::Prism { outline, length } => {
            check_outline(outline)?;
            vec![*length]
        }
    };
    if dims.iter().any(|d| !(MIN_SIZE..=MAX_SIZE).contains(d)) {
        return Err((
            "shape",
            format!(
                "sizes (and mesh scales) must be between {MIN_SIZE} and {MAX_SIZE}: \
                 the physics cannot simulate a body outside that range"
            ),
        ));
    }
    match (o.mass, o.density) {
        (Some(m), _) if !(MIN_MASS..=MAX_MASS).contains(&m) => {
            return Err((
                "mass",
                format!("mass must be between {MIN_MASS} and {MAX_MASS} kg, got {m}"),
            ));
        }
        (_, Some(d)) if !(MIN_DENSITY..=MAX_DENSITY).contains(&d) => {
            return Err((
                "density",
                format!("density must be between {MIN_DENSITY} and {MAX_DENSITY} kg/m³, got {d}"),
            ));
        }
        _ => {}
    }
    if !(o.friction.is_finite() && o.friction >= 0.0) {
        return Err(("friction", "friction must be a non-negative number".into()));
    }
    Ok(())
}

/// Most vertices a prism's outline may have.
pub const MAX_OUTLINE: usize = 256;

/// A prism's outline: a bounded simple polygon within the size limits.
fn check_outline(outline: &[[f64; 2]]) -> Result<(), FieldError> {
    if outline.len() > MAX_OUTLINE {
        return Err((
            "shape",
            format!(
                "a prism's outline has at most {MAX_OUTLINE} vertices, got {}",
                outline.len()
            ),
        ));
    }
    let points: Vec<tabula_geom::Vec2> = outline
        .iter()
        .map(|&[x, y]| tabula_geom::Vec2::new(x, y))
        .collect();
    if points
        .iter()
        .any(|p| !(p.x.abs() <= MAX_SIZE && p.y.abs() <= MAX_SIZE))
    {
        return Err((
            "shape",
            format!("a prism's outline coordinates must be finite and within ±{MAX_SIZE} m"),
        ));
    }
    tabula_geom::convex_pieces::convex_pieces(&points)
        .map_err(|e| ("shape", format!("a prism's outline: {e}")))?;
    let (lo, hi) = points.iter().fold(
        (
            tabula_geom::Vec2::splat(f64::INFINITY),
            tabula_geom::Vec2::splat(f64::NEG_INFINITY),
        ),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    if (hi - lo).min_element() < MIN_SIZE {
        return Err((
            "shape",
            format!("a prism's outline must be at least {MIN_SIZE} m across both ways"),
        ));
    }
    Ok(())
}

fn check_furniture(f: &FurnitureSpec) -> Result<(), FieldError> {
    if !finite_pose(&f.pose) {
        return Err(("pose", POSE_MESSAGE.into()));
    }
    if let Some(s) = f.size
        && s.iter().any(|d| !(MIN_SIZE..=MAX_SIZE).contains(d))
    {
        return Err((
            "size",
            format!("sizes must be between {MIN_SIZE} and {MAX_SIZE} m"),
        ));
    }
    if let Some(a) = f.angle_deg
        && !(a.is_finite() && a > 90.0 && a < 180.0)
    {
        return Err((
            "angle_deg",
            format!("a ramp angle must be between 90° and 180°, got {a}"),
        ));
    }
    Ok(())
}

fn check_robot(r: &RobotSpec) -> Result<(), FieldError> {
    if !finite_pose(&r.pose) || r.joints.values().any(|v| !v.is_finite()) {
        return Err(("", "pose and joint values must be finite".into()));
    }
    if let Some(s) = r.pedestal
        && s.iter().any(|d| !(MIN_SIZE..=MAX_SIZE).contains(d))
    {
        return Err((
            "pedestal",
            format!("sizes must be between {MIN_SIZE} and {MAX_SIZE} m"),
        ));
    }
    Ok(())
}

fn check_camera(c: &CameraSpec) -> Result<(), FieldError> {
    if c.look_at.is_some() == c.link.is_some() {
        return Err((
            "look_at",
            "give either look_at = {eye, target} or robot + link".into(),
        ));
    }
    if c.width == 0 || c.height == 0 || c.width.checked_mul(c.height).is_none_or(|n| n > 16_000_000)
    {
        return Err((
            "width",
            "image size must be between 1 and 16 million pixels".into(),
        ));
    }
    let fov_ok = |v: f64| v.is_finite() && v > 0.0 && v < 179.0;
    if !fov_ok(c.hfov_deg) || !fov_ok(c.vfov_deg) {
        return Err(("hfov_deg", "fields of view must be in (0°, 179°)".into()));
    }
    if !(c.min_range.is_finite()
        && c.max_range.is_finite()
        && 0.0 <= c.min_range
        && c.min_range < c.max_range)
    {
        return Err(("max_range", "need 0 ≤ min_range < max_range".into()));
    }
    if !(c.noise_coefficient.is_finite() && c.noise_coefficient >= 0.0) {
        return Err(("noise_coefficient", "noise must be non-negative".into()));
    }
    if !(0.0..=1.0).contains(&c.outlier_fraction) {
        return Err((
            "outlier_fraction",
            "outlier_fraction must be in [0, 1]".into(),
        ));
    }
    if let Some(l) = &c.look_at
        && (l.eye.iter().chain(&l.target).any(|v| !v.is_finite()) || l.eye == l.target)
    {
        return Err((
            "look_at",
            "eye and target must be finite and distinct".into(),
        ));
    }
    Ok(())
}

/// Just a spanned name, for entries made by code rather than read from a file.
#[derive(Debug, Clone, Deserialize, Serialize)]
pub struct NameOnly {
    pub name: Spanned<String>,
}
