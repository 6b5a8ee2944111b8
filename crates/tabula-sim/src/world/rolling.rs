//! Rolling resistance, which the physics engine does not model.

use super::{EntityKind, SimWorld};

/// Angular damping (1/s) of an object touching something: a can rolling at 10 cm/s
/// stops within about 10 cm, as with a rolling-resistance coefficient near 0.01
/// (rubber or cardboard on wood); an object tipping over an edge (angular
/// accelerations of 100 rad/s² and more) is not noticeably slowed.
pub const ROLLING_DAMPING: f64 = 1.0;

impl SimWorld {
    /// Rolling resistance, which the physics lacks (a lying can pushed at 10 cm/s
    /// would roll on for ever, off the table and across the floor): objects touching
    /// something have their spin damped by [`ROLLING_DAMPING`]; in the air they are not.
    pub(super) fn resist_rolling(&mut self) {
        let mut touching = rustc_hash::FxHashSet::default();
        for pair in self.physics.narrow_phase.contact_pairs() {
            if pair.has_any_active_contact() {
                for c in [pair.collider1, pair.collider2] {
                    if let Some(body) = self.physics.colliders.get(c).and_then(|c| c.parent()) {
                        touching.insert(body);
                    }
                }
            }
        }
        for e in self
            .entities
            .iter()
            .filter(|e| e.kind == EntityKind::Object && !e.deleted)
        {
            let want = if touching.contains(&e.body) {
                ROLLING_DAMPING
            } else {
                0.0
            };
            if let Some(b) = self.physics.bodies.get(e.body)
                && b.is_dynamic()
                && b.angular_damping() != want
                && let Some(b) = self.physics.bodies.get_mut(e.body)
            {
                b.set_angular_damping(want);
            }
        }
    }
}
