//! The HTTP surface of `blurlab serve` against requests a browser should never send: bad and
//! unknown tokens, bad JSON, oversize bodies, replayed and out-of-order answers, a second tab,
//! path traversal (plain, percent-encoded, absolute), another subject's video ids and stimulus
//! names. Each gets its status and a JSON message, and changes nothing (the log is compared byte
//! for byte). Also: the security headers, the admin token, and that a video's frames decode to the
//! PNG files' pixels exactly.

use experiment::Design;
use experiment::fixture::{StudySpec, write_study};
use experiment::web::wire::State;
use serde_json::{Value, json};
use web_client::{Running, config, display_facts, post, tokens};

mod web_client;

struct Case {
    what: &'static str,
    method: &'static str,
    path: String,
    body: Option<String>,
    status: u16,
    message: &'static str,
}

async fn send(http: &reqwest::Client, base: &str, c: &Case) -> (u16, Value) {
    let url = format!("{base}{}", c.path);
    let req = match c.method {
        "GET" => http.get(&url),
        "POST" => http.post(&url).body(c.body.clone().unwrap_or_default()),
        m => http
            .request(m.parse().unwrap(), &url)
            .body(c.body.clone().unwrap_or_default()),
    };
    let r = req.send().await.unwrap();
    let status = r.status().as_u16();
    let v = serde_json::from_slice(&r.bytes().await.unwrap()).unwrap_or(Value::Null);
    (status, v)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn malformed_requests_get_their_status_and_message_and_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let design = Design::load(&study.design_path).unwrap();
    let out = dir.path().join("study");
    let server = Running::start(&config(&design.path, &out, 2)).await;
    let base = server.base.clone();
    let http = reqwest::Client::new();
    let t = tokens(&out);
    let (subject, token) = t[0].clone();
    let other_token = t[1].1.clone();
    let api = |rest: &str| format!("{base}/api/s/{token}/{rest}");

    // A tab claims, passes the display check and the instructions: a practice trial is current.
    let r = post(&http, &api("claim"), json!({"tab": "A"}))
        .await
        .unwrap();
    assert_eq!(r.status, 200, "{}", r.body);
    let r = post(&http, &api("display"), display_facts("A"))
        .await
        .unwrap();
    assert_eq!(r.status, 200, "{}", r.body);
    let r = post(
        &http,
        &api("advance"),
        json!({"tab": "A", "from": "instructions"}),
    )
    .await
    .unwrap();
    let st: State = serde_json::from_value(r.body).unwrap();
    assert_eq!(st.phase, "practice");
    let trial = st.trial.clone().unwrap();
    let answer = |trial: u32, practice: bool| {
        json!({"tab": "A", "session": 1, "practice": practice, "trial": trial, "response": 1,
               "timing": {"rt_ms": 500.0}})
    };
    // The current trial's answer with one field (`outer` or `outer.inner`) set to `value`
    // (a body for a bad case).
    let answer_with = |field: &str, value: Value| {
        let mut a = answer(1, true);
        match field.split_once('.') {
            Some((outer, inner)) => a[outer][inner] = value,
            None => a[field] = value,
        }
        Some(a.to_string())
    };
    // The first answer is stored; the replay is acknowledged without a second line.
    let r = post(&http, &api("answer"), answer(0, true)).await.unwrap();
    assert_eq!(r.status, 200, "{}", r.body);
    let first_ack = r.body["ack"].clone();
    let log_path = out.join("sessions").join(format!("{subject}.jsonl"));
    let log_before = std::fs::read(&log_path).unwrap();
    let first_id = trial.pairs[0][0].clone();
    let practice0 = &experiment::trials::plan(&design, &subject).practice[0];
    let trial_stimulus = practice0.video(1, experiment::log::Side::Left).to_string();
    let handle = {
        let r = http.get(api("state?tab=A")).send().await.unwrap();
        let st: State = serde_json::from_slice(&r.bytes().await.unwrap()).unwrap();
        st.trial.unwrap().pairs[1][1].clone()
    };
    let p = |s: &str| format!("/api/s/{token}/{s}");
    let design_stimulus = experiment::trials::plan(&design, &subject).main[0]
        .test_stimulus
        .clone();
    let big = format!("{{\"tab\":\"A\",\"pad\":\"{}\"}}", "x".repeat(300 * 1024));
    let cases = vec![
        Case {
            what: "replayed answer",
            method: "POST",
            path: p("answer"),
            body: Some(answer(0, true).to_string()),
            status: 200,
            message: "",
        },
        Case {
            what: "answer for a later trial",
            method: "POST",
            path: p("answer"),
            body: Some(answer(5, false).to_string()),
            status: 409,
            message: "is not the trial being presented",
        },
        Case {
            what: "answer for session 2",
            method: "POST",
            path: p("answer"),
            body: Some(
                json!({"tab":"A","session":2,"practice":true,"trial":1,"response":1,
                                 "timing":{"rt_ms":1.0}})
                .to_string(),
            ),
            status: 409,
            message: "session 1 only",
        },
        Case {
            what: "response 3",
            method: "POST",
            path: p("answer"),
            body: Some(
                json!({"tab":"A","session":1,"practice":true,"trial":1,"response":3,
                                 "timing":{"rt_ms":1.0}})
                .to_string(),
            ),
            status: 400,
            message: "field `response` is 3",
        },
        Case {
            what: "bad JSON",
            method: "POST",
            path: p("answer"),
            body: Some("{\"tab\":".into()),
            status: 400,
            message: "EOF while parsing",
        },
        Case {
            what: "wrong type",
            method: "POST",
            path: p("answer"),
            body: Some(
                json!({"tab":"A","session":1,"practice":"yes","trial":1,"response":1,
                                 "timing":{"rt_ms":1.0}})
                .to_string(),
            ),
            status: 400,
            message: "field `practice`",
        },
        Case {
            what: "oversize body",
            method: "POST",
            path: p("claim"),
            body: Some(big),
            status: 413,
            message: "larger than",
        },
        Case {
            what: "second tab claims",
            method: "POST",
            path: p("claim"),
            body: Some(json!({"tab":"B"}).to_string()),
            status: 409,
            message: "open in another tab or window",
        },
        Case {
            what: "second tab answers",
            method: "POST",
            path: p("answer"),
            body: Some(
                json!({"tab":"B","session":1,"practice":true,"trial":1,"response":1,
                                 "timing":{"rt_ms":1.0}})
                .to_string(),
            ),
            status: 409,
            message: "open in another tab or window",
        },
        Case {
            what: "bad tab id",
            method: "POST",
            path: p("claim"),
            body: Some(json!({"tab":"../x"}).to_string()),
            status: 400,
            message: "field `tab`",
        },
        Case {
            what: "unknown token",
            method: "POST",
            path: format!("/api/s/{}/claim", "0".repeat(32)),
            body: Some(json!({"tab":"A"}).to_string()),
            status: 404,
            message: "not known to the server",
        },
        Case {
            what: "not a token",
            method: "GET",
            path: "/api/s/..%2f..%2fetc/state?tab=A".into(),
            body: None,
            status: 404,
            message: "",
        },
        Case {
            what: "uppercase token",
            method: "GET",
            path: format!("/api/s/{}/state?tab=A", token.to_uppercase()),
            body: None,
            status: 404,
            message: "not known to the server",
        },
        Case {
            what: "state without tab",
            method: "GET",
            path: p("state"),
            body: None,
            status: 400,
            message: "query `tab`",
        },
        Case {
            what: "another link's video id",
            method: "GET",
            path: format!("/api/s/{other_token}/video/{handle}"),
            body: None,
            status: 404,
            message: "no such video",
        },
        Case {
            what: "a stimulus by its name",
            method: "GET",
            path: p(&format!("video/{}", design_stimulus)),
            body: None,
            status: 404,
            message: "no such video",
        },
        Case {
            what: "uppercase id",
            method: "GET",
            path: p(&format!("video/{}", handle.to_uppercase())),
            body: None,
            status: 404,
            message: "no such video",
        },
        Case {
            what: "traversal in id",
            method: "GET",
            path: p("video/..%2f..%2fdesign.json"),
            body: None,
            status: 404,
            message: "no such video",
        },
        // (The client's URL parser resolves `%2e%2e` as `..` before sending: the server sees a
        // shorter path, which no route matches.)
        Case {
            what: "encoded dots",
            method: "GET",
            path: p("video/%2e%2e"),
            body: None,
            status: 404,
            message: "no such",
        },
        Case {
            what: "encoded dots in an id",
            method: "GET",
            path: p("video/a%2e%2e"),
            body: None,
            status: 404,
            message: "no such video",
        },
        Case {
            what: "absolute path",
            method: "GET",
            path: p("video/%2fetc%2fpasswd"),
            body: None,
            status: 404,
            message: "no such video",
        },
        Case {
            what: "manifest by name",
            method: "GET",
            path: p("video/manifest.json"),
            body: None,
            status: 404,
            message: "no such video",
        },
        Case {
            what: "asset traversal",
            method: "GET",
            path: "/assets/..%2f..%2fCargo.toml".into(),
            body: None,
            status: 404,
            message: "no such file",
        },
        Case {
            what: "asset dots",
            method: "GET",
            path: "/assets/%2e%2e/Cargo.toml".into(),
            body: None,
            status: 404,
            message: "",
        },
        Case {
            what: "unknown route",
            method: "GET",
            path: "/stimuli/tiny/manifest.json".into(),
            body: None,
            status: 404,
            message: "no such page",
        },
        Case {
            what: "admin without token",
            method: "GET",
            path: "/admin/progress.json".into(),
            body: None,
            status: 401,
            message: "admin token",
        },
        Case {
            what: "a method the route does not take",
            method: "PUT",
            path: p("answer"),
            body: Some("{}".into()),
            status: 405,
            message: "method",
        },
        Case {
            what: "a body nested past any answer",
            method: "POST",
            path: p("answer"),
            body: Some(format!(
                "{{\"tab\": {}{}}}",
                "[".repeat(50_000),
                "]".repeat(50_000)
            )),
            status: 400,
            message: "field `tab`",
        },
        Case {
            what: "an answer with a field the API does not have",
            method: "POST",
            path: p("answer"),
            body: answer_with("level", json!(8)),
            status: 400,
            message: "unknown field `level`",
        },
        Case {
            what: "an answer's timing with a field the API does not have",
            method: "POST",
            path: p("answer"),
            body: answer_with("timing.level", json!(8)),
            status: 400,
            message: "unknown field `level`",
        },
        Case {
            what: "a browser's answer with pauses",
            method: "POST",
            path: p("answer"),
            body: answer_with("timing.pauses", json!(2)),
            status: 400,
            message: "`timing.pauses` is 2",
        },
        Case {
            what: "frame times going back",
            method: "POST",
            path: p("answer"),
            body: answer_with("timing.frame_times_ms", json!([20.0, 10.0])),
            status: 400,
            message: "`timing.frame_times_ms`",
        },
        Case {
            what: "more dropped frames than the trial shows",
            method: "POST",
            path: p("answer"),
            body: answer_with("timing.dropped_frames", json!(1_000_000)),
            status: 400,
            message: "`timing.dropped_frames`",
        },
        Case {
            what: "admin with a wrong token",
            method: "GET",
            path: format!("/admin?token={}", "f".repeat(32)),
            body: None,
            status: 401,
            message: "admin token",
        },
    ];
    for c in &cases {
        let (status, body) = send(&http, &base, c).await;
        assert_eq!(status, c.status, "{}: {body}", c.what);
        if status >= 400 {
            let msg = body["error"]
                .as_str()
                .unwrap_or_else(|| panic!("{}: no JSON error: {body}", c.what));
            assert!(
                msg.contains(c.message),
                "{}: {msg:?} lacks {:?}",
                c.what,
                c.message
            );
        } else {
            assert_eq!(body["ack"], first_ack, "{}", c.what);
        }
    }
    assert_eq!(
        std::fs::read(&log_path).unwrap(),
        log_before,
        "nothing was written"
    );
    let r = http.get(api("state?tab=A")).send().await.unwrap();
    let st: State = serde_json::from_slice(&r.bytes().await.unwrap()).unwrap();
    assert_eq!(
        (st.progress.practice_done, st.trial.unwrap().index),
        (1, 1),
        "nothing moved"
    );

    // A video is the stimulus's frames as lossless WebP, pixel for pixel; headers leak nothing.
    let r = http
        .get(api(&format!("video/{first_id}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 200);
    let h = r.headers().clone();
    assert_eq!(h["content-type"], "application/octet-stream");
    assert_eq!(h["cache-control"], "no-store");
    assert!(h.get("etag").is_none() && h.get("last-modified").is_none());
    assert!(h.get("content-disposition").is_none());
    let bytes = r.bytes().await.unwrap();
    let frames = experiment::web::packs::split(&bytes).unwrap();
    assert_eq!(frames.len(), 6);
    let stimulus = &trial_stimulus;
    let manifest = renderer::manifest::Manifest::load(&design.manifest_path).unwrap();
    let folder = design.manifest_path.parent().unwrap();
    let files = &manifest.get(stimulus).unwrap().frame_paths;
    for (n, range) in frames.iter().enumerate() {
        let got = image::load_from_memory(&bytes[range.clone()])
            .unwrap()
            .into_rgb8();
        let want = image::open(folder.join(&files[n])).unwrap().into_rgb8();
        assert_eq!(got.as_raw(), want.as_raw(), "frame {n} of {stimulus}");
    }

    // Every page carries the security headers.
    let r = http.get(format!("{base}/s/{token}")).send().await.unwrap();
    assert_eq!(r.status(), 200);
    let csp = r.headers()["content-security-policy"]
        .to_str()
        .unwrap()
        .to_string();
    assert!(
        csp.contains("default-src 'self'") && !csp.contains("unsafe-inline"),
        "{csp}"
    );
    assert_eq!(r.headers()["x-content-type-options"], "nosniff");
    assert_eq!(r.headers()["referrer-policy"], "no-referrer");

    // The admin token opens the progress: a Bearer header in any case of the scheme, or the
    // query the page takes.
    let admin = &server.started.admin_token;
    let progress = format!("{base}/admin/progress.json");
    for req in [
        http.get(&progress).bearer_auth(admin),
        http.get(&progress)
            .header("authorization", format!("bearer {admin}")),
        http.get(&progress)
            .header("authorization", format!("BEARER  {admin}")),
        http.get(format!("{progress}?token={admin}")),
    ] {
        let r = req.send().await.unwrap();
        assert_eq!(r.status(), 200);
        let v: Value = serde_json::from_slice(&r.bytes().await.unwrap()).unwrap();
        assert_eq!(
            (v["enrolled"].as_u64(), v["started"].as_u64()),
            (Some(2), Some(1))
        );
    }

    // The JSON the browser saw names no level, point set, scene or stimulus.
    let r = http.get(api("state?tab=A")).send().await.unwrap();
    let text = String::from_utf8(r.bytes().await.unwrap().to_vec()).unwrap();
    for secret in [
        "alpha",
        "beta",
        "random",
        "stratified",
        "box",
        "diff",
        "level",
        "spp",
    ] {
        assert!(!text.contains(secret), "state names {secret:?}: {text}");
    }
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn guessing_links_is_rate_limited_per_address() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let out = dir.path().join("study");
    let server = Running::start(&config(&study.design_path, &out, 1)).await;
    let http = reqwest::Client::new();
    let mut statuses = Vec::new();
    for i in 0..40 {
        let url = format!("{}/api/s/{:032x}/state?tab=A", server.base, i);
        statuses.push(http.get(url).send().await.unwrap().status().as_u16());
    }
    assert_eq!(statuses[0], 404);
    assert_eq!(*statuses.last().unwrap(), 429, "{statuses:?}");
    // Behind a proxy every subject shares the guesser's address: a known link still opens
    // (issue 51 item 6).
    let (_, token) = tokens(&out)[0].clone();
    let r = post(
        &http,
        &format!("{}/api/s/{token}/claim", server.base),
        json!({"tab": "A"}),
    )
    .await
    .unwrap();
    assert_eq!(r.status, 200, "{}", r.body);
    server.stop().await;
}

/// Issue 51 item 6: a connection that sends no request head, or half of one, or stays idle
/// after a request, is closed after the header timeout; past the connection cap a new one is
/// closed at once; and the server still answers afterwards.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn slow_idle_and_surplus_connections_are_closed() {
    use std::io::{Read, Write};
    use std::net::TcpStream;
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let design = Design::load(&study.design_path).unwrap();
    let mut cfg = config(&design.path, &dir.path().join("study"), 1);
    cfg.connections = experiment::web::connections::Limits {
        header_read_timeout: Duration::from_millis(700),
        max_connections: 4,
    };
    let server = Running::start(&cfg).await;
    let addr = server.started.addr;
    let held = tokio::task::spawn_blocking(move || {
        // Reads until the server closes; the time it took.
        let closed_after = |mut s: TcpStream| {
            let t = Instant::now();
            s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
            let mut buf = vec![0u8; 4096];
            loop {
                match s.read(&mut buf) {
                    Ok(0) => return t.elapsed(),
                    Ok(_) => continue,
                    Err(e)
                        if e.kind() == std::io::ErrorKind::WouldBlock
                            || e.kind() == std::io::ErrorKind::TimedOut =>
                    {
                        panic!("held open for 10 s")
                    }
                    Err(_) => return t.elapsed(),
                }
            }
        };
        let silent = TcpStream::connect(addr).unwrap();
        let mut half = TcpStream::connect(addr).unwrap();
        half.write_all(b"GET /admin HTTP/1.1\r\nHost: x\r\n")
            .unwrap();
        let mut idle = TcpStream::connect(addr).unwrap();
        idle.write_all(b"GET /nothing HTTP/1.1\r\nHost: x\r\n\r\n")
            .unwrap();
        let fourth = TcpStream::connect(addr).unwrap();
        std::thread::sleep(Duration::from_millis(100));
        // Four held: the fifth is over the cap.
        let surplus = closed_after(TcpStream::connect(addr).unwrap());
        let mut out = vec![("surplus", surplus)];
        for (what, s) in [
            ("silent", silent),
            ("half a head", half),
            ("idle", idle),
            ("fourth", fourth),
        ] {
            out.push((what, closed_after(s)));
        }
        out
    })
    .await
    .unwrap();
    assert!(held[0].1 < Duration::from_millis(500), "{held:?}");
    for (what, t) in &held[1..] {
        assert!(*t < Duration::from_secs(3), "{what}: held {t:?}");
    }
    // Every permit is back: a request is answered.
    let r = reqwest::get(format!("http://{addr}/nothing"))
        .await
        .unwrap();
    assert_eq!(r.status(), 404);
    server.stop().await;
}
