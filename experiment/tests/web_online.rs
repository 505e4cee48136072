//! Issue 49 over real HTTP on 127.0.0.1: a Prolific-style study link makes one subject per
//! participant id (a second visit goes back to it), consent comes before the display check and
//! is logged in the header with the text's hash, catch trials are logged, the end names the
//! completion URL with its code; a declined consent, a display outside the design's screening
//! ranges and a window too small end on the screen-out URL with no log written; bad ids and
//! reasons are refused naming what was wrong; the admin JSON counts all of it.

use experiment::Observer;
use experiment::fixture::{StudySpec, write_study};
use experiment::log::SessionLog;
use serde_json::json;
use std::path::Path;
use std::time::Duration;
use web_client::{Running, SimBrowser, config, display_facts, post};

mod web_client;

const OBSERVER: &str = r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1.5,
    "thresholds": [{"spp": 4}]}"#;

fn study(root: &Path) -> experiment::Design {
    let mut spec = StudySpec::tiny();
    spec.design = json!({"repeats": 2, "practice": {"trials": 1}, "break_every": 0,
        "catch_trials": {"rate": 0.25},
        "exclusion": {"min_rt_ms": 150},
        "online": {"platform": "prolific",
                   "completion_url": "https://app.prolific.com/submissions/complete?cc={code}",
                   "completion_code": "C0MPLETE",
                   "screen_out_url": "https://app.prolific.com/submissions/complete?cc={code}",
                   "screen_out_code": "SCREENED",
                   "consent": "consent.md", "debriefing": "debriefing.md",
                   "screening": {"refresh_hz": [50, 130]}}});
    std::fs::write(
        root.join("consent.md"),
        "# Consent\n\nYou agree to take part.",
    )
    .unwrap();
    std::fs::write(
        root.join("debriefing.md"),
        "Thank you. The study measured noise.",
    )
    .unwrap();
    experiment::Design::load(&write_study(root, &spec).unwrap().design_path).unwrap()
}

