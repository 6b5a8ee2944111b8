//! A run recorded for people to look at: every body's shape once, the poses of what
//! moves over time, and pictures of the moments that matter (before, each grasp and
//! release, after) — what MeshCat's animations and RViz's bag playback show.

use crate::camera::snapshot;
use crate::world::{EntityKind, SimWorld};
use rapier3d_f64::prelude::*;
use serde::Serialize;
use std::sync::{Arc, Mutex};
use tabula_geom::{Pose, Vec3};

/// One body: its triangles in its own frame, its colour, and whether it ever moves.
#[derive(Debug, Clone, Serialize)]
pub struct ReplayBody {
    pub name: String,
    /// `floor`, `furniture`, `object` or `robot`.
    pub kind: &'static str,
    pub color: [f32; 3],
    /// x y z of each vertex in the body's frame (m).
    pub vertices: Vec<f32>,
    /// Three vertex indices per triangle.
    pub triangles: Vec<u32>,
    /// Fixed bodies keep `pose` for the whole run and are not in the frames.
    pub fixed: bool,
    /// Pose when recording began: x y z, then the quaternion x y z w.
    pub pose: [f32; 7],
}

/// The bodies and their motion: `frames[k]` holds 7 numbers (x y z qx qy qz qw) for
/// each body of `moving`, in that order, at `times[k]` simulated seconds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Replay {
    pub bodies: Vec<ReplayBody>,
    pub moving: Vec<usize>,
    pub times: Vec<f32>,
    pub frames: Vec<Vec<f32>>,
    /// Labelled moments (grasps, releases), in simulated seconds.
    pub marks: Vec<(f32, String)>,
}

/// A picture taken at a moment of the run.
#[derive(Clone)]
pub struct Moment {
    /// Simulated seconds.
    pub time: f64,
    pub label: String,
    /// One picture per eye: (eye name, image).
    pub pictures: Vec<(String, image::RgbImage)>,
}

/// Where pictures are taken from: a name, the eye and the point it looks at.
#[derive(Debug, Clone)]
pub struct Eye {
    pub name: String,
    pub eye: Vec3,
    pub target: Vec3,
    /// A scene camera to follow (a head camera moves with the head); `None` keeps
    /// `eye` and `target` fixed.
    pub camera: Option<String>,
}

/// How a run is recorded.
#[derive(Debug, Clone)]
pub struct RecorderParams {
    /// Frames per simulated second kept for the replay (the physics runs at 1/dt).
    pub rate_hz: f64,
    /// Picture size (pixels).
    pub picture_size: (usize, usize),
}

impl Default for RecorderParams {
    fn default() -> Self {
        Self {
            rate_hz: 15.0,
            picture_size: (480, 360),
        }
    }
}

/// Watches a world (as a [`crate::SimDriver`] observer) and records a [`Replay`] and
/// the [`Moment`]s when a robot takes or lets go of something.
pub struct Recorder {
    replay: Replay,
    entities: Vec<usize>,
    moving_entities: Vec<usize>,
    last: f64,
    params: RecorderParams,
    eyes: Vec<Eye>,
    held: Vec<(String, Vec<String>)>,
    /// Notes of the world already turned into moments.
    notes_seen: usize,
    moments: Vec<Moment>,
}

/// Rounds to 0.1 mm (and 1e-4 of a unit quaternion) so the page stays small.
fn rounded(x: f64) -> f32 {
    ((x * 1e4).round() * 1e-4) as f32
}

fn pose7(p: &Pose) -> [f32; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(rounded)
}

