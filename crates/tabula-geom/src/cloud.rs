//! Point clouds (organized like a depth image, or not) and the PCD file format.

use crate::{Pose, Vec3};
use std::io::Write;

/// A point cloud. Organized clouds keep the sensor's `width × height` grid, with NaN
/// points where the sensor had no return; unorganized ones have `height == 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCloud {
    pub width: usize,
    pub height: usize,
    pub points: Vec<Vec3>,
}

/// A cloud as a sensor file carries it: its points, their colours and labels when the
/// file has them (one per point, grid kept), and the sensor's pose in the cloud's frame
/// (PCD's `VIEWPOINT`; identity when the file says nothing).
#[derive(Debug, Clone, PartialEq)]
pub struct CloudFile {
    pub cloud: PointCloud,
    pub colors: Option<Vec<[u8; 3]>>,
    /// PCL's `label` field: a segmentation (0 none, k segment k) or a ground truth.
    pub labels: Option<Vec<u32>>,
    pub viewpoint: Pose,
}

impl CloudFile {
    /// A cloud without colours whose sensor sits at the origin.
    pub fn plain(cloud: PointCloud) -> Self {
        Self {
            cloud,
            colors: None,
            labels: None,
            viewpoint: Pose::IDENTITY,
        }
    }
}

/// PCD data encodings this writer produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PcdEncoding {
    Ascii,
    Binary,
}

impl PointCloud {
    /// An organized cloud; `points.len()` must be `width * height`.
    pub fn organized(width: usize, height: usize, points: Vec<Vec3>) -> Option<Self> {
        (points.len() == width * height).then_some(Self {
            width,
            height,
            points,
        })
    }

    /// An unorganized cloud.
    pub fn unorganized(points: Vec<Vec3>) -> Self {
        Self {
            width: points.len(),
            height: 1,
            points,
        }
    }

    /// Every `step`-th pixel of every `step`-th row of an organized cloud (a sensor's
    /// lower-resolution mode, as the Kinect's 320 × 240); an unorganized cloud keeps every
    /// `step`²-th point. `step` 0 or 1 returns a copy.
    pub fn decimated(&self, step: usize) -> Self {
        if step <= 1 {
            return self.clone();
        }
        if !self.is_organized() {
            return Self::unorganized(self.points.iter().copied().step_by(step * step).collect());
        }
        let (w, h) = (self.width.div_ceil(step), self.height.div_ceil(step));
        let mut points = Vec::with_capacity(w * h);
        for r in (0..self.height).step_by(step) {
            let row = &self.points[r * self.width..(r + 1) * self.width];
            points.extend(row.iter().step_by(step));
        }
        Self {
            width: w,
            height: h,
            points,
        }
    }

    pub fn is_organized(&self) -> bool {
        self.height > 1
    }

    /// Number of finite points.
    pub fn finite_count(&self) -> usize {
        self.points.iter().filter(|p| p.is_finite()).count()
    }

    /// The cloud moved by a rigid transform (`target_from_source`), keeping its grid
    /// and its missing points.
    pub fn transformed(&self, target_from_source: &Pose) -> Self {
        Self {
            width: self.width,
            height: self.height,
            points: self
                .points
                .iter()
                .map(|p| {
                    if p.is_finite() {
                        *target_from_source * *p
                    } else {
                        Vec3::NAN
                    }
                })
                .collect(),
        }
    }

