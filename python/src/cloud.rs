//! Point clouds: PCD and PLY files read into numpy arrays, and one frame's perception
//! (the table, its objects, every surface, the free space) — `tabula perceive`'s JSON
//! with a label per point.

use crate::{finite, pose_of_rows, rows, value_error};
use numpy::ndarray::ArrayD;
use numpy::{IntoPyArray, PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;
use tabula_geom::{CloudFile, PointCloud, Vec3};
use tabula_perception::TabletopParams;
use tabula_perception::frame::{Perceived, perceive as perceive_frame, read_cloud_file};

/// Points (an organized cloud's `(h, w, 3)`, else `(n, 3)`, NaN where the sensor had no
/// return), colours (the same shape in uint8, or `None`) and the file's `VIEWPOINT` as a
/// (4, 4) matrix.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn read_cloud<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(
    Bound<'py, PyArrayDyn<f64>>,
    Option<Bound<'py, PyArrayDyn<u8>>>,
    Vec<Vec<f64>>,
)> {
    let file = py.detach(|| read_cloud_file(&path)).map_err(value_error)?;
    let c = &file.cloud;
    let shape: Vec<usize> = if c.is_organized() {
        vec![c.height, c.width, 3]
    } else {
        vec![c.points.len(), 3]
    };
    let flat: Vec<f64> = c.points.iter().flat_map(|p| p.to_array()).collect();
    let points = ArrayD::from_shape_vec(shape.clone(), flat).map_err(value_error)?;
    let colors = match &file.colors {
        Some(cols) => {
            let flat: Vec<u8> = cols.iter().flat_map(|c| *c).collect();
            Some(
                ArrayD::from_shape_vec(shape, flat)
                    .map_err(value_error)?
                    .into_pyarray(py),
            )
        }
        None => None,
    };
    Ok((points.into_pyarray(py), colors, rows(&file.viewpoint)))
}

/// A cloud from a `(h, w, 3)` (organized) or `(n, 3)` float64 array; NaN marks no point.
/// The points are read in place (the Python half made the array contiguous): the cloud
/// is the one copy.
fn cloud_of(points: &PyReadonlyArrayDyn<'_, f64>) -> PyResult<PointCloud> {
    let shape = points.shape();
    let flat = points.as_slice().map_err(value_error)?;
    if flat.iter().any(|v| v.is_infinite()) {
        return Err(value_error(
            "points: infinite values (NaN marks a missing point; infinity is not a position)",
        ));
    }
    let pts: Vec<Vec3> = flat
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    match shape {
        [h, w, 3] => PointCloud::organized(*w, *h, pts)
            .ok_or_else(|| value_error("points: bad organized size")),
        [_, 3] => Ok(PointCloud::unorganized(pts)),
        other => Err(value_error(format!(
            "points must be (h, w, 3) or (n, 3), not {other:?}"
        ))),
    }
}

/// Per point: -1 none, 0 the table, k + 1 object k, -2 objects cut by the frame's edge.
fn labels(p: &Perceived, n: usize) -> Vec<i32> {
    let mut out = vec![-1; n];
    for &i in &p.result.table.inliers {
        out[i] = 0;
    }
    for (k, o) in p.result.objects.iter().enumerate() {
        for &i in &o.indices {
            out[i] = k as i32 + 1;
        }
    }
    for &i in p.result.partial.iter().flat_map(|o| &o.indices) {
        out[i] = -2;
    }
    out
}

/// One frame's perception: `(json, labels, segments)`, the JSON being `tabula perceive
/// --json`'s, `labels` the points' (shape of the cloud without its last axis) and
/// `segments` the same in PCL's convention (`perceive --labels`: 0 not an object, k the
/// object whose JSON `label` is k).
#[pyfunction]
#[pyo3(signature = (points, world_from_camera=None, up=None, params=None))]
#[allow(clippy::type_complexity)]
pub fn perceive<'py>(
    py: Python<'py>,
    points: PyReadonlyArrayDyn<'py, f64>,
    world_from_camera: Option<Vec<Vec<f64>>>,
    up: Option<[f64; 3]>,
    params: Option<(String, String)>,
) -> PyResult<(
    String,
    Bound<'py, PyArrayDyn<i32>>,
    Bound<'py, PyArrayDyn<u32>>,
)> {
    let params: TabletopParams = match &params {
        Some((kind, text)) => crate::params::parse(kind, text)?,
        None => TabletopParams::default(),
    };
    let cloud = cloud_of(&points)?;
    let shape: Vec<usize> = points.shape()[..points.ndim() - 1].to_vec();
    let pose = match world_from_camera {
        Some(rows) => Some(pose_of_rows(&rows)?),
        None => None,
    };
    let up = match up {
        Some(u) => {
            finite(&u, "up")?;
            let v = Vec3::from_array(u);
            if v.length() < 1e-9 {
                return Err(value_error("up must be a non-zero direction"));
            }
            Some(v.normalize())
        }
        None => None,
    };
    let n = cloud.points.len();
    let file = CloudFile::plain(cloud);
    let perceived = py
        .detach(|| perceive_frame(&file, pose, up, &[], &params))
        .map_err(value_error)?;
    let json = perceived.to_json(None, None).to_string();
    let labels =
        ArrayD::from_shape_vec(shape.clone(), labels(&perceived, n)).map_err(value_error)?;
    let segments =
        ArrayD::from_shape_vec(shape, perceived.segment_labels()).map_err(value_error)?;
    Ok((json, labels.into_pyarray(py), segments.into_pyarray(py)))
}
