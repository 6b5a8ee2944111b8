//! `tabula.Robot`: a robot from a built-in name, a URDF or a xacro file (with its SRDF),
//! and its kinematics on any chain: joint names, FK, IK (every solution found, nearest
//! to the seed first) and the geometric Jacobian.

use crate::{finite, runtime_error, value_error};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};
use tabula_geom::{Mat4, Pose};
use tabula_robot::Chain;
use tabula_robot::description::IkKind;
use tabula_robot::ik::{AutoIk, IkError, IkMode, IkSolver, NumericIk, NumericIkParams};
use tabula_robot::packages::PackagePaths;
use tabula_robot::robots::{LoadOptions, NamedRobot, load_with};

/// A chain with its IK solver, built once per (base, tip) and kept: building a solver
/// (closed-form detection, limits) costs more than a solve.
struct Kinematics {
    chain: Chain,
    solver: OnceLock<Box<dyn IkSolver + Send + Sync>>,
}

/// At most this many chains are kept (a program walking every link pair starts over).
const MAX_CHAINS: usize = 256;

/// A robot model with its description (arms, grippers, named states).
#[pyclass(module = "tabula._tabula", frozen)]
pub struct Robot {
    robot: NamedRobot,
    /// The first arm's chain: most calls use it.
    default_kinematics: Option<Arc<Kinematics>>,
    /// Other chains asked for by base and tip.
    chains: Mutex<HashMap<(String, String), Arc<Kinematics>>>,
}

impl Robot {
    /// The loaded robot (model and description).
    pub(crate) fn named(&self) -> &NamedRobot {
        &self.robot
    }

    /// The chain from `base` to `tip` (the first arm's by default), built once.
    fn kinematics(&self, base: Option<&str>, tip: Option<&str>) -> PyResult<Arc<Kinematics>> {
        let base = base.unwrap_or(&self.robot.default_base);
        let tip = tip.unwrap_or(&self.robot.default_tip);
        if let Some(k) = &self.default_kinematics
            && k.chain.base_link == base
            && k.chain.tip_link == tip
        {
            return Ok(k.clone());
        }
        let key = (base.to_string(), tip.to_string());
        let mut chains = self.chains.lock().map_err(runtime_error)?;
        if let Some(k) = chains.get(&key) {
            return Ok(k.clone());
        }
        let chain = Chain::new(&self.robot.model, base, tip).map_err(value_error)?;
        let k = Arc::new(Kinematics {
            chain,
            solver: OnceLock::new(),
        });
        if chains.len() >= MAX_CHAINS {
            chains.clear();
        }
        chains.insert(key, k.clone());
        Ok(k)
    }

    /// The solver of the chain: a closed form where one applies, numeric otherwise.
    fn solver<'k>(&self, k: &'k Kinematics) -> PyResult<&'k (dyn IkSolver + Send + Sync)> {
        if let Some(s) = k.solver.get() {
            return Ok(s.as_ref());
        }
        let chain = &k.chain;
        let arm = self
            .robot
            .description
            .arms
            .iter()
            .find(|a| a.base == chain.base_link && a.tip == chain.tip_link);
        // Every closed form that applies (spherical-shoulder 7R arms too), numeric for the
        // rest; an arm's own solver where its description names one (Golem-III).
        let solver: Box<dyn IkSolver + Send + Sync> = match arm {
            Some(a) if a.ik != IkKind::Numeric => a
                .ik_solver(&self.robot.model, NumericIkParams::default())
                .map_err(value_error)?,
            _ => Box::new(AutoIk::all_solutions(NumericIk::new(
                chain.clone(),
                NumericIkParams::default(),
            ))),
        };
        Ok(k.solver.get_or_init(|| solver).as_ref())
    }

    fn joints<'a>(&self, chain: &Chain, q: &'a [f64]) -> PyResult<&'a [f64]> {
        if q.len() != chain.dof() {
            return Err(value_error(format!(
                "the chain {} → {} has {} joints ({}), {} values given",
                chain.base_link,
                chain.tip_link,
                chain.dof(),
                chain.joint_names.join(", "),
                q.len()
            )));
        }
        finite(q, "joint values")
    }
}

/// A pose as a (4, 4) numpy matrix.
fn matrix<'py>(py: Python<'py>, p: &Pose) -> Bound<'py, PyArray2<f64>> {
    let m = Mat4::from_rotation_translation(p.rotation, p.translation);
    Array2::from_shape_fn((4, 4), |(r, c)| m.col(c)[r]).into_pyarray(py)
}

