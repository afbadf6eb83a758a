//! # tumble
//!
//! Rigid body dynamics with exact triangle-mesh contact, built on
//! [`tumble_collide`].

#![warn(missing_docs)]

pub use tumble_collide as collide;

pub mod export;
