//! Placing's parameters (SPEC §1 and §6), loadable from TOML.

use crate::observe::ObserveParams;
use crate::stable::StableParams;
use tabula_geom::input::{
    Validate, check_count, check_in, check_non_negative, check_positive, nested,
};
use tabula_motion::MoveGroupParams;
use tabula_perception::freespace::FreeSpaceParams;
use tabula_perception::surfaces::SurfaceParams;

/// Parameters of placing (SPEC §1 and §6).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlaceParams {
    pub observe: ObserveParams,
    pub motion: MoveGroupParams,
    pub stable: StableParams,
    pub surfaces: SurfaceParams,
    pub free_space: FreeSpaceParams,
    /// The head camera.
    pub camera: String,
    /// Where the object is held to be scanned: this far in front of the camera (m) …
    pub scan_distance: f64,
    /// … and this far below it (m).
    pub scan_drop: f64,
    /// Directions (in the tool frame) the camera looks at the object from: SPEC §1.1's
    /// lateral views, the top, and views from below the hand.
    pub scan_views: Vec<[f64; 3]>,
    /// Twists about the line of sight tried per view (the arm reaches some).
    pub scan_twists: usize,
    /// Other places to hold the object for the views the arm cannot show at the scan
    /// position: (forward, left, up) from it in the base's heading (m), tried in turn.
    pub scan_shifts: Vec<[f64; 3]>,
    /// Points farther than this from the tool are not the object (m), SPEC §1.1: 40 cm.
    pub crop_radius: f64,
    /// The scan is downsampled to this leaf (m), SPEC §6: 5 mm.
    pub scan_leaf: f64,
    /// A cluster with a point this close to the tool frame is the held object (m).
    pub grip_reach: f64,
    /// Protective sphere radius while the object is unknown (m), SPEC §6: 0.20 m.
    pub protective_radius: f64,
    /// Stable poses whose topple tilt is below this are not used (deg): the seed's
    /// objects placed near an edge of their support fell when the gripper opened.
    pub min_topple_deg: f64,
    /// The gripper must stay this far above the surface at release (m), Alg. 6.
    pub gripper_clearance: f64,
    /// Stable poses tried, best first.
    pub poses_tried: usize,
    /// Head pan angles of the surface sweep (rad), SPEC §6: −90°…+90° in 45° steps …
    pub sweep_pans: Vec<f64>,
    /// … looking at points this far out (m) at this height (m).
    pub sweep_distance: f64,
    pub sweep_height: f64,
    /// Surface search leaf (m) and range (m): the seed worked to 3.5 m.
    pub search_leaf: f64,
    pub search_range: f64,
    /// Surface points seen from at most this far (m) draw the free-space map's edges
    /// once there are enough of them: a depth camera's range noise grows with the
    /// square of the range (Kinect σ ≈ 1.5 mm·z², SPEC §5: 4 mm at 1.6 m, 13 mm at
    /// 3 m), and a table seen from across the room reaches centimetres past its edge.
    pub edge_range: f64,
    /// Search frames keep every `search_decimate`-th pixel of every such row.
    pub search_decimate: usize,
    /// Looks at an accepted surface's centroid that refine it, SPEC §6: 3 (at most) …
    pub refine_looks: usize,
    /// … stopping once a look moves the centroid less than this (m): the next look
    /// would be aimed at the same spot and see the same. Not in the seed.
    pub refine_converged: f64,
    /// Turn the base around and sweep again when nothing fits in front.
    pub turn_around: bool,
    /// Spots farther than this from the arm's shoulder are out of reach (m), Alg. 11.
    pub reach: f64,
    /// Gap kept between the base and the surface's edge when driving up to it (m).
    pub standoff: f64,
    /// The base turns to face the surface this far back from its goal, then drives
    /// straight in (m).
    pub approach_run: f64,
    /// Roll angles about the support normal per spot, SPEC §6: 10.
    pub roll_samples: usize,
    /// The object's lowest point at most this far above the surface when released
    /// (m), SPEC §6: 8 mm …
    pub release_height: f64,
    /// … and at least this far: lower where the hand stays `gripper_clearance` above
    /// the surface there. A drop of 8 mm sets a mug held by its rim or a cone on its
    /// side rocking; this is what the model's support plane is uncertain by (the
    /// scan's depth noise, ≈ 0.5 mm at the scan's 0.6 m, and a held object's slip).
    /// Not in the seed.
    pub release_height_min: f64,
    /// Free margin around the resting footprint: to edges, objects, unseen cells (m).
    pub place_margin: f64,
    /// Approach from above the spot: desired and minimum (m), SPEC §6: 0.2 / 0.1.
    pub approach_desired: f64,
    pub approach_min: f64,
    /// Retreat after release: desired and minimum (m), SPEC §6: 0.25 / 0.1.
    pub retreat_desired: f64,
    pub retreat_min: f64,
    /// Spots (with IK) planned at most before giving up.
    pub max_planned: usize,
    /// Raise the torso fully before anything else, seed 000 §1.6 (its `torso_up`
    /// defaults to true, following Willow Garage's advice for the PR2).
    pub raise_torso: bool,
    /// The finger gap grows at most this fast when releasing (m/s): a gentle release,
    /// fingers parting from the object rather than snapping off it.
    pub release_speed: f64,
}

