//! What a scene may not do with its robots: place an object inside one (the physics
//! would shove it away at the first step and a task would start from a world the file
//! never described), or give an object or furniture a robot's or a link's name (a name
//! that means two things at once).

use super::*;

impl SimWorld {
    /// Objects and furniture named as a robot or one of its links are refused.
    pub(super) fn check_names_apart_from_robots(&self) -> Result<(), SimError> {
        for e in self.live_entities() {
            if !matches!(e.kind, EntityKind::Object | EntityKind::Furniture) {
                continue;
            }
            for r in &self.robots {
                if e.name == r.name || r.model.link(&e.name).is_ok() {
                    return Err(SimError::Robot(format!(
                        "`{}` is the name of robot `{}`{}: name it otherwise",
                        e.name,
                        r.name,
                        if e.name == r.name { "" } else { "'s link" }
                    )));
                }
            }
        }
        Ok(())
    }

    /// Every object but those in `held` stays out of the robots' links (deeper than a
    /// scene may place bodies into each other, [`saved::MAX_LOAD_OVERLAP`]).
    pub(super) fn check_objects_clear_of_robots(&self, held: &[&str]) -> Result<(), SimError> {
        let bounds = |e: &Entity| {
            let body = &self.physics.bodies[e.body];
            body.colliders()
                .iter()
                .map(|&c| self.physics.colliders[c].compute_aabb())
                .reduce(|a, b| a.merged(&b))
        };
        let links: Vec<(&Entity, _)> = self
            .live_entities()
            .filter(|e| e.kind == EntityKind::RobotLink)
            .filter_map(|e| Some((e, bounds(e)?)))
            .collect();
        for o in self.live_entities() {
            if o.kind != EntityKind::Object || held.contains(&o.name.as_str()) {
                continue;
            }
            let Some(ob) = bounds(o) else { continue };
            for (link, lb) in &links {
                if ob.intersects(lb)
                    && self
                        .overlap(&o.name, &link.name)
                        .is_some_and(|d| d < -saved::MAX_LOAD_OVERLAP)
                {
                    return Err(SimError::Overlap {
                        new: o.name.clone(),
                        existing: link.name.clone(),
                    });
                }
            }
        }
        Ok(())
    }
}