/// The triangles of a collider shape at `local`, appended to `vertices`/`triangles`.
fn append_shape(
    shape: &dyn Shape,
    local: &Pose,
    vertices: &mut Vec<f32>,
    triangles: &mut Vec<u32>,
) {
    let (points, tris): (Vec<Vec3>, Vec<[u32; 3]>) = match shape.as_typed_shape() {
        TypedShape::Cuboid(s) => s.to_trimesh(),
        TypedShape::Ball(s) => s.to_trimesh(12, 16),
        TypedShape::Capsule(s) => s.to_trimesh(12, 16),
        TypedShape::Cylinder(s) => s.to_trimesh(24),
        TypedShape::Cone(s) => s.to_trimesh(24),
        TypedShape::ConvexPolyhedron(s) => s.to_trimesh(),
        TypedShape::TriMesh(s) => (s.vertices().to_vec(), s.indices().to_vec()),
        TypedShape::Compound(c) => {
            for (p, s) in c.shapes() {
                append_shape(s.as_ref(), &(*local * *p), vertices, triangles);
            }
            return;
        }
        _ => return,
    };
    let base = (vertices.len() / 3) as u32;
    for p in points {
        let q = *local * p;
        vertices.extend([q.x, q.y, q.z].map(rounded));
    }
    triangles.extend(tris.into_iter().flatten().map(|i| base + i));
}

impl Recorder {
    /// Starts recording `world` as it is now; pictures are taken from `eyes`.
    pub fn new(world: &SimWorld, eyes: Vec<Eye>, params: RecorderParams) -> Self {
        let mut replay = Replay::default();
        let mut entities = Vec::new();
        let mut moving_entities = Vec::new();
        for (i, e) in world.entities.iter().enumerate() {
            if e.deleted {
                continue;
            }
            let Some(body) = world.physics.bodies.get(e.body) else {
                continue;
            };
            let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
            for &c in body.colliders() {
                if let Some(c) = world.physics.colliders.get(c)
                    && !crate::world::is_support_piece(c.user_data)
                {
                    let local = c.position_wrt_parent().copied().unwrap_or(Pose::IDENTITY);
                    append_shape(c.shape(), &local, &mut vertices, &mut triangles);
                }
            }
            let fixed = body.is_fixed();
            if !fixed {
                replay.moving.push(replay.bodies.len());
                moving_entities.push(i);
            }
            replay.bodies.push(ReplayBody {
                name: e.name.clone(),
                kind: match e.kind {
                    EntityKind::Floor => "floor",
                    EntityKind::Furniture => "furniture",
                    EntityKind::Object => "object",
                    EntityKind::RobotLink => "robot",
                },
                color: e.color.map(|c| c as f32),
                vertices,
                triangles,
                fixed,
                pose: pose7(body.position()),
            });
            entities.push(i);
        }
        let mut r = Self {
            replay,
            entities,
            moving_entities,
            last: f64::NEG_INFINITY,
            params,
            eyes,
            held: held_by_robot(world),
            notes_seen: world.notes.len(),
            moments: Vec::new(),
        };
        r.frame(world);
        r
    }

    /// A recorder behind a mutex, with the observer that feeds it (hand that to
    /// [`crate::SimDriver::observe`]; take the recording back with [`Self::finish`]).
    pub fn shared(self) -> (Arc<Mutex<Self>>, impl FnMut(&SimWorld) + Send + 'static) {
        let shared = Arc::new(Mutex::new(self));
        let feed = shared.clone();
        (shared, move |w: &SimWorld| {
            if let Ok(mut r) = feed.lock() {
                r.observe(w);
            }
        })
    }

    fn frame(&mut self, world: &SimWorld) {
        let hidden = [0.0, 0.0, -100.0, 0.0, 0.0, 0.0, 1.0];
        let mut poses = Vec::with_capacity(7 * self.moving_entities.len());
        for &i in &self.moving_entities {
            let e = &world.entities[i];
            let pose = match world.physics.bodies.get(e.body) {
                Some(b) if !e.deleted => pose7(b.position()),
                _ => hidden,
            };
            poses.extend(pose);
        }
        self.replay.times.push(world.time() as f32);
        self.replay.frames.push(poses);
        self.last = world.time();
    }