    /// The points as x y z little-endian f32 triples (NaN kept): the binary body of
    /// both PCD and PLY.
    pub(crate) fn write_xyz_f32_le(&self, out: &mut impl Write) -> std::io::Result<()> {
        let mut buf = Vec::with_capacity(self.points.len() * 12);
        for p in &self.points {
            for v in [p.x, p.y, p.z] {
                buf.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        out.write_all(&buf)
    }

    /// Writes PCD v0.7 (fields x y z, float32), keeping NaN points so the grid survives.
    pub fn write_pcd(&self, out: &mut impl Write, encoding: PcdEncoding) -> std::io::Result<()> {
        self.write_pcd_with(out, encoding, &PcdExtras::default())
    }

    /// Writes PCD v0.7 with the sensor pose as `VIEWPOINT` (x y z qw qx qy qz) and, when
    /// given (one per point), colours as PCL's packed float `rgb` field and labels as its
    /// `label` field (uint32, as `pcl::PointXYZRGBL` and `pcl_viewer` read it).
    pub fn write_pcd_with(
        &self,
        out: &mut impl Write,
        encoding: PcdEncoding,
        extras: &PcdExtras<'_>,
    ) -> std::io::Result<()> {
        let n = self.points.len();
        let colors = extras.colors.filter(|c| c.len() == n);
        let labels = extras.labels.filter(|l| l.len() == n);
        let (t, q) = (extras.viewpoint.translation, extras.viewpoint.rotation);
        // (name, type) of each field; every one is 4 bytes, one value.
        let mut fields = vec![("x", "F"), ("y", "F"), ("z", "F")];
        if colors.is_some() {
            fields.push(("rgb", "F"));
        }
        if labels.is_some() {
            fields.push(("label", "U"));
        }
        let column = |f: &dyn Fn(&(&str, &str)) -> String| {
            fields.iter().map(f).collect::<Vec<_>>().join(" ")
        };
        write!(
            out,
            "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {}\nSIZE {}\nTYPE {}\nCOUNT {}\nWIDTH {}\nHEIGHT {}\nVIEWPOINT {} {} {} {} {} {} {}\nPOINTS {n}\nDATA {}\n",
            column(&|f| f.0.to_string()),
            column(&|_| "4".to_string()),
            column(&|f| f.1.to_string()),
            column(&|_| "1".to_string()),
            self.width,
            self.height,
            t.x,
            t.y,
            t.z,
            q.w,
            q.x,
            q.y,
            q.z,
            match encoding {
                PcdEncoding::Ascii => "ascii",
                PcdEncoding::Binary => "binary",
            }
        )?;
        let packed = |k: usize| {
            colors.map(|c| {
                let [r, g, b] = c[k];
                f32::from_bits((r as u32) << 16 | (g as u32) << 8 | b as u32)
            })
        };
        match encoding {
            PcdEncoding::Ascii => {
                for (k, p) in self.points.iter().enumerate() {
                    if p.is_finite() {
                        write!(out, "{} {} {}", p.x as f32, p.y as f32, p.z as f32)?;
                    } else {
                        write!(out, "nan nan nan")?;
                    }
                    // `{:e}` of an f32 reads back to the same bits.
                    if let Some(c) = packed(k) {
                        write!(out, " {c:e}")?;
                    }
                    if let Some(l) = labels {
                        write!(out, " {}", l[k])?;
                    }
                    writeln!(out)?;
                }
            }
            PcdEncoding::Binary if colors.is_none() && labels.is_none() => {
                self.write_xyz_f32_le(out)?
            }
            PcdEncoding::Binary => {
                let mut buf = Vec::with_capacity(n * 20);
                for (k, p) in self.points.iter().enumerate() {
                    for v in [p.x, p.y, p.z] {
                        buf.extend_from_slice(&(v as f32).to_le_bytes());
                    }
                    if let Some(c) = packed(k) {
                        buf.extend_from_slice(&c.to_le_bytes());
                    }
                    if let Some(l) = labels {
                        buf.extend_from_slice(&l[k].to_le_bytes());
                    }
                }
                out.write_all(&buf)?;
            }
        }
        Ok(())
    }
}

/// What a PCD file may carry beside the points: the sensor's pose and, one per point,
/// colours and labels.
#[derive(Debug, Clone, Copy)]
pub struct PcdExtras<'a> {
    pub viewpoint: Pose,
    pub colors: Option<&'a [[u8; 3]]>,
    pub labels: Option<&'a [u32]>,
}

impl Default for PcdExtras<'_> {
    fn default() -> Self {
        Self {
            viewpoint: Pose::IDENTITY,
            colors: None,
            labels: None,
        }
    }
}

