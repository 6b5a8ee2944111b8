//! The tool a URDF most likely means, for robots without a description.

use super::{JointKind, RobotModel};

impl RobotModel {
    /// The link an arm most likely ends at, for a URDF with no description: down from
    /// the first root along the moving joints, through a branch only into subtrees of
    /// at least three moving joints (arms, not fingers: the first by name when there
    /// are several), stopping where the moving joints end or split into fingers; then
    /// the tool frame below that link if one is named so (`tcp`, `tool`, `flange`,
    /// `ee`), never a finger, a camera frame or a self-collision helper (`_sc`).
    pub fn default_tool(&self) -> usize {
        let mut link = self.roots.first().copied().unwrap_or(0);
        loop {
            let mut arms: Vec<(usize, &str)> = self.links[link]
                .child_joints
                .iter()
                .map(|&j| self.joints[j].child)
                .filter(|&c| {
                    self.moving_depth(c, link) >= 3
                        || (self.is_only_moving_child(link, c) && !self.is_finger(c))
                })
                .map(|c| (c, self.links[c].name.as_str()))
                .collect();
            arms.sort_by(|a, b| a.1.cmp(b.1));
            match arms.first() {
                Some(&(next, _)) => link = next,
                None => break,
            }
        }
        self.tool_frame_below(link).unwrap_or(link)
    }

    /// The most moving (single-axis, not mimic) joints on a path from `link` down,
    /// counting the joint into `link` from `parent`.
    fn moving_depth(&self, link: usize, parent: usize) -> usize {
        let own = self.links[link].parent_joint.map_or(0, |j| {
            let joint = &self.joints[j];
            (joint.parent == parent && joint.kind.is_single_axis() && joint.mimic.is_none())
                as usize
        });
        let below = self.links[link]
            .child_joints
            .iter()
            .map(|&j| self.moving_depth(self.joints[j].child, link))
            .max()
            .unwrap_or(0);
        own + below
    }

    /// True when `child` is the one child of `link` whose subtree moves at all.
    fn is_only_moving_child(&self, link: usize, child: usize) -> bool {
        let moving: Vec<usize> = self.links[link]
            .child_joints
            .iter()
            .map(|&j| self.joints[j].child)
            .filter(|&c| self.moving_depth(c, link) > 0)
            .collect();
        moving == [child]
    }

    /// True for a link a gripper's finger joint moves: named so, driving a mimic, or on
    /// a prismatic joint of a few centimetres.
    fn is_finger(&self, link: usize) -> bool {
        let Some(j) = self.links[link].parent_joint else {
            return false;
        };
        let name = self.links[link].name.to_ascii_lowercase();
        let joint = &self.joints[j];
        ["finger", "gripper", "jaw", "knuckle"]
            .iter()
            .any(|k| name.contains(k))
            || self
                .joints
                .iter()
                .any(|o| o.mimic.as_ref().is_some_and(|m| m.master == j))
            || (joint.kind == JointKind::Prismatic
                && joint.limits.upper - joint.limits.lower <= 0.15)
    }

    /// A link hung on fixed joints below `link` whose name says it is the tool frame.
    fn tool_frame_below(&self, link: usize) -> Option<usize> {
        let mut fixed_below = Vec::new();
        let mut stack = vec![link];
        while let Some(l) = stack.pop() {
            for &j in &self.links[l].child_joints {
                if self.joints[j].kind == JointKind::Fixed {
                    fixed_below.push(self.joints[j].child);
                    stack.push(self.joints[j].child);
                }
            }
        }
        let name = |l: usize| self.links[l].name.to_ascii_lowercase();
        let excluded = |n: &str| {
            [
                "finger", "camera", "optical", "_sc", "sensor", "ft_frame", "inertia",
            ]
            .iter()
            .any(|x| n.contains(x))
        };
        ["tcp", "tool", "grasp", "end_effector", "ee_link", "flange"]
            .iter()
            .find_map(|key| {
                fixed_below
                    .iter()
                    .copied()
                    .filter(|&l| name(l).contains(key) && !excluded(&name(l)))
                    .min_by_key(|&l| (name(l).len(), name(l)))
            })
    }
}
