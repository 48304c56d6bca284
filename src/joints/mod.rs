//! Joints: bilateral constraints between two bodies, projected together
//! with the contacts.
//!
//! A [`Joint`] locks some relative motions of an anchor frame on each of
//! its bodies ([`model`]) and may limit free ones. Each locked axis is an
//! equality constraint `e(q) = 0` and each limit two unilateral ones,
//! measured exactly from the poses and linearized for the projection QP
//! ([`constraints`]): the equalities become the QP's equality rows, the
//! limits inequality rows beside the contacts. [`IslandJoints`] is the
//! joints of one island as the projection sees them.

pub mod constraints;
pub mod island_joints;
pub mod model;
mod summary;

pub use constraints::{AnchorFrames, JointConstraint};
pub use island_joints::IslandJoints;
pub use model::{Joint, JointAxes, JointError, JointKind, JointLimits, Limit};
pub use summary::JointErrors;
