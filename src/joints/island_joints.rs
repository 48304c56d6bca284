//! The joints of one island as the projection sees them: each end either a
//! body of the island's configuration (a slot) or a body held where it is
//! (fixed, or outside the configuration), its constraints, and their rows
//! and values at any configuration of the island.

use nalgebra::{Isometry3, Vector3};

use super::constraints::{AnchorFrames, JointConstraint};
use super::model::Joint;
use crate::rows::{BodyState, ConstraintRow, RowKind};

/// One end of a joint.
#[derive(Debug, Clone, Copy, PartialEq)]
enum End {
    /// Body `slot` of the configuration.
    Moving(usize),
    /// A body held at this centre-of-mass pose.
    Held(Isometry3<f64>),
}

/// One joint of the island.
#[derive(Debug, Clone, PartialEq)]
struct IslandJoint {
    joint: Joint,
    ends: [End; 2],
    offsets: [Vector3<f64>; 2],
    constraints: Vec<JointConstraint>,
    /// The weight of each constraint ([`equality_weights`]).
    weights: Vec<f64>,
}

/// Each equality of a joint weighted by the square root of the number of
/// its kind (locked translations, or locked rotations), limits by 1: then
/// a joint whose weighted components are all within the tolerance has its
/// anchor separation (the norm of the locked translations) and its
/// misalignment within it too (`|v| <= sqrt(n) max_k |v_k|`), which is what
/// the report and the call's stop rule measure ([`super::JointErrors`]).
fn equality_weights(constraints: &[JointConstraint]) -> Vec<f64> {
    let count = |linear: bool| {
        constraints
            .iter()
            .filter(|c| c.is_equality() && c.is_angular() != linear)
            .count() as f64
    };
    let (linear, angular) = (count(true).sqrt(), count(false).sqrt());
    constraints
        .iter()
        .map(|c| match (c.is_equality(), c.is_angular()) {
            (true, false) => linear,
            (true, true) => angular,
            (false, _) => 1.0,
        })
        .collect()
}

/// The joints of one island (module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IslandJoints {
    joints: Vec<IslandJoint>,
    /// Scene indices of the joints, in order.
    indices: Vec<usize>,
    /// The length that turns angles into lengths.
    scale: f64,
    /// A limit's rows are linearized when its value is below this.
    margin: f64,
}

/// What [`IslandJoints::new`] needs to know of a joint's body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointBody {
    /// Slot in the island's configuration, if the body moves.
    pub slot: Option<usize>,
    /// Centre-of-mass pose (used when the body does not move).
    pub com_pose: Isometry3<f64>,
    /// Centre of mass in the body's user frame.
    pub com_offset: Vector3<f64>,
}

impl IslandJoints {
    /// The joints `(scene index, joint, [body a, body b])` of an island;
    /// angles are measured in lengths by `scale` and limits give rows when
    /// their value is below `margin`.
    pub fn new(
        joints: impl IntoIterator<Item = (usize, Joint, [JointBody; 2])>,
        scale: f64,
        margin: f64,
    ) -> Self {
        let mut out = IslandJoints {
            scale,
            margin,
            ..IslandJoints::default()
        };
        for (index, joint, bodies) in joints {
            let end = |b: &JointBody| match b.slot {
                Some(slot) => End::Moving(slot),
                None => End::Held(b.com_pose),
            };
            out.indices.push(index);
            let constraints = JointConstraint::of(&joint);
            out.joints.push(IslandJoint {
                weights: equality_weights(&constraints),
                constraints,
                joint,
                ends: [end(&bodies[0]), end(&bodies[1])],
                offsets: [bodies[0].com_offset, bodies[1].com_offset],
            });
        }
        out
    }

    /// Whether the island has no joint.
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// Scene indices of the joints.
    pub fn indices(&self) -> &[usize] {
        &self.indices
    }

    /// Whether the joints close a loop (bodies held still count as one
    /// node, the ground): only then can their equality rows be redundant
    /// for any pose (a tree of joints locks each body's motions once).
    pub fn close_a_loop(&self) -> bool {
        let slots = self
            .joints
            .iter()
            .flat_map(|j| j.ends)
            .filter_map(|end| match end {
                End::Moving(slot) => Some(slot + 1),
                End::Held(_) => None,
            })
            .max()
            .unwrap_or(0);
        // Node 0 is the ground, node `slot + 1` a moving body.
        let mut parent: Vec<usize> = (0..=slots).collect();
        fn root(parent: &mut [usize], mut node: usize) -> usize {
            while parent[node] != node {
                parent[node] = parent[parent[node]];
                node = parent[node];
            }
            node
        }
        let node = |end: &End| match end {
            End::Moving(slot) => slot + 1,
            End::Held(_) => 0,
        };
        for joint in &self.joints {
            let (a, b) = (
                root(&mut parent, node(&joint.ends[0])),
                root(&mut parent, node(&joint.ends[1])),
            );
            if a == b {
                return true;
            }
            parent[a] = b;
        }
        false
    }

    /// Anchor frames of joint `j` at `configuration`.
    fn frames(&self, j: usize, configuration: &[BodyState]) -> AnchorFrames {
        let joint = &self.joints[j];
        let pose = |end: &End| match *end {
            End::Moving(slot) => configuration[slot].isometry(),
            End::Held(pose) => pose,
        };
        AnchorFrames::at(
            &joint.joint,
            &pose(&joint.ends[0]),
            &joint.offsets[0],
            &pose(&joint.ends[1]),
            &joint.offsets[1],
        )
    }

    /// The rows at `configuration`: every equality, and every limit whose
    /// value is below the margin.
    pub fn rows(&self, configuration: &[BodyState]) -> Vec<ConstraintRow> {
        let mut rows = Vec::new();
        for (j, joint) in self.joints.iter().enumerate() {
            let frames = self.frames(j, configuration);
            for (constraint, weight) in joint.constraints.iter().zip(&joint.weights) {
                let mut linearized = constraint.linearize(&frames, self.scale);
                linearized.value *= weight;
                linearized.grad_a *= *weight;
                linearized.grad_b *= *weight;
                let equality = constraint.is_equality();
                if !equality && linearized.value >= self.margin {
                    continue;
                }
                let mut blocks = Vec::with_capacity(2);
                for (end, grad) in joint
                    .ends
                    .iter()
                    .zip([linearized.grad_a, linearized.grad_b])
                {
                    if let End::Moving(slot) = *end {
                        blocks.push((slot, grad));
                    }
                }
                rows.push(ConstraintRow {
                    kind: if equality {
                        RowKind::Equality
                    } else {
                        RowKind::Inequality
                    },
                    phi: linearized.value,
                    blocks,
                    friction: None,
                });
            }
        }
        rows
    }

    /// The exact values at `configuration`: the equalities' and the
    /// limits', each in a fixed order.
    pub fn measure(&self, configuration: &[BodyState]) -> (Vec<f64>, Vec<f64>) {
        let mut equalities = Vec::new();
        let mut limits = Vec::new();
        for (j, joint) in self.joints.iter().enumerate() {
            let frames = self.frames(j, configuration);
            for (constraint, weight) in joint.constraints.iter().zip(&joint.weights) {
                let value = weight * constraint.value(&frames, self.scale);
                match constraint.is_equality() {
                    true => equalities.push(value),
                    false => limits.push(value),
                }
            }
        }
        (equalities, limits)
    }
}
