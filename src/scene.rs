//! The scene: an ordered list of validated bodies and optional settings.
//!
//! Body indices are positions in [`Scene::bodies`] and are what broad
//! phase, islands and reports use. Appending keeps every index;
//! [`Scene::remove_bodies`] keeps the order of the bodies left, so each
//! moves down by the number of removed bodies before it, and returns that
//! old-to-new map ([`IndexMap`]). Names are labels only: they need not be
//! unique.
//!
//! A scene also carries the settings its file gave
//! ([`SceneSettings`], every field optional, lengths absolute in the
//! scene's unit) as data: [`crate::Stabilizer::for_scene`] builds the
//! stabilizer they ask for, and [`crate::Settings::with_scene_settings`]
//! applies them to other settings. `Stabilizer::new(Settings::default())`
//! ignores them.

use nalgebra::Isometry3;
use thiserror::Error;

use crate::body::{Body, BodyDesc, BodyError};
use crate::joints::{Joint, JointError};
use crate::settings::{SceneSettings, SettingsError};

/// Why a scene could not be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    /// A body description is invalid.
    #[error("body {index} ({name:?}), field `{}`: {source}", source.field())]
    Body {
        /// Index the body has (or would have had) in the scene.
        index: usize,
        /// The body's name.
        name: String,
        /// What is wrong.
        source: BodyError,
    },
    /// A body index is out of range.
    #[error("no body {index}: the scene has {len} bodies")]
    NoSuchBody {
        /// The index asked for.
        index: usize,
        /// Number of bodies.
        len: usize,
    },
    /// The settings are invalid.
    #[error("{0}")]
    Settings(#[from] SettingsError),
    /// A joint is invalid.
    #[error("joint {index} ({name:?}): {source}")]
    Joint {
        /// Index the joint has (or would have had) in the scene.
        index: usize,
        /// The joint's name.
        name: String,
        /// What is wrong.
        source: JointError,
    },
    /// A joint index is out of range.
    #[error("no joint {index}: the scene has {len} joints")]
    NoSuchJoint {
        /// The index asked for.
        index: usize,
        /// Number of joints.
        len: usize,
    },
}

/// A body index and the user pose (translation, `[x, y, z, w]`) it had,
/// as recorded by [`Scene::set_user_poses`] to undo a failed batch.
type RecordedPose = (usize, (nalgebra::Vector3<f64>, [f64; 4]));

/// Old body index to new after [`Scene::remove_bodies`]: `old_to_new[i]` is
/// `None` for a removed body, else its new index (order preserved).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IndexMap {
    old_to_new: Vec<Option<usize>>,
}

impl IndexMap {
    /// The map that removes `removed[i] == true` bodies and shifts the rest.
    fn removing(removed: &[bool]) -> Self {
        let mut next = 0;
        let old_to_new = removed
            .iter()
            .map(|&gone| {
                (!gone).then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect();
        IndexMap { old_to_new }
    }

    /// The new index of old body `old`; `None` if it was removed or out of
    /// range.
    pub fn new_index(&self, old: usize) -> Option<usize> {
        self.old_to_new.get(old).copied().flatten()
    }

    /// `new_index` of every old index, in old order.
    pub fn old_to_new(&self) -> &[Option<usize>] {
        &self.old_to_new
    }

    /// Number of bodies before the removal.
    pub fn old_len(&self) -> usize {
        self.old_to_new.len()
    }

    /// Whether no body was removed.
    pub fn is_identity(&self) -> bool {
        self.old_to_new
            .iter()
            .enumerate()
            .all(|(i, &n)| n == Some(i))
    }
}

/// Bodies in a fixed order, the joints between them, and the settings
/// given with them.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    bodies: Vec<Body>,
    joints: Vec<Joint>,
    settings: SceneSettings,
}

impl Scene {
    /// An empty scene with no settings.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds a scene from body descriptions; the first invalid one is
    /// reported with its index and name.
    pub fn from_descs(
        descs: impl IntoIterator<Item = BodyDesc>,
        settings: SceneSettings,
    ) -> Result<Self, SceneError> {
        let mut scene = Scene::new();
        scene.set_settings(settings)?;
        for desc in descs {
            scene.add_body(desc)?;
        }
        Ok(scene)
    }

    /// Validates and appends a body; returns its index.
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<usize, SceneError> {
        let index = self.bodies.len();
        let name = desc.name.clone();
        let body = Body::new(desc).map_err(|source| SceneError::Body {
            index,
            name,
            source,
        })?;
        self.bodies.push(body);
        Ok(index)
    }

    /// Appends an already validated body; returns its index.
    pub fn push_body(&mut self, body: Body) -> usize {
        self.bodies.push(body);
        self.bodies.len() - 1
    }

    /// Removes the bodies at `indices` (any order, repeats allowed), keeping
    /// the order of the others; returns the old-to-new index map. An index
    /// out of range is an error and removes nothing.
    pub fn remove_bodies(&mut self, indices: &[usize]) -> Result<IndexMap, SceneError> {
        let len = self.bodies.len();
        let mut removed = vec![false; len];
        for &index in indices {
            *removed
                .get_mut(index)
                .ok_or(SceneError::NoSuchBody { index, len })? = true;
        }
        let map = IndexMap::removing(&removed);
        let mut old = 0;
        self.bodies.retain(|_| {
            old += 1;
            !removed[old - 1]
        });
        self.joints.retain_mut(|joint| {
            match (map.new_index(joint.body_a), map.new_index(joint.body_b)) {
                (Some(a), Some(b)) => {
                    (joint.body_a, joint.body_b) = (a, b);
                    true
                }
                _ => false,
            }
        });
        Ok(map)
    }

