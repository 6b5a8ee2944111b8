//! Rolling resistance, which the physics engine does not model.
//!
//! Without it a can lying on the table and nudged rolls on for ever; worse, rapier's
//! rolling contact (measured with a cylinder on a box) feeds a slowly rolling can
//! energy (one set rolling at 2 cm/s speeds up to 5.3 cm/s and keeps that pace across
//! any table, see `rolling_tests`). A viscous spin damping (1/s, used before) only slows a can to
//! that pace: cans left the table after a neighbour was lifted from beside them.
//!
//! The model is Coulomb's, as MuJoCo's rolling friction: an object touching something
//! feels a torque against its spin of at most `c_rr · m · g · r` (r the radius it rolls
//! on), which stops it rather than slowing it exponentially. A lying can set rolling at
//! v stops after v² / (2 · ⅔ · c_rr · g): 7.6 cm from 10 cm/s at c_rr = 0.01.

use super::{EntityKind, SimWorld};

impl SimWorld {
    /// Applies one step of rolling resistance: every object touching something has its
    /// angular velocity reduced, along its spin, by the torque `c_rr · m · g · r` over
    /// its inertia about that axis, and never past zero. Objects in the air are free.
    pub(super) fn resist_rolling(&mut self) {
        let c_rr = self.params.rolling_resistance;
        // Off at 0, and for a value that is not a number rather than stopping every spin.
        if c_rr.is_nan() || c_rr <= 0.0 {
            return;
        }
        let c_rr = c_rr.min(1.0);
        let g = self.physics.gravity.length();
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
        let dt = self.physics.integration_parameters.dt;
        for e in self
            .entities
            .iter()
            .filter(|e| e.kind == EntityKind::Object && !e.deleted && touching.contains(&e.body))
        {
            let radius = e.rolling_radius;
            let Some(b) = self.physics.bodies.get_mut(e.body) else {
                continue;
            };
            let spin = b.angvel();
            let speed = spin.length();
            if !b.is_dynamic() || speed < 1e-12 || !speed.is_finite() {
                continue;
            }
            let axis = spin / speed;
            // The spin a torque impulse along `axis` takes away, per unit of impulse.
            let inv_inertia = axis.dot(b.mass_properties().effective_world_inv_inertia * axis);
            let torque = c_rr * b.mass() * g * radius;
            let slowed = (speed - torque * dt * inv_inertia).max(0.0);
            b.set_angvel(axis * slowed, false);
        }
    }

    /// The radius an object rolls on: the smallest half-extent of its colliders' local
    /// bounds (a lying cylinder's radius, a ball's radius, a box's half thickness),
    /// computed once when the object enters the world.
    pub(super) fn rolling_radius(&self, body: rapier3d_f64::prelude::RigidBodyHandle) -> f64 {
        let Some(b) = self.physics.bodies.get(body) else {
            return 0.0;
        };
        b.colliders()
            .iter()
            .filter_map(|&c| self.physics.colliders.get(c))
            .filter(|c| !super::is_support_piece(c.user_data))
            .map(|c| {
                let half = c.shared_shape().compute_local_aabb().half_extents();
                half.x.min(half.y).min(half.z)
            })
            .fold(0.0, f64::max)
    }
}
