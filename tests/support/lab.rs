//! A whole lab session in the real app (`experiment::app::SessionApp`) without a display:
//! egui_kittest steps the app at 60 Hz and presses the answer keys, so the log is the one the
//! lab writes (`mode: gui`). Used where a lab log must sit beside a browser's.

use egui::Key;
use egui_kittest::Harness;
use experiment::app::{Pacing, SessionApp};
use experiment::log::writer::Durability;
use experiment::playback::frame_store::FrameDir;
use experiment::preflight::{PreflightOptions, preflight};
use experiment::{Design, Phase, Session};
use std::path::Path;
use std::sync::Arc;

/// Run `subject`'s whole session of the design at `design_path` into `log`, answering pair 1.
pub fn run(design_path: &Path, subject: &str, log: &Path) {
    let design = Design::load(design_path).unwrap();
    let checks = PreflightOptions { check_hashes: true };
    let report = preflight(&design, checks, &renderer::progress::NoProgress);
    let manifest_path = report.manifest_path.clone();
    let store = Arc::new(FrameDir::new(report.into_result().unwrap(), manifest_path));
    let session = Session::open(&design, subject, log, Durability::Sync).unwrap();
    let app = SessionApp::new(session, store, Pacing::Vsync);
    let mut h = Harness::builder()
        .with_size([1280.0, 720.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(|ui, app: &mut SessionApp| app.show(ui), app);
    // The instructions wait until the refresh interval is measured.
    h.run_steps(61);
    press(&mut h, Key::Space);
    for _ in 0..100_000 {
        match h.state().session().phase() {
            Phase::Practice(_) | Phase::Trial(_) if h.state().responding() => {
                press(&mut h, Key::Num1);
                h.run_steps(70); // practice feedback, if any
            }
            Phase::PracticeDone | Phase::Break => press(&mut h, Key::Space),
            Phase::Finished => return,
            _ if h.state().loading() => std::thread::sleep(std::time::Duration::from_millis(2)),
            _ => {}
        }
        assert_eq!(h.state().fatal_error(), None);
        h.step();
    }
    panic!("the lab session never finished");
}

fn press(h: &mut Harness<'_, SessionApp>, key: Key) {
    h.key_press(key);
    h.step();
}
