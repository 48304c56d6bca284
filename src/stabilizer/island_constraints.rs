//! The constraint provider of one island: its contacts and its joints
//! together, one problem.
//!
//! Rows come in the order the projection QP wants them: the joints'
//! equality rows first, then the joints' limit rows, then the contacts'
//! rows. A measurement holds the joints' equality values, and as
//! unilateral values the limits' then the contacts' (each block in a fixed
//! order), so that the merit, the line search and the stop rule count
//! joint errors beside penetrations.

use crate::contact::IslandContacts;
use crate::joints::IslandJoints;
use crate::rows::{BodyState, ConstraintProvider, ConstraintRow, Measurement, RowKind};

/// An island's contacts and joints (module docs).
pub struct IslandConstraints<'a> {
    /// The contacts.
    pub contacts: IslandContacts<'a>,
    /// The joints.
    pub joints: IslandJoints,
}

impl<'a> IslandConstraints<'a> {
    /// The provider of `contacts` and `joints`.
    pub fn new(contacts: IslandContacts<'a>, joints: IslandJoints) -> Self {
        IslandConstraints { contacts, joints }
    }
}

impl ConstraintProvider for IslandConstraints<'_> {
    fn linearize(&mut self, configuration: &[BodyState]) -> Vec<ConstraintRow> {
        let mut rows = self.joints.rows(configuration);
        // Equalities first (a stable sort keeps each block's order).
        rows.sort_by_key(|row| row.kind != RowKind::Equality);
        rows.extend(self.contacts.linearize(configuration));
        rows
    }

    fn equalities_may_be_redundant(&self) -> bool {
        self.joints.close_a_loop()
    }

    fn measure(&mut self, configuration: &[BodyState]) -> Measurement {
        let (equalities, mut values) = self.joints.measure(configuration);
        values.extend(self.contacts.measure(configuration).values);
        Measurement { values, equalities }
    }
}
