//! `tabula.Scene`: a scene file in tabula's simulator — settle it, capture its cameras,
//! and run the jobs on it (clear, place, pick and place, tidy), each judged by physics
//! and answered with the CLI's `--json` content. A job changes the scene, as it would
//! change the world: the next call starts from where the last one left it.

use crate::{finite, runtime_error, value_error};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Mutex;
use tabula_geom::Vec3;
use tabula_sim::{PhysicsParams, SimWorld};

/// A simulated world built from a scene file.
#[pyclass(module = "tabula._tabula")]
pub struct Scene {
    world: Mutex<Option<SimWorld>>,
}

/// What a job gives back: its run as JSON text and the world after it.
type JobResult = anyhow::Result<(serde_json::Value, SimWorld)>;

impl Scene {
    /// Runs `job` on the world with the GIL released, keeping the world it leaves.
    fn run(
        &self,
        py: Python<'_>,
        job: impl FnOnce(SimWorld) -> JobResult + Send,
    ) -> PyResult<String> {
        let world = self
            .world
            .lock()
            .map_err(runtime_error)?
            .take()
            .ok_or_else(|| runtime_error("the scene was lost by an earlier failure"))?;
        // A failed job consumed the world: it is rebuilt from where it stood.
        let kept = world.to_scene();
        let (out, world) = match py.detach(|| job(world)) {
            Ok(r) => r,
            Err(e) => {
                let rebuilt = SimWorld::from_scene(&kept, PhysicsParams::default()).ok();
                *self.world.lock().map_err(runtime_error)? = rebuilt;
                return Err(runtime_error(format!("{e:#}")));
            }
        };
        *self.world.lock().map_err(runtime_error)? = Some(world);
        Ok(out.to_string())
    }

    fn with_world<T>(&self, f: impl FnOnce(&mut SimWorld) -> PyResult<T>) -> PyResult<T> {
        let mut guard = self.world.lock().map_err(runtime_error)?;
        let world = guard
            .as_mut()
            .ok_or_else(|| runtime_error("the scene was lost by an earlier failure"))?;
        f(world)
    }
}

fn point(v: [f64; 3], what: &str) -> PyResult<Vec3> {
    finite(&v, what)?;
    Ok(Vec3::from_array(v))
}

#[pymethods]
impl Scene {
    /// `Scene(path)`: the scene file (TOML) built into a world.
    #[new]
    fn new(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let world = py
            .detach(|| -> anyhow::Result<SimWorld> {
                let scene = tabula_sim::Scene::load(&path)?;
                Ok(SimWorld::from_scene(&scene, PhysicsParams::default())?)
            })
            .map_err(|e| value_error(format!("{e:#}")))?;
        Ok(Self {
            world: Mutex::new(Some(world)),
        })
    }

    /// Steps the physics until everything rests: `{steps, simulated_seconds,
    /// all_asleep}` as JSON text.
    fn settle(&self) -> PyResult<String> {
        self.with_world(|w| serde_json::to_string(&w.settle()).map_err(runtime_error))
    }

    /// The scene's cameras, by name.
    fn cameras(&self) -> PyResult<Vec<String>> {
        self.with_world(|w| Ok(w.cameras.iter().map(|c| c.name.get_ref().clone()).collect()))
    }

