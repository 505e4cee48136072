//! Playing a trial's videos, with no GUI types: the lab app (`app/`) draws what these decide,
//! and the browser client (`experiment/web/trial.js`) follows the same rules.
//!
//! | module | what |
//! |---|---|
//! | `presentation` | the clock-driven presentation of a trial (frames not yet loaded are held, never drawn) |
//! | `layout` | where the videos go, in whole physical pixels |
//! | `frames` | a stimulus's frame files and their decoding |
//! | `frame_store` | the app's frame seam `FrameStore`: `FrameDir` (a stimulus folder), `MemoryFrames` |
//! | `refresh` | measuring the display's refresh interval |
//! | `stream` | when a loading trial may start (frames in the order they are due) |

pub mod frame_store;
pub mod frames;
pub mod layout;
pub mod presentation;
pub mod refresh;
pub mod stream;
