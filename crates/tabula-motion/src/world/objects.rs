//! The world's objects: fixed obstacles (shapes, meshes, boxes, occupancy), their
//! bounding-volume tree, and objects attached to a link.

use super::*;
use tabula_geom::parry::bounding_volume::BoundingVolume;

/// Scenes with at most this many objects are searched box by box.
const LINEAR_SCAN_OBJECTS: usize = 32;

impl CollisionWorld {
    /// Adds a fixed object.
    pub fn add_object(
        &mut self,
        name: &str,
        shape: SharedShape,
        world_from_object: Pose,
    ) -> Result<(), WorldError> {
        self.add_objects(vec![(name.to_string(), shape, world_from_object)])
    }

    /// Adds fixed objects (names unique among them and in the world), rebuilding the
    /// broad phase once: objects may overlap one another, they are static.
    pub fn add_objects(
        &mut self,
        objects: Vec<(String, SharedShape, Pose)>,
    ) -> Result<(), WorldError> {
        let mut taken: HashSet<&str> = self
            .objects
            .iter()
            .map(|o| o.name.as_str())
            .chain(self.attached.iter().map(|o| o.name.as_str()))
            .collect();
        for (name, _, pose) in &objects {
            if !taken.insert(name) {
                return Err(WorldError::NameTaken(name.clone()));
            }
            if !tabula_geom::pose_is_finite(pose) {
                return Err(WorldError::NonFinite);
            }
        }
        for (name, shape, world_from_object) in objects {
            let aabb = shape.compute_aabb(&world_from_object);
            self.objects.push(WorldObject {
                name,
                shape,
                world_from_object,
                aabb,
                allowed_bodies: Vec::new(),
            });
        }
        self.rebuild_bvh();
        Ok(())
    }

    /// The objects' boxes and their BVH, after any change to the objects (indices into
    /// both are the objects' own).
    pub(super) fn rebuild_bvh(&mut self) {
        self.object_boxes = self.objects.iter().map(|o| o.aabb).collect();
        self.objects_bvh = Bvh::from_leaves(BvhBuildStrategy::default(), &self.object_boxes);
    }

