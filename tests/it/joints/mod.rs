//! Joints: the constraints' exact values and derivatives, the closed forms
//! of a projection with joints, joints with contacts, chains and loops.

mod closed_forms;
mod derivatives;
mod with_contacts;
