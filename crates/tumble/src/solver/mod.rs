//! Contact solvers: the sub-stepped soft sequential-impulse solver used by the
//! world every step.

pub mod contact_solver;
pub mod soft;
