//! What `blurlab serve` refuses before it listens (issue 51 items 1 and 2): stimuli missing or
//! changed since they were rendered, a sessions folder holding another subject's, mode's or
//! design's log, and a `tokens.json` whose tokens are not tokens or are shared. Each refusal
//! names the file and the field; a stale `links.csv` is rewritten.

use experiment::Design;
use experiment::fixture::{StudySpec, write_study};
use serde_json::json;
use std::path::Path;
use web_client::config;

mod web_client;

/// The error `Server::bind` gives for the study in `root` after `spoil`, or `None` if it binds.
async fn bind_error(root: &Path, enrol: u32, spoil: impl FnOnce(&Design, &Path)) -> Option<String> {
    let design = Design::load(&root.join("design.json")).unwrap();
    let out = root.join("study");
    spoil(&design, &out);
    match experiment::web::Server::bind(&config(&design.path, &out, enrol)).await {
        Ok(_) => None,
        Err(e) => Some(format!("{e:#}")),
    }
}

fn study() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let s = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    assert_eq!(s.design_path, dir.path().join("design.json"));
    dir
}

/// The first frame file of the first stimulus in the manifest of `design`.
fn a_frame(design: &Design, reference: bool) -> std::path::PathBuf {
    let m = renderer::manifest::Manifest::load(&design.manifest_path).unwrap();
    let s = m.stimuli.iter().find(|s| s.reference == reference).unwrap();
    design
        .manifest_path
        .parent()
        .unwrap()
        .join(&s.frame_paths[0])
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stimuli_missing_or_changed_are_refused_before_listening() {
    let dir = study();
    let e = bind_error(dir.path(), 1, |d, _| {
        std::fs::remove_file(a_frame(d, false)).unwrap()
    })
    .await
    .expect("a missing frame refused");
    assert!(
        e.contains("frame_0000") && e.contains("not ready to serve"),
        "{e}"
    );

    let dir = study();
    let e = bind_error(dir.path(), 1, |d, _| {
        // Same size, other pixels: only the content hash can tell.
        let path = a_frame(d, true);
        let img = image::open(&path).unwrap().into_rgb8();
        let mut other = img.clone();
        other.get_pixel_mut(0, 0).0[0] ^= 0x40;
        other.save(&path).unwrap();
    })
    .await
    .expect("a changed reference frame refused");
    assert!(e.contains("hash"), "{e}");
}

fn header(subject: &str, mode: &str, design_hash: &str) -> String {
    json!({
        "kind": "header", "format": "blurlab-session/1", "subject": subject, "session": 1,
        "design": "tiny", "design_hash": design_hash, "seed": 1, "app_version": "test",
        "mode": mode, "started_unix": 0.0, "trials_planned": 4,
    })
    .to_string()
        + "\n"
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_log_of_another_subject_mode_or_design_is_refused_naming_its_field() {
    for (field, subject, mode, other_design) in [
        ("`subject`", "w002", "web", false),
        ("`mode`", "w001", "gui", false),
        ("`design_hash`", "w001", "web", true),
    ] {
        let dir = study();
        let e = bind_error(dir.path(), 1, |d, out| {
            let sessions = out.join("sessions");
            std::fs::create_dir_all(&sessions).unwrap();
            let hash = if other_design {
                "0".repeat(64)
            } else {
                d.hash.clone()
            };
            std::fs::write(sessions.join("w001.jsonl"), header(subject, mode, &hash)).unwrap();
        })
        .await
        .unwrap_or_else(|| panic!("{field}: bound"));
        assert!(
            e.contains("w001.jsonl") && e.contains(field),
            "{field}: {e}"
        );
    }
    // The subject's own web log of this design is a session to continue.
    let dir = study();
    let bound = bind_error(dir.path(), 1, |d, out| {
        let sessions = out.join("sessions");
        std::fs::create_dir_all(&sessions).unwrap();
        std::fs::write(sessions.join("w001.jsonl"), header("w001", "web", &d.hash)).unwrap();
    })
    .await;
    assert_eq!(bound, None);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tokens_json_is_checked_like_any_input() {
    let t = |n: u8| format!("{n:x}").repeat(32);
    let subject = |name: &str, token: String| json!({"subject": name, "token": token});
    let cases = [
        ("`admin`", json!({"admin": "", "subjects": []})),
        ("`admin`", json!({"admin": "x", "subjects": []})),
        (
            "`open.token`",
            json!({"admin": t(1), "open": {"token": "short", "cap": 5}, "subjects": []}),
        ),
        (
            "w001 and w002 have the same token",
            json!({"admin": t(1), "subjects": [subject("w001", t(2)), subject("w002", t(2))]}),
        ),
        (
            "w001 has two tokens",
            json!({"admin": t(1), "subjects": [subject("w001", t(2)), subject("w001", t(3))]}),
        ),
        (
            "`subjects[0].subject`",
            json!({"admin": t(1), "subjects": [subject("../x", t(2))]}),
        ),
        (
            "is also `admin`",
            json!({"admin": t(1), "subjects": [subject("w001", t(1))]}),
        ),
    ];
    for (needle, tokens) in cases {
        let dir = study();
        let e = bind_error(dir.path(), 1, |_, out| {
            std::fs::create_dir_all(out.join("web")).unwrap();
            std::fs::write(out.join("web/tokens.json"), tokens.to_string()).unwrap();
        })
        .await
        .unwrap_or_else(|| panic!("{needle}: bound"));
        assert!(
            e.contains("tokens.json") && e.contains(needle),
            "{needle}: {e}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stale_links_csv_is_rewritten() {
    let dir = study();
    let design = Design::load(&dir.path().join("design.json")).unwrap();
    let out = dir.path().join("study");
    drop(
        experiment::web::Server::bind(&config(&design.path, &out, 2))
            .await
            .unwrap(),
    );
    let links = out.join("links.csv");
    let good = std::fs::read_to_string(&links).unwrap();
    std::fs::write(&links, "subject,url\nw001,http://old/s/0\n").unwrap();
    let mut cfg = config(&design.path, &out, 2);
    cfg.enrol = None;
    drop(experiment::web::Server::bind(&cfg).await.unwrap());
    let now = std::fs::read_to_string(&links).unwrap();
    // The port differs between the two starts; the subjects and tokens do not.
    let tokens = |text: &str| -> Vec<String> {
        text.lines()
            .skip(1)
            .map(|l| l.rsplit('/').next().unwrap().to_string())
            .collect()
    };
    assert_eq!(tokens(&now), tokens(&good));
}