    /// Records the world after a physics step (at most `rate_hz` frames per simulated
    /// second) and takes pictures when what a robot holds changes or a task annotates
    /// a moment.
    pub fn observe(&mut self, world: &SimWorld) {
        if world.time() - self.last >= 1.0 / self.params.rate_hz {
            self.frame(world);
        }
        while self.notes_seen < world.notes.len() {
            let label = world.notes[self.notes_seen].1.clone();
            self.notes_seen += 1;
            self.mark(world, &label);
        }
        let held = held_by_robot(world);
        if held != self.held {
            let mut labels = Vec::new();
            for (robot, now) in &held {
                let before = self
                    .held
                    .iter()
                    .find(|(r, _)| r == robot)
                    .map(|(_, h)| h.clone())
                    .unwrap_or_default();
                labels.extend(
                    now.iter()
                        .filter(|o| !before.contains(o))
                        .map(|o| format!("{robot} grasps {o}")),
                );
                labels.extend(
                    before
                        .iter()
                        .filter(|o| !now.contains(o))
                        .map(|o| format!("{robot} lets go of {o}")),
                );
            }
            self.held = held;
            if !labels.is_empty() {
                self.mark(world, &labels.join(", "));
            }
        }
    }

    /// A labelled moment: a frame and a picture from every eye.
    pub fn mark(&mut self, world: &SimWorld, label: &str) {
        self.frame(world);
        self.replay
            .marks
            .push((world.time() as f32, label.to_string()));
        let (w, h) = self.params.picture_size;
        let pictures = self
            .eyes
            .iter()
            .map(|eye| {
                let (from, to) = eye
                    .camera
                    .as_deref()
                    .and_then(|c| world.camera(c).ok())
                    .map(|c| {
                        let p = c.world_from_camera;
                        (p.translation, p.translation + p.rotation * Vec3::Z)
                    })
                    .unwrap_or((eye.eye, eye.target));
                (eye.name.clone(), snapshot(world, from, to, w, h))
            })
            .collect();
        self.moments.push(Moment {
            time: world.time(),
            label: label.to_string(),
            pictures,
        });
    }

    /// The recording and its moments.
    pub fn finish(self) -> (Replay, Vec<Moment>) {
        debug_assert_eq!(self.entities.len(), self.replay.bodies.len());
        (self.replay, self.moments)
    }
}

/// What each robot holds, robots in world order, objects sorted.
fn held_by_robot(world: &SimWorld) -> Vec<(String, Vec<String>)> {
    world
        .robots
        .iter()
        .map(|r| {
            let mut h = world.held_objects(&r.name);
            h.sort();
            (r.name.clone(), h)
        })
        .collect()
}

/// The eyes a report looks from: each scene camera (following its link), and an
/// overview from above and in front of everything, looking at the middle of the
/// furniture and robots.
pub fn default_eyes(world: &SimWorld) -> Vec<Eye> {
    let mut eyes: Vec<Eye> = world
        .cameras
        .iter()
        .map(|c| Eye {
            name: c.name.get_ref().clone(),
            eye: Vec3::ZERO,
            target: Vec3::X,
            camera: Some(c.name.get_ref().clone()),
        })
        .collect();
    let bounds = world
        .live_entities()
        .filter(|e| e.kind != EntityKind::Floor)
        .filter_map(|e| world.entity_bounds(&e.name))
        .reduce(|a, b| {
            use tabula_geom::parry::bounding_volume::BoundingVolume;
            a.merged(&b)
        });
    if let Some(b) = bounds {
        let centre = b.center();
        let reach = b.half_extents().length().clamp(0.5, 5.0);
        let dir = Vec3::new(-0.75, -1.0, 0.85).normalize();
        let eye = centre + dir * (1.7 * reach);
        eyes.push(Eye {
            name: "overview".into(),
            eye,
            target: centre,
            camera: None,
        });
    }
    eyes
}
