//! The line search's push test with an allowed penetration: measured from
//! the allowance, a contact at its edge may be pushed in by a tenth of the
//! violation being removed, as a contact at the edge of the plain
//! tolerance may. Measured from zero (the rule before), the same step was
//! rejected at every length and the island stalled (the pile of 200 of
//! `examples/with_and_without.rs` under `RespectAllowedPenetration`,
//! step 29).

use constraint_stabilization::internals::projector::{LineSearchOutcome, line_search};
use constraint_stabilization::internals::rows::{
    BodyState, ConstraintProvider, ConstraintRow, Measurement,
};
use constraint_stabilization::settings::LineSearchSettings;
use nalgebra::{DVector, Point3, UnitQuaternion};

/// The allowed penetration (Rapier's allowed linear error).
const ALLOWED: f64 = 5e-3;
/// The tolerance beyond the allowance.
const TOLERANCE: f64 = 8e-7;
/// How far the step removes the deep contact (m).
const STEP: f64 = 3e-4;
/// How much the clear contact sinks per unit of the deep one's correction
/// (a first-order push the linearization did not see).
const PUSH: f64 = 0.086;

/// Two contacts of one body, linear in its `x`: the deep one at
/// `-(ALLOWED + STEP)` lifted one for one, the clear one at the edge of
/// the tolerance (1e-9 inside it) sunk by [`PUSH`] per unit.
struct TwoContacts;

impl ConstraintProvider for TwoContacts {
    fn linearize(&mut self, _: &[BodyState]) -> Vec<ConstraintRow> {
        Vec::new()
    }

    fn measure(&mut self, configuration: &[BodyState]) -> Measurement {
        let x = configuration[0].position.x;
        Measurement {
            values: vec![
                -(ALLOWED + STEP) + x,
                -(ALLOWED + TOLERANCE - 1e-9) - PUSH * x,
            ],
            equalities: Vec::new(),
        }
    }
}

fn search(allowed: f64) -> LineSearchOutcome {
    let mut provider = TwoContacts;
    let configuration = vec![BodyState {
        position: Point3::origin(),
        rotation: UnitQuaternion::identity(),
    }];
    let before = provider.measure(&configuration);
    let dq = DVector::from_vec(vec![STEP, 0.0, 0.0, 0.0, 0.0, 0.0]);
    line_search(
        &mut provider,
        &configuration,
        &dq,
        &before,
        ALLOWED + TOLERANCE,
        allowed,
        &LineSearchSettings::default(),
    )
}

/// Measured from the allowance, the full step is taken: the clear
/// contact ends 2.6e-5 beyond the tolerance, within a tenth of the 3e-4
/// being removed, and the merit falls.
#[test]
fn a_contact_at_the_edge_of_the_allowance_may_yield_a_tenth_of_the_removed_depth() {
    match search(ALLOWED) {
        LineSearchOutcome::Accepted {
            alpha, measurement, ..
        } => {
            assert_eq!(alpha, 1.0);
            let pushed = -measurement.values[1] - (ALLOWED + TOLERANCE);
            assert!(pushed > 0.0 && pushed <= 0.1 * STEP, "pushed {pushed:e}");
        }
        other => panic!("rejected: {other:?}"),
    }
}

/// The same numbers read without the allowance (the test measured from
/// zero): the clear contact may not go beyond the tolerance, and no step
/// length short of the smallest keeps it there.
#[test]
fn measured_from_zero_the_same_step_is_rejected() {
    assert!(matches!(search(0.0), LineSearchOutcome::Rejected { .. }));
}