impl Default for PlaceParams {
    fn default() -> Self {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        Self {
            observe: ObserveParams {
                max_range: 3.5,
                ..ObserveParams::default()
            },
            motion: MoveGroupParams {
                cartesian_tolerance: 0.01,
                ..MoveGroupParams::default()
            },
            stable: StableParams::default(),
            surfaces: SurfaceParams {
                height_range: [0.25, 1.3],
                ..SurfaceParams::default()
            },
            free_space: FreeSpaceParams::default(),
            camera: "head".into(),
            scan_distance: 0.6,
            scan_drop: 0.3,
            scan_views: vec![
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
                [1.0, 0.0, 0.0],
                [-0.5, 0.87, 0.0],
                [-0.5, -0.87, 0.0],
                [-0.5, 0.0, 0.87],
                [-0.5, 0.0, -0.87],
                [s, s, 0.0],
                [s, -s, 0.0],
            ],
            scan_twists: 4,
            scan_shifts: vec![
                [-0.15, 0.3, 0.0],
                [-0.15, -0.3, 0.0],
                [-0.25, 0.35, 0.1],
                [-0.25, -0.35, 0.1],
            ],
            crop_radius: 0.4,
            scan_leaf: 0.005,
            grip_reach: 0.05,
            protective_radius: 0.20,
            min_topple_deg: 8.0,
            gripper_clearance: 0.003,
            poses_tried: 3,
            sweep_pans: [-90.0f64, -45.0, 0.0, 45.0, 90.0]
                .iter()
                .map(|d| d.to_radians())
                .collect(),
            sweep_distance: 1.6,
            sweep_height: 0.45,
            search_leaf: 0.01,
            search_range: 3.5,
            edge_range: 1.6,
            search_decimate: 2,
            refine_looks: 3,
            refine_converged: 0.01,
            turn_around: true,
            reach: 0.75,
            standoff: 0.06,
            approach_run: 0.5,
            roll_samples: 10,
            release_height: 0.008,
            release_height_min: 0.003,
            place_margin: 0.02,
            approach_desired: 0.2,
            approach_min: 0.1,
            retreat_desired: 0.25,
            retreat_min: 0.1,
            max_planned: 12,
            raise_torso: true,
            release_speed: 0.02,
        }
    }
}

impl Validate for PlaceParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.observe.check(&nested(at, "observe"))?;
        self.motion.check(&nested(at, "motion"))?;
        self.stable.check(&nested(at, "stable"))?;
        self.surfaces.check(&nested(at, "surfaces"))?;
        self.free_space.check(&nested(at, "free_space"))?;
        for (name, v) in [
            ("scan_distance", self.scan_distance),
            ("crop_radius", self.crop_radius),
            ("scan_leaf", self.scan_leaf),
            ("search_leaf", self.search_leaf),
            ("search_range", self.search_range),
            ("edge_range", self.edge_range),
            ("reach", self.reach),
            ("approach_desired", self.approach_desired),
            ("retreat_desired", self.retreat_desired),
            ("release_speed", self.release_speed),
        ] {
            check_positive(at, name, v)?;
        }
        for (name, v) in [
            ("scan_drop", self.scan_drop),
            ("refine_converged", self.refine_converged),
            ("grip_reach", self.grip_reach),
            ("protective_radius", self.protective_radius),
            ("gripper_clearance", self.gripper_clearance),
            ("sweep_distance", self.sweep_distance),
            ("sweep_height", self.sweep_height),
            ("standoff", self.standoff),
            ("approach_run", self.approach_run),
            ("release_height", self.release_height),
            ("place_margin", self.place_margin),
            ("approach_min", self.approach_min),
            ("retreat_min", self.retreat_min),
        ] {
            check_non_negative(at, name, v)?;
        }
        check_in(at, "min_topple_deg", self.min_topple_deg, 0.0, 90.0)?;
        check_in(
            at,
            "release_height_min",
            self.release_height_min,
            0.0,
            self.release_height,
        )?;
        check_in(
            at,
            "approach_min",
            self.approach_min,
            0.0,
            self.approach_desired,
        )?;
        check_in(
            at,
            "retreat_min",
            self.retreat_min,
            0.0,
            self.retreat_desired,
        )?;
        check_count(at, "scan_twists", self.scan_twists, 1)?;
        for shift in &self.scan_shifts {
            for v in shift {
                check_in(at, "scan_shifts", *v, -1.0, 1.0)?;
            }
        }
        check_count(at, "poses_tried", self.poses_tried, 1)?;
        check_count(at, "search_decimate", self.search_decimate, 1)?;
        check_count(at, "roll_samples", self.roll_samples, 1)?;
        check_count(at, "max_planned", self.max_planned, 1)
    }
}