    /// World objects whose boxes meet `aabb` (through the BVH).
    pub(super) fn objects_near<'a>(
        &'a self,
        aabb: &'a Aabb,
    ) -> impl Iterator<Item = &'a WorldObject> + 'a {
        self.object_indices_near(aabb)
            .filter_map(|i| self.objects.get(i))
    }

    /// Indices of the world objects whose boxes meet `aabb`: a pass over the boxes for a
    /// scene of a few dozen objects (a BVH walk costs more than that), the BVH beyond.
    pub(super) fn object_indices_near<'a>(
        &'a self,
        aabb: &'a Aabb,
    ) -> impl Iterator<Item = usize> + 'a {
        if self.objects.len() <= LINEAR_SCAN_OBJECTS {
            NearObjects::Scan(self.object_boxes.iter().enumerate(), aabb)
        } else {
            NearObjects::Walk(self.objects_bvh.intersect_aabb(aabb))
        }
    }

    /// A mesh file (OBJ or STL) as a world object: its convex hull, or with `decompose`
    /// a V-HACD convex decomposition that keeps its concavities (a shelf, a bin).
    pub fn add_mesh(
        &mut self,
        name: &str,
        path: &std::path::Path,
        scale: Vec3,
        world_from_mesh: Pose,
        decompose: bool,
    ) -> Result<(), WorldError> {
        let (points, triangles) = tabula_geom::mesh::load_mesh(path, scale.to_array())
            .map_err(|e| WorldError::Robot(e.to_string()))?;
        let shape = if decompose && !triangles.is_empty() {
            let (p, t) = (points.clone(), triangles.clone());
            tabula_geom::guard::catch_quietly(move || SharedShape::convex_decomposition(&p, &t))
                .map_err(|_| {
                    WorldError::Robot(format!("{}: convex decomposition failed", path.display()))
                })?
        } else {
            SharedShape::convex_hull(&points).ok_or_else(|| {
                WorldError::Robot(format!(
                    "{}: degenerate mesh, no convex hull",
                    path.display()
                ))
            })?
        };
        self.add_object(name, shape, world_from_mesh)
    }

    /// A box (full sizes) at a pose — the common case.
    pub fn add_box(
        &mut self,
        name: &str,
        size: Vec3,
        world_from_box: Pose,
    ) -> Result<(), WorldError> {
        self.add_object(
            name,
            SharedShape::cuboid(size.x / 2.0, size.y / 2.0, size.z / 2.0),
            world_from_box,
        )
    }

    /// An occupancy map from a point cloud (world frame, NaN points skipped): every
    /// occupied `voxel`-sized cell is covered, all of it one compound object whose own
    /// bounding-volume hierarchy keeps queries fast (the role of MoveIt's octomap).
    /// Cells are merged greedily into boxes — runs along x, then equal runs along y —
    /// so a table top or a shelf board is a handful of boxes, not thousands of cubes;
    /// each box is the bounding box of the points in its cells (at least `voxel / 4`
    /// thick), not of the cells, so a surface is not raised by up to a voxel.
    /// Returns the number of occupied cells.
    pub fn add_occupancy(
        &mut self,
        name: &str,
        world_points: &[Vec3],
        voxel: f64,
    ) -> Result<usize, WorldError> {
        if !(voxel.is_finite() && voxel > 0.0) {
            return Err(WorldError::NonFinite);
        }
        let key = |p: &Vec3| tabula_geom::voxel_key(*p, voxel);
        // Sorted by z, then y, then x, so x-runs are consecutive.
        let mut cells: Vec<([i64; 3], Vec3, Vec3)> = Vec::new();
        let mut keyed: Vec<([i64; 3], Vec3)> = world_points
            .iter()
            .filter(|p| p.is_finite())
            .map(|p| (key(p), *p))
            .collect();
        keyed.sort_unstable_by_key(|(c, _)| (c[2], c[1], c[0]));
        for (c, p) in keyed {
            match cells.last_mut() {
                Some((k, lo, hi)) if *k == c => {
                    *lo = lo.min(p);
                    *hi = hi.max(p);
                }
                _ => cells.push((c, p, p)),
            }
        }
        if cells.is_empty() {
            return Ok(0);
        }
        let count = cells.len();
        // Runs along x: (z, y, x0, x1, lo, hi).
        let mut runs: Vec<(i64, i64, i64, i64, Vec3, Vec3)> = Vec::new();
        for (c, lo, hi) in &cells {
            match runs.last_mut() {
                Some(r) if r.0 == c[2] && r.1 == c[1] && r.3 + 1 == c[0] => {
                    r.3 = c[0];
                    r.4 = r.4.min(*lo);
                    r.5 = r.5.max(*hi);
                }
                _ => runs.push((c[2], c[1], c[0], c[0], *lo, *hi)),
            }
        }
        // Equal x-runs on consecutive y rows merge: (z, x0, x1, y1, lo, hi).
        runs.sort_unstable_by_key(|r| (r.0, r.2, r.3, r.1));
        let mut boxes: Vec<(i64, i64, i64, i64, Vec3, Vec3)> = Vec::new();
        for r in &runs {
            match boxes.last_mut() {
                Some(b) if b.0 == r.0 && b.1 == r.2 && b.2 == r.3 && b.3 + 1 == r.1 => {
                    b.3 = r.1;
                    b.4 = b.4.min(r.4);
                    b.5 = b.5.max(r.5);
                }
                _ => boxes.push((r.0, r.2, r.3, r.1, r.4, r.5)),
            }
        }
        let min_half = voxel / 8.0;
        let parts: Vec<(Pose, SharedShape)> = boxes
            .iter()
            .map(|&(_, _, _, _, lo, hi)| {
                let half = ((hi - lo) / 2.0).max(Vec3::splat(min_half));
                (
                    Pose::from_translation((lo + hi) / 2.0),
                    SharedShape::cuboid(half.x, half.y, half.z),
                )
            })
            .collect();
        self.add_object(name, SharedShape::compound(parts), Pose::IDENTITY)?;
        Ok(count)
    }

    /// Every colliding pair at `q` (names), not only the first.
    pub fn contacts(&self, q: &[f64]) -> Result<Vec<(String, String)>, WorldError> {
        let mut out = Vec::new();
        let mut probe = self.clone();
        // Remove each reported object (or allow the reported link pair) and ask again.
        while let Some((a, b)) = probe.first_collision(q)? {
            out.push((a.clone(), b.clone()));
            if a == "joint limits" {
                break;
            }
            if probe.objects.iter().any(|o| o.name == b) {
                probe.objects.retain(|o| o.name != b);
                probe.rebuild_bvh();
            } else if let (Some(x), Some(y)) = (
                probe.bodies.iter().position(|l| l.name == a),
                probe.bodies.iter().position(|l| l.name == b),
            ) {
                let n = probe.bodies.len();
                probe.allowed_matrix[x * n + y] = true;
                probe.allowed_matrix[y * n + x] = true;
                probe.rebuild_body_index();
            } else if probe.attached.iter().any(|o| o.name == a) {
                probe.attached.retain(|o| o.name != a);
            } else {
                break;
            }
        }
        Ok(out)
    }

    pub fn remove_object(&mut self, name: &str) -> Result<(), WorldError> {
        let before = self.objects.len() + self.attached.len();
        self.objects.retain(|o| o.name != name);
        self.attached.retain(|o| o.name != name);
        self.rebuild_bvh();
        if before == self.objects.len() + self.attached.len() {
            return Err(WorldError::UnknownObject(name.into()));
        }
        Ok(())
    }

    /// Attaches an object to `link` (it moves with it); `touch_links` may touch it.
    pub fn attach(
        &mut self,
        name: &str,
        shape: SharedShape,
        link: &str,
        link_from_object: Pose,
        touch_links: &[&str],
    ) -> Result<(), WorldError> {
        let li = self.model.link(link)?;
        let body = match self.bodies.iter().position(|b| b.link == li) {
            Some(b) => b,
            None => {
                self.bodies.push(LinkBody {
                    link: li,
                    padding: self
                        .params
                        .link_padding
                        .get(link)
                        .copied()
                        .unwrap_or(self.params.padding),
                    name: link.into(),
                    shapes: Vec::new(),
                    covers: Vec::new(),
                    hulls: Vec::new(),
                    outer: None,
                    moving: true,
                    bound: None,
                });
                let root_poses = self.model.forward_kinematics(&self.values)?;
                self.anchors
                    .push(self.anchor_for(self.bodies.len() - 1, &root_poses));
                self.rebuild_allowed_matrix();
                self.bodies.len() - 1
            }
        };
        let mut touch = vec![body];
        for t in touch_links {
            let tl = self.model.link(t)?;
            if let Some(b) = self.bodies.iter().position(|b| b.link == tl) {
                touch.push(b);
            }
        }
        self.attached.push(Attached {
            name: name.into(),
            shape,
            link_from_object,
            body,
            touch,
        });
        self.tighten_motion_radius();
        if self.bodies.len() != self.pair_tables.bodies() {
            self.pair_tables = PairTables::build(self);
        }
        Ok(())
    }
}

/// [`CollisionWorld::object_indices_near`]'s two ways, one iterator. The scan reads
/// the packed boxes, not whole objects; a BVH walk carries a traversal stack of a few
/// hundred bytes, which an `Option`-and-`chain` of both copied three times over on
/// every call (a tenth of a check's time, profiled).
enum NearObjects<'a, W> {
    Scan(std::iter::Enumerate<std::slice::Iter<'a, Aabb>>, &'a Aabb),
    Walk(W),
}

impl<W: Iterator<Item = u32>> Iterator for NearObjects<'_, W> {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        match self {
            NearObjects::Scan(objects, aabb) => {
                objects.find(|(_, b)| b.intersects(aabb)).map(|(i, _)| i)
            }
            NearObjects::Walk(leaves) => leaves.next().map(|i| i as usize),
        }
    }
}
