//! `tabula.stable_poses`: how a mesh rests on a table (seed 000), in trimesh's
//! convention: each transform puts the mesh on z = 0 resting on that face, its centre of
//! mass above the origin.

use crate::{finite, value_error};
use numpy::{PyArray1, PyArray3, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use tabula_geom::{Pose, Vec3};
use tabula_tasks::stable::{StableParams, StablePose, of_mesh};

/// The transform that rests the mesh on `pose`'s face: the support normal turned onto
/// −z, the centre of mass over the origin, the lowest vertex on z = 0.
fn resting(pose: &StablePose, vertices: &[Vec3], com: Vec3) -> Pose {
    let r = pose.resting_rotation(0.0);
    let c = r * com;
    let lowest = vertices
        .iter()
        .map(|v| (r * *v).z)
        .fold(f64::INFINITY, f64::min);
    let t = Vec3::new(-c.x, -c.y, -lowest);
    Pose::from_parts(t, r)
}

/// `(transforms (k, 4, 4), probabilities (k,), margins (k,))` of a triangle mesh, most
/// likely first; margins are the distance (m) from the centre of mass's projection to
/// the nearest edge of the contact polygon.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn stable_poses<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
) -> PyResult<(
    Bound<'py, PyArray3<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    if vertices.shape()[1] != 3 || faces.shape()[1] != 3 {
        return Err(value_error("vertices must be (n, 3) and faces (m, 3)"));
    }
    let v = vertices.as_array();
    let flat: Vec<f64> = v.iter().copied().collect();
    finite(&flat, "vertices")?;
    let points: Vec<Vec3> = flat
        .chunks(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    let n = points.len() as i64;
    let mut triangles = Vec::with_capacity(faces.shape()[0]);
    for f in faces.as_array().rows() {
        if f.iter().any(|&i| i < 0 || i >= n) {
            return Err(value_error(format!("a face names a vertex outside 0..{n}")));
        }
        triangles.push([f[0] as u32, f[1] as u32, f[2] as u32]);
    }
    let poses = py
        .detach(|| of_mesh(&points, &triangles, &StableParams::default()))
        .map_err(value_error)?;
    let com = Vec3::from_array(poses.center_of_mass);
    let mut order: Vec<usize> = (0..poses.poses.len()).collect();
    order.sort_by(|&a, &b| {
        poses.poses[b]
            .probability
            .total_cmp(&poses.poses[a].probability)
    });
    let transforms: Vec<Vec<Vec<f64>>> = order
        .iter()
        .map(|&k| crate::rows(&resting(&poses.poses[k], &points, com)))
        .collect();
    let probabilities: Vec<f64> = order.iter().map(|&k| poses.poses[k].probability).collect();
    let margins: Vec<f64> = order.iter().map(|&k| poses.poses[k].margin_m).collect();
    let transforms = PyArray3::from_vec3(py, &transforms).map_err(value_error)?;
    Ok((
        transforms,
        PyArray1::from_vec(py, probabilities),
        PyArray1::from_vec(py, margins),
    ))
}