    /// Validates and appends a joint between two of the scene's bodies;
    /// returns its index. Removing either body removes the joint
    /// ([`Scene::remove_bodies`]).
    pub fn add_joint(&mut self, joint: Joint) -> Result<usize, SceneError> {
        let index = self.joints.len();
        joint
            .validate(&self.fixed_flags())
            .map_err(|source| SceneError::Joint {
                index,
                name: joint.name.clone(),
                source,
            })?;
        self.joints.push(joint);
        Ok(index)
    }

    /// Validates and appends several joints, all or nothing: on the first
    /// invalid one (the error names its would-be index) no joint is added.
    /// The bodies' fixed flags are computed once, so adding many joints
    /// takes time linear in bodies plus joints (one [`Scene::add_joint`]
    /// per joint takes their product).
    pub fn add_joints(&mut self, joints: Vec<Joint>) -> Result<(), SceneError> {
        let fixed = self.fixed_flags();
        let first = self.joints.len();
        for (offset, joint) in joints.iter().enumerate() {
            joint.validate(&fixed).map_err(|source| SceneError::Joint {
                index: first + offset,
                name: joint.name.clone(),
                source,
            })?;
        }
        self.joints.extend(joints);
        Ok(())
    }

    /// Removes the joints at `indices` (any order, repeats allowed),
    /// keeping the order of the others. An index out of range is an error
    /// and removes nothing.
    pub fn remove_joints(&mut self, indices: &[usize]) -> Result<(), SceneError> {
        let len = self.joints.len();
        let mut removed = vec![false; len];
        for &index in indices {
            *removed
                .get_mut(index)
                .ok_or(SceneError::NoSuchJoint { index, len })? = true;
        }
        let mut old = 0;
        self.joints.retain(|_| {
            old += 1;
            !removed[old - 1]
        });
        Ok(())
    }

    /// The joints, in index order.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// Sets the user poses (shape frame in the world, see
    /// [`Body::set_user_pose`]) of several bodies in one call. All or
    /// nothing: on an index out of range or an invalid pose (not finite),
    /// the error names the body and every pose is as it was.
    pub fn set_user_poses(
        &mut self,
        poses: impl IntoIterator<Item = (usize, Isometry3<f64>)>,
    ) -> Result<(), SceneError> {
        let mut before = Vec::new();
        for (index, pose) in poses {
            let result = self.body_mut(index).and_then(|body| {
                let old = (*body.translation_user(), body.rotation_user_xyzw());
                let q = pose.rotation.quaternion();
                body.set_user_pose(pose.translation.vector, [q.i, q.j, q.k, q.w])
                    .map(|()| old)
                    .map_err(|source| SceneError::Body {
                        index,
                        name: body.name().to_owned(),
                        source,
                    })
            });
            match result {
                Ok(old) => before.push((index, old)),
                Err(error) => {
                    self.restore_user_poses(&before);
                    return Err(error);
                }
            }
        }
        Ok(())
    }

    /// Puts back poses recorded by [`Scene::set_user_poses`], last first (a
    /// body set twice ends at its first recorded pose).
    fn restore_user_poses(&mut self, before: &[RecordedPose]) {
        for (index, (translation, rotation)) in before.iter().rev() {
            // Recorded from the body itself before a successful set: the
            // index exists and the pose was valid, so this cannot fail.
            let restored = self.bodies[*index].set_user_pose(*translation, *rotation);
            debug_assert!(restored.is_ok());
        }
    }

    /// The bodies, in index order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The bodies, mutable (poses can be set; bodies stay valid).
    pub fn bodies_mut(&mut self) -> &mut [Body] {
        &mut self.bodies
    }

    /// Body `index`.
    pub fn body(&self, index: usize) -> Result<&Body, SceneError> {
        let len = self.bodies.len();
        self.bodies
            .get(index)
            .ok_or(SceneError::NoSuchBody { index, len })
    }

    /// Body `index`, mutable.
    pub fn body_mut(&mut self, index: usize) -> Result<&mut Body, SceneError> {
        let len = self.bodies.len();
        self.bodies
            .get_mut(index)
            .ok_or(SceneError::NoSuchBody { index, len })
    }

    /// Moves body `index` to a new centre-of-mass pose (see
    /// [`Body::set_com_pose`]); errors name the body.
    pub fn set_com_pose(
        &mut self,
        index: usize,
        com_pose: nalgebra::Isometry3<f64>,
    ) -> Result<(), SceneError> {
        let body = self.body_mut(index)?;
        body.set_com_pose(com_pose)
            .map_err(|source| SceneError::Body {
                index,
                name: body.name().to_owned(),
                source,
            })
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// Whether there are no bodies.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// `is_fixed()` of every body, in index order.
    pub fn fixed_flags(&self) -> Vec<bool> {
        self.bodies.iter().map(Body::is_fixed).collect()
    }

    /// The settings given with the scene.
    pub fn settings(&self) -> &SceneSettings {
        &self.settings
    }

    /// Validates and replaces the settings.
    pub fn set_settings(&mut self, settings: SceneSettings) -> Result<(), SceneError> {
        settings.validate()?;
        self.settings = settings;
        Ok(())
    }
}
