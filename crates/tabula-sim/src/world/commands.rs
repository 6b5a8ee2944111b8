//! The scene commands on a running world (spawn, move, put on a surface, delete) and
//! the world written back as a scene.

use super::*;

impl SimWorld {
    /// Spawns catalogue model `model` named `name` at `xyz` (upright).
    pub fn spawn(&mut self, model: &str, name: &str, xyz: [f64; 3]) -> Result<(), SimError> {
        let (shape, mass) = model_shape(model).ok_or_else(|| SimError::UnknownModel {
            name: model.into(),
            valid: MODELS
                .iter()
                .map(|(n, _)| *n)
                .collect::<Vec<_>>()
                .join(", "),
        })?;
        if xyz
            .iter()
            .any(|v| !v.is_finite() || v.abs() > crate::scene::MAX_COORDINATE)
        {
            return Err(SimError::NonFinite);
        }
        let text = format!("name = \"{}\"", name.replace('"', ""));
        let spanned_name: crate::scene::NameOnly =
            toml::from_str(&text).map_err(|_| SimError::UnknownEntity(name.into()))?;
        let spec = ObjectSpec {
            name: spanned_name.name,
            shape,
            pose: PoseSpec { xyz, rpy: [0.0; 3] },
            mass: Some(mass),
            density: None,
            friction: 0.8,
            color: [0.3, 0.5, 0.8],
        };
        self.add_object(&spec)?;
        self.source.objects.push(spec);
        Ok(())
    }

    /// Moves an object (teleport, velocities zeroed).
    pub fn move_to(&mut self, name: &str, world_from_object: Pose) -> Result<(), SimError> {
        if !(world_from_object.translation.is_finite() && world_from_object.rotation.is_finite())
            || world_from_object.translation.abs().max_element() > crate::scene::MAX_COORDINATE
        {
            return Err(SimError::NonFinite);
        }
        let i = self
            .entity(name)
            .ok_or_else(|| SimError::UnknownEntity(name.into()))?;
        let b = &mut self.physics.bodies[self.entities[i].body];
        b.set_position(world_from_object, true);
        b.set_linvel(Vec3::ZERO, true);
        b.set_angvel(Vec3::ZERO, true);
        Ok(())
    }

    /// Puts an object on whatever surface is below it: it keeps x, y and orientation
    /// and is lowered until it touches (the seed's "put on surface" script).
    pub fn put_on_surface(&mut self, name: &str) -> Result<(), SimError> {
        let i = self
            .entity(name)
            .ok_or_else(|| SimError::UnknownEntity(name.into()))?;
        let handle = self.entities[i].body;
        let pose = *self.physics.bodies[handle].position();
        let colliders: Vec<ColliderHandle> = self.physics.bodies[handle].colliders().to_vec();
        let Some(&ch) = colliders.first() else {
            return Err(SimError::NoSurfaceBelow(name.into()));
        };
        let collider = &self.physics.colliders[ch];
        let shape = collider.shared_shape().clone();
        let local = *collider.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
        // Cast the object's shape straight down against everything else.
        let mut best: Option<f64> = None;
        for (h, c) in self.physics.colliders.iter() {
            if colliders.contains(&h) {
                continue;
            }
            let hit = rapier3d_f64::parry::query::cast_shapes(
                &(pose * local),
                Vec3::new(0.0, 0.0, -1.0),
                shape.as_ref(),
                c.position(),
                Vec3::ZERO,
                c.shape(),
                rapier3d_f64::parry::query::ShapeCastOptions::with_max_time_of_impact(50.0),
            )
            .ok()
            .flatten();
            if let Some(hit) = hit {
                best = Some(best.map_or(hit.time_of_impact, |b: f64| b.min(hit.time_of_impact)));
            }
        }
        let drop = best.ok_or_else(|| SimError::NoSurfaceBelow(name.into()))?;
        let placed = Pose::from_parts(
            pose.translation - Vec3::new(0.0, 0.0, drop - 1e-4),
            pose.rotation,
        );
        self.move_to(name, placed)
    }

    /// Removes an entity.
    pub fn delete(&mut self, name: &str) -> Result<(), SimError> {
        let i = self
            .entity(name)
            .ok_or_else(|| SimError::UnknownEntity(name.into()))?;
        let e = self.entities[i].clone();
        if e.kind == EntityKind::RobotLink {
            return Err(SimError::Robot(format!(
                "`{name}` is part of a robot; robots cannot be deleted link by link"
            )));
        }
        self.physics.remove_body_with_colliders(e.body, true);
        self.attachments.retain(|a| a.object != e.name);
        // Keep labels stable: the slot stays, renamed, with no body left.
        self.entities[i].name = format!("__deleted_{}", e.name);
        self.entities[i].deleted = true;
        self.source.objects.retain(|o| o.name.get_ref() != name);
        self.source.furniture.retain(|f| f.name.get_ref() != name);
        Ok(())
    }

    /// The world now as a scene: objects where they are, robots at their joint values,
    /// mesh paths made absolute so the file loads from wherever it is written.
    pub fn to_scene(&self) -> Scene {
        let mut scene = self.source.clone();
        let absolute = |path: &mut String| {
            if let Some(d) = &self.base_dir
                && Path::new(path.as_str()).is_relative()
            {
                let full = d.join(path.as_str());
                *path = std::fs::canonicalize(&full)
                    .unwrap_or(full)
                    .display()
                    .to_string();
            }
        };
        let pose_spec = |p: Pose| PoseSpec {
            xyz: p.translation.to_array(),
            rpy: tabula_geom::rpy_from_quat(p.rotation),
        };
        let held: Vec<String> = self
            .robots
            .iter()
            .flat_map(|r| self.held_objects(&r.name))
            .collect();
        let saved = self.saved_object_poses(&held);
        for o in &mut scene.objects {
            if let Some((_, p)) = saved.iter().find(|(n, _)| n == o.name.get_ref()) {
                o.pose = pose_spec(*p);
            }
            if let ShapeSpec::Mesh { path, .. } = &mut o.shape {
                absolute(path);
            }
        }
        for r in &mut scene.robots {
            if let Ok(placed) = self.robot(r.name.get_ref()) {
                r.joints = placed
                    .model
                    .joints
                    .iter()
                    .enumerate()
                    .filter(|(_, j)| j.kind.is_single_axis() && j.mimic.is_none())
                    .map(|(i, j)| (j.name.clone(), placed.values[i]))
                    .collect();
                r.pose = pose_spec(placed.world_from_root);
                let held = self.held_objects(placed.name.as_str());
                if let Some(h) = &mut r.hold {
                    if held.contains(&h.object) {
                        let tool = self.link_pose(&placed.name, &h.tool_link);
                        let object = self.pose(&h.object);
                        if let (Ok(t), Ok(o)) = (tool, object) {
                            h.tool_from_object = Some(pose_spec(t.inverse() * o));
                        }
                    } else {
                        r.hold = None;
                    }
                }
            }
            if Path::new(&r.urdf).extension().is_some() {
                absolute(&mut r.urdf);
            }
        }
        scene.base_dir = None;
        scene
    }

    /// Names of the entities of one kind (`None` = all).
    pub fn list(&self, kind: Option<EntityKind>) -> Vec<String> {
        self.entities
            .iter()
            .filter(|e| kind.is_none_or(|k| e.kind == k) && !e.deleted)
            .map(|e| e.name.clone())
            .collect()
    }
}