    /// One depth frame of camera `camera` (the first by default): `(points (h, w, 3) in
    /// the camera's optical frame, NaN where nothing was hit, world_from_camera (4, 4))`.
    #[pyo3(signature = (camera=None, seed=1))]
    #[allow(clippy::type_complexity)]
    fn capture<'py>(
        &self,
        py: Python<'py>,
        camera: Option<String>,
        seed: u64,
    ) -> PyResult<(Bound<'py, PyArray3<f64>>, Vec<Vec<f64>>)> {
        let frame = self.with_world(|w| {
            let name = match camera {
                Some(c) => c,
                None => w
                    .cameras
                    .first()
                    .map(|c| c.name.get_ref().clone())
                    .ok_or_else(|| value_error("the scene has no camera"))?,
            };
            let cam = w.camera(&name).map_err(value_error)?;
            Ok(tabula_sim::camera::capture(w, &cam, seed))
        })?;
        let flat: Vec<f64> = frame
            .cloud
            .points
            .iter()
            .flat_map(|p| p.to_array())
            .collect();
        let points =
            Array3::from_shape_vec((frame.height, frame.width, 3), flat).map_err(runtime_error)?;
        Ok((
            points.into_pyarray(py),
            crate::rows(&frame.world_from_camera),
        ))
    }

    /// The world now, as a scene file's text.
    fn to_toml(&self) -> PyResult<String> {
        self.with_world(|w| w.to_scene().to_toml().map_err(runtime_error))
    }

    /// Clears the table into the bin (seed 002): `tabula clear --json`'s content.
    #[pyo3(signature = (seed=1, max_actions=None))]
    fn clear(&self, py: Python<'_>, seed: u64, max_actions: Option<usize>) -> PyResult<String> {
        let params = tabula_tasks::clear::ClearParams::default();
        self.run(py, move |world| {
            let (out, world) =
                tabula_bench::clear::clear_in(world, None, (&params, max_actions), seed, |_| {})?;
            Ok((serde_json::to_value(&out)?, world))
        })
    }

    /// Places the object the robot holds (seed 000; `arm`: the holding one by default):
    /// `tabula place --json`'s content.
    #[pyo3(signature = (arm=None, seed=1))]
    fn place(&self, py: Python<'_>, arm: Option<String>, seed: u64) -> PyResult<String> {
        let params = tabula_tasks::place::PlaceParams::default();
        self.run(py, move |world| {
            let robot = tabula_bench::scene_robot(&world, None)?;
            let request = tabula_tasks::place::PlaceRequest {
                arm: arm.or_else(|| tabula_bench::place::held_by(&world, &robot)),
                not_on: Vec::new(),
                near: None,
            };
            let (out, world) = tabula_bench::place::place_in(
                world,
                Some(&robot),
                (&request, &params),
                seed,
                |_| {},
            )?;
            Ok((serde_json::to_value(&out)?, world))
        })
    }

    /// Picks the object near `pick` and places it at `place` (world, m; seed 001's
    /// integral test): `tabula pick-place --json`'s content.
    #[pyo3(signature = (pick, place, arm=None, seed=1))]
    fn pick_place(
        &self,
        py: Python<'_>,
        pick: [f64; 3],
        place: [f64; 3],
        arm: Option<String>,
        seed: u64,
    ) -> PyResult<String> {
        let request = tabula_tasks::pick_place::PickPlaceRequest {
            arm,
            pick: point(pick, "pick")?,
            place: point(place, "place")?,
        };
        let params = tabula_tasks::pick_place::PickPlaceParams::default();
        self.run(py, move |world| {
            let (out, world) = tabula_bench::pick_place::pick_place_in(
                world,
                None,
                (&request, &params),
                seed,
                |_| {},
            )?;
            Ok((serde_json::to_value(&out)?, world))
        })
    }

    /// Moves every object off the furniture `source` onto other surfaces the robot finds:
    /// `tabula tidy --json`'s content.
    #[pyo3(signature = (source="table".to_string(), seed=1))]
    fn tidy(&self, py: Python<'_>, source: String, seed: u64) -> PyResult<String> {
        let request = tabula_tasks::tidy::TidyRequest::default();
        let params = tabula_tasks::tidy::TidyParams::default();
        self.run(py, move |world| {
            let (out, world) = tabula_bench::tidy::tidy_in(
                world,
                (None, &source),
                (&request, &params),
                seed,
                |_| {},
            )?;
            Ok((serde_json::to_value(&out)?, world))
        })
    }
}
