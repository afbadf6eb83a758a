//! Recording a world while it steps, and exporting the recording as an
//! animated glTF (`tumble::export::write_glb`, the file the viewer plays) or
//! a CSV trajectory table. Without a recording, the current state is
//! exported as a single frame.

use crate::errors::{invalid, OrRaise};
use pyo3::prelude::*;
use std::path::Path;
use tumble::export::{write_glb, write_trajectory_csv, Recording, WorldRecorder};
use tumble::world::World as RWorld;

/// A `WorldRecorder` sampling every `every`-th step.
#[derive(Debug)]
pub struct Recorder {
    recorder: WorldRecorder,
    every: u32,
    since_last: u32,
}

impl Recorder {
    /// Starts recording; the current state is the first frame.
    pub fn start(world: &RWorld, every: u32) -> PyResult<Recorder> {
        if every == 0 {
            return Err(invalid("every: must be at least 1 step"));
        }
        Ok(Recorder {
            recorder: WorldRecorder::new(world).or_raise()?,
            every,
            since_last: 0,
        })
    }

    /// Called after each step.
    pub fn after_step(&mut self, world: &RWorld) {
        self.since_last += 1;
        if self.since_last >= self.every {
            self.since_last = 0;
            self.recorder.record(world);
        }
    }

    /// Frames so far.
    pub fn frames(&self) -> usize {
        self.recorder.frames()
    }

    fn recording(rec: Option<&Recorder>, world: &RWorld) -> PyResult<Recording> {
        match rec {
            Some(r) => Ok(r.recorder.clone().finish()),
            None => Ok(WorldRecorder::new(world).or_raise()?.finish()),
        }
    }

    /// Writes `.glb`.
    pub fn export_glb(rec: Option<&Recorder>, world: &RWorld, path: &Path) -> PyResult<()> {
        write_glb(&Self::recording(rec, world)?, path).or_raise()
    }

    /// Writes the CSV trajectory table.
    pub fn export_csv(rec: Option<&Recorder>, world: &RWorld, path: &Path) -> PyResult<()> {
        write_trajectory_csv(&Self::recording(rec, world)?, path).or_raise()
    }
}