#[pymethods]
impl Robot {
    /// `Robot(path_or_name, srdf=None, xacro_args=None, package_paths=None)`.
    #[new]
    #[pyo3(signature = (path_or_name, srdf=None, xacro_args=None, package_paths=None))]
    fn new(
        py: Python<'_>,
        path_or_name: &str,
        srdf: Option<PathBuf>,
        xacro_args: Option<Vec<(String, String)>>,
        package_paths: Option<Vec<PathBuf>>,
    ) -> PyResult<Self> {
        let options = LoadOptions {
            xacro_args: xacro_args.unwrap_or_default(),
            packages: PackagePaths::new(package_paths.unwrap_or_default()),
            srdf,
        };
        let robot = py
            .detach(|| load_with(path_or_name, &options))
            .map_err(value_error)?;
        let default_kinematics = Chain::new(&robot.model, &robot.default_base, &robot.default_tip)
            .ok()
            .map(|chain| {
                Arc::new(Kinematics {
                    chain,
                    solver: OnceLock::new(),
                })
            });
        Ok(Self {
            robot,
            default_kinematics,
            chains: Mutex::new(HashMap::new()),
        })
    }

    /// The robot's name as loaded.
    #[getter]
    fn name(&self) -> String {
        self.robot.label.clone()
    }

    /// The arms the description names, with their chains' base and tip links.
    fn arms(&self) -> Vec<(String, String, String)> {
        let arms = &self.robot.description.arms;
        arms.iter()
            .map(|a| (a.name.clone(), a.base.clone(), a.tip.clone()))
            .collect()
    }

    /// The moving joints from `base` to `tip`, in the order `q` lists them.
    #[pyo3(signature = (base=None, tip=None))]
    fn joint_names(&self, base: Option<&str>, tip: Option<&str>) -> PyResult<Vec<String>> {
        Ok(self.kinematics(base, tip)?.chain.joint_names.clone())
    }

    /// Joint limits `(lower, upper)` of the chain, one row per joint.
    #[pyo3(signature = (base=None, tip=None))]
    fn limits<'py>(
        &self,
        py: Python<'py>,
        base: Option<&str>,
        tip: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let k = self.kinematics(base, tip)?;
        let c = &k.chain;
        let rows: Vec<Vec<f64>> = c
            .lower
            .iter()
            .zip(&c.upper)
            .map(|(l, u)| vec![*l, *u])
            .collect();
        PyArray2::from_vec2(py, &rows).map_err(runtime_error)
    }

    /// `base_from_tip` at joint values `q`: a (4, 4) matrix.
    #[pyo3(signature = (q, base=None, tip=None))]
    fn fk<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArray1<'py, f64>,
        base: Option<&str>,
        tip: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let k = self.kinematics(base, tip)?;
        let q = self.joints(&k.chain, q.as_slice().map_err(value_error)?)?;
        let p = k.chain.fk(q).map_err(value_error)?;
        Ok(matrix(py, &p))
    }

    /// The geometric Jacobian at `q` (6 × n: linear rows first, in the base frame).
    #[pyo3(signature = (q, base=None, tip=None))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArray1<'py, f64>,
        base: Option<&str>,
        tip: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let k = self.kinematics(base, tip)?;
        let q = self.joints(&k.chain, q.as_slice().map_err(value_error)?)?;
        let j = k.chain.jacobian(q).map_err(value_error)?;
        Ok(Array2::from_shape_fn((j.nrows(), j.ncols()), |(r, c)| j[(r, c)]).into_pyarray(py))
    }

    /// Every solution for `base_from_tip` = `T` (4 × 4) found, nearest to `seed` first;
    /// an empty list when there is none. `position_only` ignores the orientation.
    #[pyo3(signature = (t, base=None, tip=None, seed=None, position_only=false))]
    fn ik<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray2<'py, f64>,
        base: Option<&str>,
        tip: Option<&str>,
        seed: Option<PyReadonlyArray1<'py, f64>>,
        position_only: bool,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        let target = crate::pose_of_matrix(t.as_slice().map_err(value_error)?)?;
        let k = self.kinematics(base, tip)?;
        let seed = match &seed {
            Some(s) => self
                .joints(&k.chain, s.as_slice().map_err(value_error)?)?
                .to_vec(),
            None => k.chain.mid_configuration(),
        };
        let solver = self.solver(&k)?;
        let mode = if position_only {
            IkMode::PositionOnly
        } else {
            IkMode::Full
        };
        let solutions = match py.detach(|| solver.solve(&target, mode, &seed)) {
            Ok(s) => s,
            Err(IkError::NoSolution | IkError::NotFound { .. }) => Vec::new(),
            Err(e) => return Err(value_error(e)),
        };
        Ok(solutions
            .into_iter()
            .map(|s| s.joints.into_pyarray(py))
            .collect())
    }
}
