//! Pick and place's parameters (SPEC §3.2 and §6 where the seeds give a number),
//! loadable from TOML.

use crate::observe::ObserveParams;
use crate::skills::grasp::SideGrasps;
use tabula_geom::input::{Validate, check_count, check_non_negative, check_positive, nested};
use tabula_motion::MoveGroupParams;

/// Parameters of pick and place (SPEC §3.2 and §6 where the seeds give a number).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PickPlaceParams {
    pub observe: ObserveParams,
    pub motion: MoveGroupParams,
    /// Camera used to look (the robot's head camera in the scene).
    pub camera: String,
    /// Pre-grasp distance back along the approach (m), SPEC §3.2: 10 cm.
    pub pregrasp_distance: f64,
    /// Lift after closing (m): enough to clear the board, not to hit the one above.
    pub lift: f64,
    /// Retreat out of the shelf along the approach after lifting (m).
    pub retreat: f64,
    /// Height of the object's bottom above the surface when released (m), SPEC §6: 8 mm.
    pub release_height: f64,
    /// Distance of the pre-place pose back along the approach (m), SPEC §6: 0.1 m min.
    pub place_approach: f64,
    /// Retreat after opening (m), SPEC §6: 0.1 m min.
    pub place_retreat: f64,
    /// Room left between each open finger and the object (m) …
    pub finger_clearance: f64,
    /// … or less, down to this, for an object that leaves the open hand less room (m).
    pub min_finger_clearance: f64,
    /// The tool point stays at least this far above the support (m): the fingertips
    /// must not scrape the board.
    pub min_grasp_height: f64,
    /// Approach yaws tried within ± this of the direction from the arm to the object
    /// (rad) …
    pub yaw_range: f64,
    /// … this far apart (rad): narrow arms such as Golem-III's reach a level grasp
    /// only in narrow bands of yaw.
    pub yaw_step: f64,
    /// Downward tilts of a side grasp's approach (rad): lower boards need some.
    pub side_tilts: Vec<f64>,
    /// Head pan angles (rad, from the robot's heading) of the sweep that maps the
    /// workspace, SPEC §6: −90°…+90° in 45° steps …
    pub sweep_angles: Vec<f64>,
    /// … looking at points this far out (m) at the working height and at these heights
    /// above it (the arm's motions rise above what a level sweep sees).
    pub sweep_radius: f64,
    pub sweep_rises: Vec<f64>,
    /// Grasps (and, per grasp, placements) planned at most, best first.
    pub max_planned_grasps: usize,
    /// Straight lines into and out of a grasp or a placement may also rise by these
    /// (m): an arm whose level lines are short still gets in and out.
    pub rise_offsets: Vec<f64>,
    /// The grasp point may also sit this far deeper (+) or shallower (−) along the
    /// approach than the object's centre (m).
    pub grasp_depth_offsets: Vec<f64>,
    /// Margin around the object's footprint that must be free at the target (m).
    pub place_margin: f64,
    /// What a full gripper holds is seen up to this far from its tool point (m) …
    pub held_reach: f64,
    /// … and, unseen, is a ball this much wider than the finger gap (m).
    pub held_margin: f64,
}

impl Default for PickPlaceParams {
    fn default() -> Self {
        Self {
            observe: ObserveParams::default(),
            motion: MoveGroupParams {
                cartesian_tolerance: 0.01,
                ..MoveGroupParams::default()
            },
            camera: "head".into(),
            pregrasp_distance: 0.10,
            lift: 0.04,
            retreat: 0.15,
            release_height: 0.008,
            place_approach: 0.10,
            place_retreat: 0.10,
            finger_clearance: 0.01,
            min_finger_clearance: 0.005,
            min_grasp_height: 0.035,
            yaw_range: 1.5,
            yaw_step: 0.05,
            side_tilts: vec![0.0, 0.2, 0.4],
            max_planned_grasps: 8,
            sweep_angles: [-90.0f64, -45.0, 0.0, 45.0, 90.0]
                .iter()
                .map(|d| d.to_radians())
                .collect(),
            sweep_radius: 0.8,
            sweep_rises: vec![0.0, 0.45],
            rise_offsets: vec![0.0, 0.03, 0.06, 0.09, 0.12],
            grasp_depth_offsets: vec![0.015, -0.01],
            place_margin: 0.01,
            held_reach: 0.3,
            held_margin: 0.02,
        }
    }
}

impl Validate for PickPlaceParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.observe.check(&nested(at, "observe"))?;
        self.motion.check(&nested(at, "motion"))?;
        for (name, v) in [
            ("pregrasp_distance", self.pregrasp_distance),
            ("lift", self.lift),
            ("retreat", self.retreat),
            ("release_height", self.release_height),
            ("place_approach", self.place_approach),
            ("place_retreat", self.place_retreat),
            ("finger_clearance", self.finger_clearance),
            ("min_finger_clearance", self.min_finger_clearance),
            ("min_grasp_height", self.min_grasp_height),
            ("yaw_range", self.yaw_range),
            ("sweep_radius", self.sweep_radius),
            ("place_margin", self.place_margin),
            ("held_reach", self.held_reach),
            ("held_margin", self.held_margin),
        ] {
            check_non_negative(at, name, v)?;
        }
        check_positive(at, "yaw_step", self.yaw_step)?;
        check_count(at, "max_planned_grasps", self.max_planned_grasps, 1)
    }
}

impl PickPlaceParams {
    /// The grasp planner pick and place proposes candidates with: side grasps around
    /// the direction from the arm, then top grasps.
    pub fn grasp_planner(&self) -> SideGrasps {
        SideGrasps {
            finger_clearance: self.finger_clearance,
            min_finger_clearance: self.min_finger_clearance,
            min_grasp_height: self.min_grasp_height,
            yaw_range: self.yaw_range,
            yaw_step: self.yaw_step,
            tilts: self.side_tilts.clone(),
            depth_offsets: self.grasp_depth_offsets.clone(),
            top: true,
        }
    }
}
