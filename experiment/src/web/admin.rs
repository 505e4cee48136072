//! The experimenter's view: progress of every subject, behind the admin token (a `Bearer`
//! header, or `?token=` for the page in a browser), compared in constant time.

use super::error::ApiError;
use super::subject::SubjectProgress;
use super::{App, tokens};
use axum::extract::{Query, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use std::sync::Arc;

#[derive(Debug, Serialize)]
pub struct Overview {
    pub design: String,
    pub enrolled: usize,
    pub started: usize,
    pub finished: usize,
    /// Participants screened out before any trial (consent declined, display check failed).
    pub screened_out: usize,
    /// Subjects the design's exclusion criteria flag so far.
    pub flagged: usize,
    pub trials_done: usize,
    pub trials_planned: usize,
    /// Seconds until the slowest active subject is expected to finish, at the pace each has
    /// kept in this run of the server; absent before any answers.
    pub expected_finish_s: Option<f64>,
    pub subjects: Vec<SubjectProgress>,
}

#[derive(serde::Deserialize)]
pub struct TokenQuery {
    token: Option<String>,
}

fn authorized(app: &App, headers: &HeaderMap, query: Option<&str>) -> Result<(), ApiError> {
    // RFC 9110: the scheme is case-insensitive, separated from the token by white space.
    let bearer = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().split_once(' '))
        .filter(|(scheme, _)| scheme.eq_ignore_ascii_case("bearer"))
        .map(|(_, token)| token.trim());
    let given = bearer.or(query).unwrap_or("");
    let admin = app
        .tokens
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .admin
        .clone();
    if tokens::same_secret(&admin, given) {
        Ok(())
    } else {
        Err(ApiError::new(
            StatusCode::UNAUTHORIZED,
            "the admin pages need the admin token that `blurlab serve` printed",
        ))
    }
}

fn overview(app: &App) -> Overview {
    let entries: Vec<_> = app
        .by_token
        .read()
        .unwrap_or_else(|e| e.into_inner())
        .values()
        .cloned()
        .collect();
    let mut subjects: Vec<SubjectProgress> = entries
        .iter()
        .map(|e| {
            e.subject
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .progress(&app.study)
        })
        .collect();
    subjects.sort_by(|a, b| a.subject.cmp(&b.subject));
    let expected_finish_s = subjects
        .iter()
        .filter(|s| s.started && !s.finished && s.run_answers > 0)
        .map(|s| (s.planned - s.done.min(s.planned)) as f64 * s.run_seconds / s.run_answers as f64)
        .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))));
    Overview {
        design: app.study.design.name().to_string(),
        enrolled: subjects.len(),
        started: subjects.iter().filter(|s| s.started).count(),
        finished: subjects.iter().filter(|s| s.finished).count(),
        screened_out: subjects.iter().filter(|s| s.screened_out.is_some()).count(),
        flagged: subjects.iter().filter(|s| !s.flags.is_empty()).count(),
        trials_done: subjects.iter().map(|s| s.done).sum(),
        trials_planned: subjects.iter().map(|s| s.planned).sum(),
        expected_finish_s,
        subjects,
    }
}

async fn overview_blocking(app: Arc<App>) -> Result<Overview, ApiError> {
    tokio::task::spawn_blocking(move || overview(&app))
        .await
        .map_err(|e| ApiError::internal(&anyhow::anyhow!("{e}")))
}

pub async fn progress(
    State(app): State<Arc<App>>,
    headers: HeaderMap,
    q: Result<Query<TokenQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, ApiError> {
    let query = q.ok().and_then(|Query(q)| q.token);
    authorized(&app, &headers, query.as_deref())?;
    Ok(axum::Json(overview_blocking(app).await?).into_response())
}

pub async fn page(
    State(app): State<Arc<App>>,
    headers: HeaderMap,
    q: Result<Query<TokenQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, ApiError> {
    let query = q.ok().and_then(|Query(q)| q.token);
    authorized(&app, &headers, query.as_deref())?;
    let o = overview_blocking(app).await?;
    Ok((
        [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
        html(&o),
    )
        .into_response())
}

/// A plain page that refreshes itself (a meta refresh: no script, so the CSP holds).
fn html(o: &Overview) -> String {
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut rows = String::new();
    for s in &o.subjects {
        rows.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}/{}</td><td>{}</td></tr>\n",
            esc(&s.subject),
            esc(s.participant.as_deref().unwrap_or("")),
            if s.started { "yes" } else { "no" },
            if s.finished { "yes" } else { "no" },
            s.done,
            s.planned,
            esc(&match &s.screened_out {
                Some(why) => format!("screened out: {why}"),
                None => s.flags.join("; "),
            })
        ));
    }
    let eta = o
        .expected_finish_s
        .map_or("not yet known".to_string(), |s| {
            format!("in about {:.0} min", s / 60.0)
        });
    format!(
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta http-equiv=\"refresh\" content=\"10\"><title>blurlab: {design}</title></head>\
         <body><h1>{design}</h1><p>{enrolled} enrolled, {started} started, {finished} finished, \
         {screened} screened out, {flagged} flagged for exclusion; {done} of {planned} trials; \
         expected finish {eta}.</p>\
         <table><tr><th>subject</th><th>participant</th><th>started</th><th>finished</th>\
         <th>trials</th><th>flags</th></tr>\n\
         {rows}</table></body></html>",
        design = esc(&o.design),
        enrolled = o.enrolled,
        started = o.started,
        finished = o.finished,
        screened = o.screened_out,
        flagged = o.flagged,
        done = o.trials_done,
        planned = o.trials_planned,
    )
}