/// The integer cell of a cubic grid of edge `size` that holds `p` (floor division):
/// the one voxel key of occupancy maps, clusters and masks.
/// The axis-aligned box (lowest corner, highest corner) of `points`; inverted
/// (+∞, −∞) when there are none.
pub fn bounds<'a>(points: impl IntoIterator<Item = &'a crate::Vec3>) -> (crate::Vec3, crate::Vec3) {
    points.into_iter().fold(
        (
            crate::Vec3::splat(f64::INFINITY),
            crate::Vec3::splat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

pub fn voxel_key(p: crate::Vec3, size: f64) -> [i64; 3] {
    [
        (p.x / size).floor() as i64,
        (p.y / size).floor() as i64,
        (p.z / size).floor() as i64,
    ]
}

/// [`voxel_key`] packed into one integer, 21 bits per axis: a cheaper hash key, unique
/// while every coordinate is within 2²⁰ voxels of the origin (±10 km at 1 cm); farther
/// cells wrap around onto nearer ones.
pub fn packed_voxel_key(p: crate::Vec3, size: f64) -> u64 {
    const MASK: u64 = (1 << 21) - 1;
    let [x, y, z] = voxel_key(p, size);
    ((x as u64 & MASK) << 42) | ((y as u64 & MASK) << 21) | (z as u64 & MASK)
}

#[cfg(test)]
mod tests {

    #[test]
    fn packed_voxel_keys_tell_neighbouring_cells_apart_on_both_sides_of_zero() {
        let leaf = 0.01;
        let mut seen = std::collections::HashSet::new();
        for x in -3..3 {
            for y in -3..3 {
                for z in -3..3 {
                    let p = crate::Vec3::new(x as f64, y as f64, z as f64) * leaf
                        + crate::Vec3::splat(0.004);
                    assert!(seen.insert(packed_voxel_key(p, leaf)), "{p:?}");
                    // Anywhere in the same cell, the same key.
                    let q = p + crate::Vec3::splat(0.005);
                    assert_eq!(packed_voxel_key(p, leaf), packed_voxel_key(q, leaf));
                }
            }
        }
    }
    #[test]
    fn decimation_keeps_the_grid() {
        let pts: Vec<crate::Vec3> = (0..15)
            .map(|i| crate::Vec3::new(i as f64, 0.0, 0.0))
            .collect();
        let c = PointCloud::organized(5, 3, pts).unwrap();
        let d = c.decimated(2);
        assert_eq!((d.width, d.height), (3, 2));
        let xs: Vec<f64> = d.points.iter().map(|p| p.x).collect();
        assert_eq!(xs, vec![0.0, 2.0, 4.0, 10.0, 12.0, 14.0]);
        assert_eq!(c.decimated(1).points.len(), 15);
        assert_eq!(
            PointCloud::unorganized(vec![crate::Vec3::ZERO; 10])
                .decimated(2)
                .points
                .len(),
            3
        );
    }

    use super::*;

    #[test]
    fn pcd_header_and_nan_points() {
        let c = PointCloud::organized(2, 1, vec![Vec3::new(1.0, 2.0, 3.0), Vec3::NAN]).unwrap();
        let mut out = Vec::new();
        c.write_pcd(&mut out, PcdEncoding::Ascii).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(
            text.contains("WIDTH 2\nHEIGHT 1\n")
                && text.contains("POINTS 2\nDATA ascii\n1 2 3\nnan nan nan\n")
        );
        let mut bin = Vec::new();
        c.write_pcd(&mut bin, PcdEncoding::Binary).unwrap();
        assert_eq!(
            bin.len() - text.find("1 2 3").unwrap() - "binary".len() + "ascii".len(),
            24
        );
        assert!(PointCloud::organized(3, 1, vec![Vec3::ZERO]).is_none());
    }
}