/// GET without following redirects: (status, Location).
async fn get(http: &reqwest::Client, url: &str) -> (u16, String) {
    let r = http.get(url).send().await.unwrap();
    let loc = r
        .headers()
        .get("location")
        .map(|v| v.to_str().unwrap().to_string())
        .unwrap_or_default();
    let status = r.status().as_u16();
    let body = r.text().await.unwrap_or_default();
    (status, if loc.is_empty() { body } else { loc })
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_platform_study_from_link_to_completion_and_screen_out() {
    let dir = tempfile::tempdir().unwrap();
    let design = study(dir.path());
    let out = dir.path().join("study");
    let mut cfg = config(&design.path, &out, 1);
    cfg.enrol = None;
    cfg.open_enrolment = Some(10);
    let server = Running::start(&cfg).await;
    let study_url = server
        .started
        .study_url
        .clone()
        .expect("a platform study URL");
    assert!(
        study_url.contains("PROLIFIC_PID={{%PROLIFIC_PID%}}"),
        "{study_url}"
    );
    let join = server.started.join_url.clone().unwrap();
    let http = reqwest::Client::builder()
        .redirect(reqwest::redirect::Policy::none())
        .build()
        .unwrap();

    // Bad links are refused naming the parameter.
    let (status, body) = get(&http, &join).await;
    assert_eq!(status, 400);
    assert!(body.contains("PROLIFIC_PID"), "{body}");
    let (status, body) = get(&http, &format!("{join}?PROLIFIC_PID=a%20b")).await;
    assert_eq!(status, 400);
    assert!(
        body.contains("`PROLIFIC_PID`") && body.contains("letters"),
        "{body}"
    );
    let (status, body) = get(&http, &format!("{join}?PROLIFIC_PID=p1&STUDY_ID=%3Cx%3E")).await;
    assert_eq!(status, 400);
    assert!(body.contains("`STUDY_ID`"), "{body}");

    // One subject per participant id; a second visit goes back to it.
    let link = |pid: &str| format!("{join}?PROLIFIC_PID={pid}&STUDY_ID=st1&SESSION_ID=se-{pid}");
    let (status, first) = get(&http, &link("p1")).await;
    assert_eq!(status, 303, "{first}");
    let (_, again) = get(&http, &link("p1")).await;
    assert_eq!(first, again, "the same participant, the same subject");
    let (_, other) = get(&http, &link("p2")).await;
    assert_ne!(first, other);
    let token = |loc: &str| loc.trim_start_matches("/s/").to_string();
    let base0 = server.base.clone();
    let api = |t: &str, rest: &str| format!("{base0}/api/s/{}/{rest}", token(t));

    // p1: consent first (the display check waits for it), then the whole session.
    let tab = "tab-o001";
    let r = post(&http, &api(&first, "claim"), json!({"tab": tab}))
        .await
        .unwrap();
    assert_eq!(r.body["phase"], "consent");
    assert!(r.body["message"].as_str().unwrap().contains("You agree"));
    let r = post(&http, &api(&first, "display"), display_facts(tab))
        .await
        .unwrap();
    assert_eq!(r.status, 409, "{}", r.body);
    let r = post(
        &http,
        &api(&first, "consent"),
        json!({"tab": tab, "accept": true}),
    )
    .await
    .unwrap();
    assert_eq!(r.body["phase"], "display_check", "{}", r.body);
    let observer = Observer::parse(Path::new("o.json"), OBSERVER).unwrap();
    let browser = SimBrowser::new(
        http.clone(),
        &server.base,
        &design,
        &observer,
        "o001",
        &token(&first),
        Duration::ZERO,
    );
    browser.run().await.unwrap();
    let r = post(&http, &api(&first, "claim"), json!({"tab": tab}))
        .await
        .unwrap();
    assert_eq!(r.body["phase"], "done");
    assert_eq!(
        r.body["redirect"],
        "https://app.prolific.com/submissions/complete?cc=C0MPLETE"
    );
    assert!(
        r.body["message"]
            .as_str()
            .unwrap()
            .contains("measured noise")
    );
    let log = SessionLog::read(&out.join("sessions/o001.jsonl")).unwrap();
    let p = log
        .header
        .participant
        .as_ref()
        .expect("the participant in the header");
    assert_eq!(p.ids["PROLIFIC_PID"], "p1");
    assert_eq!(p.ids["SESSION_ID"], "se-p1");
    let consent = p.consent.as_ref().expect("the consent in the header");
    assert_eq!(
        consent.text_sha256,
        renderer::digest::sha256_hex(b"# Consent\n\nYou agree to take part.")
    );
    assert!(consent.unix > 0.0);
    assert_eq!(
        log.main_trials().count(),
        design.main_trial_count() as usize
    );
    assert!(log.main_trials().any(|t| t.catch));

    // p2 declines: the screen-out route, no log.
    let tab2 = "tab-o002";
    post(&http, &api(&other, "claim"), json!({"tab": tab2}))
        .await
        .unwrap();
    let r = post(
        &http,
        &api(&other, "consent"),
        json!({"tab": tab2, "accept": false}),
    )
    .await
    .unwrap();
    assert_eq!(r.body["phase"], "screened_out");
    assert_eq!(
        r.body["redirect"],
        "https://app.prolific.com/submissions/complete?cc=SCREENED"
    );
    assert!(!out.join("sessions/o002.jsonl").exists());

    // p3: a 144 Hz display is outside the design's screening range.
    let (_, third) = get(&http, &link("p3")).await;
    let tab3 = "tab-o003";
    post(&http, &api(&third, "claim"), json!({"tab": tab3}))
        .await
        .unwrap();
    post(
        &http,
        &api(&third, "consent"),
        json!({"tab": tab3, "accept": true}),
    )
    .await
    .unwrap();
    let mut facts = display_facts(tab3);
    facts["refresh_interval_ms"] = json!(1000.0 / 144.0);
    let r = post(&http, &api(&third, "display"), facts).await.unwrap();
    assert_eq!(r.body["phase"], "screened_out", "{}", r.body);
    assert!(!out.join("sessions/o003.jsonl").exists());

    // p4: the page gives up on a window too small; a reason it may not give is refused.
    let (_, fourth) = get(&http, &link("p4")).await;
    let tab4 = "tab-o004";
    post(&http, &api(&fourth, "claim"), json!({"tab": tab4}))
        .await
        .unwrap();
    let r = post(
        &http,
        &api(&fourth, "screen_out"),
        json!({"tab": tab4, "reason": "bored"}),
    )
    .await
    .unwrap();
    assert_eq!(r.status, 400);
    assert!(r.error().contains("`reason`"), "{}", r.error());
    let r = post(
        &http,
        &api(&fourth, "screen_out"),
        json!({"tab": tab4, "reason": "window_too_small"}),
    )
    .await
    .unwrap();
    assert_eq!(r.body["phase"], "screened_out");

    // The admin JSON counts them, and the screen-outs survive a restart.
    let admin = server.started.admin_token.clone();
    let base = server.base.clone();
    server.stop().await;
    let server = Running::start(&cfg).await;
    let bytes = http
        .get(format!("{}/admin/progress.json", server.base))
        .bearer_auth(&admin)
        .send()
        .await
        .unwrap()
        .bytes()
        .await
        .unwrap();
    let o: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(o["finished"], 1, "{o}");
    assert_eq!(o["screened_out"], 3, "{o}");
    assert_eq!(o["enrolled"], 4, "{o}");
    assert_eq!(o["subjects"][0]["participant"], "p1", "{o}");
    assert!(
        o["subjects"][1]["screened_out"]
            .as_str()
            .unwrap()
            .contains("consent")
    );
    // A screened-out participant coming back is still screened out.
    let (_, back) = get(
        &http,
        &format!("{}{}", server.base, link("p2").trim_start_matches(&base)),
    )
    .await;
    assert_eq!(back, other);
    server.stop().await;
}

/// `serve --check` counts a session's catch trials with its other trials (it left them out).
#[test]
fn the_session_budget_counts_catch_trials() {
    let dir = tempfile::tempdir().unwrap();
    let design = study(dir.path());
    let cfg = config(&design.path, &dir.path().join("study"), 1);
    let (_, budget) = experiment::web::measure_study(&cfg, &mut |_, _, _| {}).unwrap();
    let procedure_trials = experiment::trials::plan(&design, "w001").main.len();
    let main = design.main_trial_count() as usize;
    assert!(main > procedure_trials, "the design has catch trials");
    assert_eq!(budget.trials, design.file.practice.trials as usize + main);
}
