//! Participants from a recruitment platform (issue 49, the design's `online`): the study link
//! `/join/{token}?PROLIFIC_PID=...` makes one subject per participant id (a second visit with
//! the same id goes back to the same subject), consent before the display check, a screen-out
//! before any trial (consent declined, the display check failed, the window too small), and
//! where the browser goes at the end: the completion or the screen-out URL with its code.

use super::error::{ApiError, UNKNOWN_LINK};
use super::study::Study;
use super::subject::Subject;
use super::wire::State;
use super::{App, tokens};
use crate::design::online::Online;
use crate::log::{Consent, SessionLog};
use axum::http::StatusCode;
use std::collections::{BTreeMap, HashMap};

/// Longest participant id, and longest kept parameter value.
pub const MAX_ID_LEN: usize = 64;
pub const MAX_PARAM_LEN: usize = 128;

/// Reasons a client may give for leaving before any trial.
pub const CLIENT_REASONS: [&str; 2] = ["window_too_small", "browser_unsupported"];

/// A query value: 1 to `max` letters, digits, `_`, `-` or `.`; the error names the parameter.
fn check_value(name: &str, value: &str, max: usize) -> Result<(), ApiError> {
    if value.is_empty()
        || value.len() > max
        || !value
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'))
    {
        let shown: String = value.chars().take(80).collect();
        return Err(ApiError::bad_request(format!(
            "query parameter `{name}` is {shown:?}; expected 1 to {max} letters, digits, `_`, \
             `-` or `.` (the participant's id from the recruitment platform)"
        )));
    }
    Ok(())
}

/// The participant id and the kept parameters of a study link's query.
pub fn ids_of(
    online: &Online,
    query: &HashMap<String, String>,
) -> Result<BTreeMap<String, String>, ApiError> {
    let id_param = online.id_param();
    let Some(id) = query.get(&id_param) else {
        return Err(ApiError::bad_request(format!(
            "this study link needs the query parameter `{id_param}` (the participant's id from \
             the recruitment platform); open the study from the platform's page"
        )));
    };
    check_value(&id_param, id, MAX_ID_LEN)?;
    let mut ids = BTreeMap::from([(id_param, id.clone())]);
    for p in online.params() {
        if let Some(v) = query.get(&p) {
            check_value(&p, v, MAX_PARAM_LEN)?;
            ids.insert(p, v.clone());
        }
    }
    Ok(ids)
}

/// Open enrolment: the token of the subject `query` names (a platform participant seen before),
/// or of a new subject. Runs on a blocking thread (it saves `tokens.json`).
pub(crate) fn join(
    app: &App,
    token: &str,
    query: &HashMap<String, String>,
) -> Result<String, ApiError> {
    let mut t = app.tokens.lock().unwrap_or_else(|e| e.into_inner());
    let Some(open) = t.open.clone() else {
        return Err(ApiError::not_found(UNKNOWN_LINK));
    };
    if !tokens::same_secret(&open.token, token) {
        return Err(ApiError::not_found(UNKNOWN_LINK));
    }
    let online = app.study.design.file.online.as_ref();
    let ids = match online {
        Some(o) => Some(ids_of(o, query)?),
        None => None,
    };
    if let (Some(o), Some(ids)) = (online, &ids) {
        let key = o.id_param();
        if let Some(known) = t.subjects.iter().find(|s| s.ids.get(&key) == ids.get(&key)) {
            return Ok(known.token.clone());
        }
    }
    let have = t.count_with_prefix("o");
    if have >= open.cap {
        return Err(ApiError::new(
            StatusCode::GONE,
            "this study is full; thank you for your interest",
        ));
    }
    let mut s = t
        .add(format!("o{:03}", have + 1))
        .map_err(|e| ApiError::internal(&e))?;
    s.ids = ids.unwrap_or_default();
    if let Some(last) = t.subjects.last_mut() {
        last.ids = s.ids.clone();
    }
    // The subject exists once tokens.json says so: a restart keeps their link.
    if let Err(e) = t.save(&app.out) {
        t.subjects.pop();
        return Err(ApiError::internal(&e));
    }
    app.insert(&s);
    Ok(s.token)
}

/// Keep what the subject's participant record holds now (consent, screen-out) in
/// `tokens.json`, if it changed.
pub(crate) fn persist(app: &App, s: &Subject) -> Result<(), ApiError> {
    let mut t = app.tokens.lock().unwrap_or_else(|e| e.into_inner());
    let Some(k) = t.subjects.iter().position(|x| x.subject == s.name) else {
        return Ok(());
    };
    let entry = &t.subjects[k];
    if entry.consent == s.participant.consent && entry.screened_out == s.screened_out {
        return Ok(());
    }
    let before = entry.clone();
    t.subjects[k].consent = s.participant.consent.clone();
    t.subjects[k].screened_out = s.screened_out.clone();
    if let Err(e) = t.save(&app.out) {
        t.subjects[k] = before;
        return Err(ApiError::internal(&e));
    }
    Ok(())
}

impl Subject {
    /// The design's exclusion criteria the log fails so far (an unfinished session is not
    /// flagged while it runs).
    pub(super) fn flags(&self, study: &Study, started: bool) -> Vec<String> {
        let Some(c) = study.design.file.exclusion.as_ref().filter(|_| started) else {
            return Vec::new();
        };
        let c = crate::design::online::Exclusion {
            require_finished: false,
            ..c.clone()
        };
        match SessionLog::read(&self.log_path) {
            Ok(log) => crate::screening::facts(std::slice::from_ref(&log))
                .first()
                .map(|f| crate::screening::reasons(f, &c))
                .unwrap_or_default(),
            Err(_) => Vec::new(),
        }
    }

    /// The participant's answer to the consent text: agreed, logged in the header when the
    /// session starts; declined, screened out (no log is ever written).
    pub fn consent(&mut self, study: &Study, tab: &str, accept: bool) -> Result<State, ApiError> {
        self.open(study)?;
        self.check_claim(tab)?;
        let Some(text) = &study.consent else {
            return Err(ApiError::conflict("this study asks for no consent"));
        };
        if !self.has_started() && self.screened_out.is_none() && self.participant.consent.is_none()
        {
            if accept {
                self.participant.consent = Some(Consent {
                    unix: now_unix(),
                    text_sha256: text.sha256.clone(),
                });
            } else {
                self.screened_out = Some("consent declined".into());
            }
        }
        Ok(self.current_state(study))
    }

    /// Leave before any trial for a reason the page found (`CLIENT_REASONS`).
    pub fn screen_out(
        &mut self,
        study: &Study,
        tab: &str,
        reason: &str,
    ) -> Result<State, ApiError> {
        self.open(study)?;
        self.check_claim(tab)?;
        if !CLIENT_REASONS.contains(&reason) {
            return Err(ApiError::bad_request(format!(
                "field `reason` is {:?}; expected one of {}",
                reason.chars().take(40).collect::<String>(),
                CLIENT_REASONS.join(", ")
            )));
        }
        if self.has_started() {
            return Err(ApiError::conflict(
                "this session has begun; a participant is screened out only before the first trial",
            ));
        }
        self.screened_out
            .get_or_insert_with(|| reason.replace('_', " "));
        Ok(self.current_state(study))
    }
}

pub fn now_unix() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}
