//! Reading ROS messages out of a YAML tree with errors that name the field
//! (`world.collision_objects[3].primitives[0].dimensions`), accepting both spellings
//! tools write: geometry as maps (`{x: 1, y: 2, z: 3}`, what `ros2 topic echo` and
//! MoveIt's own YAML give) and as lists (`[1, 2, 3]`, what MotionBenchMaker writes;
//! quaternions then `[x, y, z, w]`).

use super::MoveItError;
use serde_yaml::Value;
use tabula_geom::input::MAX_MAGNITUDE;
use tabula_geom::{Pose, Quat, Vec3};

/// A YAML node with the path it was reached by.
#[derive(Clone)]
pub(crate) struct Node<'a> {
    pub value: &'a Value,
    path: String,
}

impl<'a> Node<'a> {
    pub fn root(value: &'a Value) -> Self {
        Self {
            value,
            path: String::new(),
        }
    }

    pub fn path(&self) -> &str {
        if self.path.is_empty() {
            "(top)"
        } else {
            &self.path
        }
    }

    pub fn error(&self, why: impl Into<String>) -> MoveItError {
        MoveItError::Field {
            path: self.path().to_string(),
            why: why.into(),
        }
    }

    /// A child by key, `None` when absent or `null`.
    pub fn get(&self, key: &str) -> Option<Node<'a>> {
        let v = self.value.as_mapping()?.get(key)?;
        (!v.is_null()).then(|| Node {
            value: v,
            path: if self.path.is_empty() {
                key.to_string()
            } else {
                format!("{}.{key}", self.path)
            },
        })
    }

    /// A child that must be present.
    pub fn need(&self, key: &str) -> Result<Node<'a>, MoveItError> {
        self.get(key)
            .ok_or_else(|| self.error(format!("missing `{key}`")))
    }

    /// The items of a sequence (an absent or `null` node is empty).
    pub fn items(&self) -> Result<Vec<Node<'a>>, MoveItError> {
        if self.value.is_null() {
            return Ok(Vec::new());
        }
        let seq = self
            .value
            .as_sequence()
            .ok_or_else(|| self.error("expected a list"))?;
        Ok(seq
            .iter()
            .enumerate()
            .map(|(i, v)| Node {
                value: v,
                path: format!("{}[{i}]", self.path),
            })
            .collect())
    }

    /// The items of an optional list field.
    pub fn list(&self, key: &str) -> Result<Vec<Node<'a>>, MoveItError> {
        match self.get(key) {
            Some(n) => n.items(),
            None => Ok(Vec::new()),
        }
    }

    /// A finite number of at most [`MAX_MAGNITUDE`] in size.
    pub fn number(&self) -> Result<f64, MoveItError> {
        let v = match self.value {
            Value::Number(n) => n.as_f64(),
            // YAML 1.1 writers (and PyYAML) spell special floats this way.
            Value::String(s) => match s.trim() {
                ".nan" | ".NaN" | "nan" => Some(f64::NAN),
                ".inf" | "inf" => Some(f64::INFINITY),
                "-.inf" | "-inf" => Some(f64::NEG_INFINITY),
                _ => None,
            },
            _ => None,
        }
        .ok_or_else(|| self.error("expected a number"))?;
        if !v.is_finite() {
            return Err(self.error(format!("{v} is not a finite number")));
        }
        if v.abs() > MAX_MAGNITUDE {
            return Err(self.error(format!("{v} is beyond ±{MAX_MAGNITUDE}")));
        }
        Ok(v)
    }

    pub fn text(&self) -> Result<&'a str, MoveItError> {
        match self.value {
            Value::String(s) => Ok(s.as_str()),
            _ => Err(self.error("expected text")),
        }
    }

    pub fn numbers(&self) -> Result<Vec<f64>, MoveItError> {
        self.items()?.iter().map(Node::number).collect()
    }

    pub fn texts(&self) -> Result<Vec<&'a str>, MoveItError> {
        self.items()?.iter().map(Node::text).collect()
    }

    /// Exactly `N` numbers, either as a list or as a map with the keys `names`.
    fn fixed<const N: usize>(&self, names: [&str; N]) -> Result<[f64; N], MoveItError> {
        let mut out = [0.0; N];
        if self.value.is_sequence() {
            let v = self.numbers()?;
            if v.len() != N {
                return Err(self.error(format!("expected {N} numbers, got {}", v.len())));
            }
            out.copy_from_slice(&v);
        } else {
            for (o, k) in out.iter_mut().zip(names) {
                *o = self.need(k)?.number()?;
            }
        }
        Ok(out)
    }

    pub fn vec3(&self) -> Result<Vec3, MoveItError> {
        Ok(Vec3::from_array(self.fixed(["x", "y", "z"])?))
    }

    /// A quaternion, normalised; one far from unit length (or zero) is refused, as
    /// MoveIt refuses it.
    pub fn quat(&self) -> Result<Quat, MoveItError> {
        let [x, y, z, w] = self.fixed(["x", "y", "z", "w"])?;
        let q = Quat::from_xyzw(x, y, z, w);
        let n = q.length();
        if n <= 1e-6 {
            return Err(self.error("the quaternion has zero length"));
        }
        if (n - 1.0).abs() > 1e-3 {
            tracing::debug!("{}: quaternion of length {n} normalised", self.path());
        }
        Ok(q / n)
    }

    /// A `geometry_msgs/Pose` (`position`, `orientation`; a missing part is the identity).
    pub fn pose(&self) -> Result<Pose, MoveItError> {
        self.pose_from("position", "orientation")
    }

    /// A `geometry_msgs/Transform` (`translation`, `rotation`).
    pub fn transform(&self) -> Result<Pose, MoveItError> {
        self.pose_from("translation", "rotation")
    }

    fn pose_from(&self, translation: &str, rotation: &str) -> Result<Pose, MoveItError> {
        let t = match self.get(translation) {
            Some(p) => p.vec3()?,
            None => Vec3::ZERO,
        };
        let r = match self.get(rotation) {
            Some(o) => o.quat()?,
            None => Quat::IDENTITY,
        };
        Ok(Pose::from_parts(t, r))
    }
}
