//! `blurlab serve`: subject sessions in browsers (issue 39). The server runs each subject's
//! [`crate::Session`] and writes the same `blurlab-session/1` log as the lab app; the browser shows
//! what the server chose and reports what the subject pressed. See `docs/web.md`.

pub mod assets;
