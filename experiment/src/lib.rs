//! Subject sessions for the two-pair method of constant stimuli (thesis Chapter IV): the design
//! file, per-subject trial lists, the append-only session log, resume, simulated observers and
//! (feature `gui`) the egui/eframe presentation app.

pub mod log;
