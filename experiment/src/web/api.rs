//! The routes (docs/web.md, "HTTP API"). Every handler that touches a session runs it on a
//! blocking thread: answering syncs the log (`fsync`), which must not stall the async workers
//! that serve everyone else.

use super::error::{ApiError, UNKNOWN_LINK};
use super::subject::Subject;
use super::wire::{Advance, Claim, ConsentAnswer, DisplayFacts, ScreenOut};
use super::{App, BODY_LIMIT, Entry, admin, assets, guard, participant, tokens};
use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::{ConnectInfo, DefaultBodyLimit, Path, Query, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Redirect, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::Arc;

type Shared = State<Arc<App>>;
type Peer = ConnectInfo<SocketAddr>;

pub(crate) fn router(app: Arc<App>, csp: axum::http::HeaderValue) -> Router {
    Router::new()
        .route("/s/{token}", get(page))
        .route("/assets/{name}", get(asset))
        .route("/join/{token}", get(join))
        .route("/api/s/{token}/claim", post(claim))
        .route("/api/s/{token}/state", get(state))
        .route("/api/s/{token}/display", post(display))
        .route("/api/s/{token}/advance", post(advance))
        .route("/api/s/{token}/consent", post(consent))
        .route("/api/s/{token}/screen_out", post(screen_out))
        .route("/api/s/{token}/answer", post(answer))
        .route("/api/s/{token}/video/{id}", get(video))
        .route("/admin", get(admin::page))
        .route("/admin/progress.json", get(admin::progress))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .layer(axum::middleware::from_fn_with_state(csp, guard::headers))
        .with_state(app)
}

async fn not_found() -> ApiError {
    ApiError::not_found("no such page")
}

async fn method_not_allowed() -> ApiError {
    ApiError::new(
        StatusCode::METHOD_NOT_ALLOWED,
        "this address does not take that method (docs/web.md, \"HTTP API\", lists each route's)",
    )
}

/// The subject behind `token`, after the rate limits: unknown links count against the client's
/// address, known ones against the link.
fn lookup(app: &App, token: &str, peer: SocketAddr) -> Result<Arc<Entry>, ApiError> {
    // Only unknown links count against the address: behind a TLS proxy every subject shares
    // one address, and guesses there must not lock out the subjects whose links are known.
    let ip = peer.ip().to_string();
    let found = tokens::looks_like_token(token)
        .then(|| {
            app.by_token
                .read()
                .unwrap_or_else(|e| e.into_inner())
                .get(token)
                .cloned()
        })
        .flatten();
    match found {
        Some(e) if app.per_link.take(token) => Ok(e),
        Some(_) => Err(too_many()),
        None if !app.per_address.take(&ip) => Err(too_many()),
        None => Err(ApiError::not_found(UNKNOWN_LINK)),
    }
}

fn too_many() -> ApiError {
    ApiError::new(
        StatusCode::TOO_MANY_REQUESTS,
        "too many requests; wait a few seconds and try again",
    )
}

/// A JSON body of type `T`, or a 413/400 naming what is wrong.
fn parse<T: DeserializeOwned>(body: Result<Bytes, BytesRejection>) -> Result<T, ApiError> {
    let body = body.map_err(|e| {
        if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::new(
                StatusCode::PAYLOAD_TOO_LARGE,
                format!("the request body is larger than {BODY_LIMIT} bytes"),
            )
        } else {
            ApiError::bad_request(format!("cannot read the request body: {e}"))
        }
    })?;
    let de = &mut serde_json::Deserializer::from_slice(&body);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        ApiError::bad_request(if path == "." {
            format!("the request body is not the JSON expected: {inner}")
        } else {
            format!("field `{path}`: {inner}")
        })
    })
}

/// Run `f` on the subject, on a blocking thread; reply with its value as JSON.
async fn with_subject<T: Serialize + Send + 'static>(
    app: Arc<App>,
    entry: Arc<Entry>,
    f: impl FnOnce(&App, &mut Subject) -> Result<T, ApiError> + Send + 'static,
) -> Result<Response, ApiError> {
    let out = tokio::task::spawn_blocking(move || {
        let mut s = entry.subject.lock().unwrap_or_else(|e| e.into_inner());
        f(&app, &mut s)
    })
    .await
    .map_err(|e| ApiError::internal(&anyhow::anyhow!("{e}")))??;
    Ok(Json(out).into_response())
}

/// A POST on a subject's link: its body parsed as `T`, then `f` on the subject (as
/// [`with_subject`]).
async fn post_to_subject<T, R>(
    app: Arc<App>,
    peer: SocketAddr,
    token: &str,
    body: Result<Bytes, BytesRejection>,
    f: impl FnOnce(&App, &mut Subject, T) -> Result<R, ApiError> + Send + 'static,
) -> Result<Response, ApiError>
where
    T: DeserializeOwned + Send + 'static,
    R: Serialize + Send + 'static,
{
    let entry = lookup(&app, token, peer)?;
    let request: T = parse(body)?;
    with_subject(app, entry, move |app, s| f(app, s, request)).await
}

/// `reply`, once what the subject's answer changed of their platform record (consent, screen
/// out) is in `tokens.json`.
fn persisted<R>(app: &App, s: &Subject, reply: R) -> Result<R, ApiError> {
    participant::persist(app, s)?;
    Ok(reply)
}

async fn page(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
) -> Result<Response, ApiError> {
    lookup(&app, &token, peer)?;
    Ok((
        [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
        assets::INDEX_HTML,
    )
        .into_response())
}

async fn asset(Path(name): Path<String>) -> Result<Response, ApiError> {
    let a = assets::asset(&name).ok_or_else(|| ApiError::not_found("no such file"))?;
    Ok(([(header::CONTENT_TYPE, a.mime)], a.body).into_response())
}

/// Open enrolment: a new subject (or, for a platform participant seen before, theirs) and a
/// redirect to their link.
async fn join(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    q: Result<Query<HashMap<String, String>>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, ApiError> {
    let Query(query) = q.map_err(|e| ApiError::bad_request(format!("the link's query: {e}")))?;
    let app2 = app.clone();
    let made = tokio::task::spawn_blocking(move || participant::join(&app2, &token, &query))
        .await
        .map_err(|e| ApiError::internal(&anyhow::anyhow!("{e}")))?;
    match made {
        Ok(t) => Ok(Redirect::to(&format!("/s/{t}")).into_response()),
        // As for subject links (`lookup`): only an unknown join link counts against the
        // address, so guesses behind a shared proxy address do not turn participants away.
        Err(e)
            if e.status == StatusCode::NOT_FOUND
                && !app.per_address.take(&peer.ip().to_string()) =>
        {
            Err(too_many())
        }
        Err(e) => Err(e),
    }
}

async fn consent(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    post_to_subject(app, peer, &token, body, |app, s, c: ConsentAnswer| {
        let state = s.consent(&app.study, &c.tab, c.accept)?;
        persisted(app, s, state)
    })
    .await
}

async fn screen_out(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    post_to_subject(app, peer, &token, body, |app, s, r: ScreenOut| {
        let state = s.screen_out(&app.study, &r.tab, &r.reason)?;
        persisted(app, s, state)
    })
    .await
}

async fn claim(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    post_to_subject(app, peer, &token, body, |app, s, c: Claim| {
        s.claim(&app.study, &c.tab)
    })
    .await
}

#[derive(serde::Deserialize)]
struct TabQuery {
    tab: Option<String>,
}

async fn state(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    q: Result<Query<TabQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, ApiError> {
    let entry = lookup(&app, &token, peer)?;
    let tab = q
        .ok()
        .and_then(|Query(q)| q.tab)
        .ok_or_else(|| ApiError::bad_request("query `tab`: expected ?tab=<this tab's id>"))?;
    with_subject(app, entry, move |app, s| s.get_state(&app.study, &tab)).await
}

async fn display(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    post_to_subject(app, peer, &token, body, |app, s, d: DisplayFacts| {
        let state = s.display(&app.study, &d)?;
        persisted(app, s, state)
    })
    .await
}

async fn advance(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    post_to_subject(app, peer, &token, body, |app, s, a: Advance| {
        s.advance(&app.study, &a.tab, &a.from)
    })
    .await
}

async fn answer(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path(token): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    post_to_subject(app, peer, &token, body, |app, s, a: super::wire::Answer| {
        s.answer(&app.study, &a)
    })
    .await
}

/// The encoded video behind `id` (a frame pack, streamed from the stimulus set's cache). The
/// id is one of this subject's; nothing in the request becomes a path.
async fn video(
    State(app): Shared,
    ConnectInfo(peer): Peer,
    Path((token, id)): Path<(String, String)>,
) -> Result<Response, ApiError> {
    let entry = lookup(&app, &token, peer)?;
    let stimulus = tokens::looks_like_token(&id)
        .then(|| entry.videos.stimulus_of.get(&id))
        .flatten()
        .ok_or_else(|| ApiError::not_found("no such video: the address is wrong"))?;
    let served = app
        .study
        .video_of(stimulus)
        .ok_or_else(|| ApiError::not_found("no such video: the address is wrong"))?;
    let file = tokio::fs::File::open(&served.path).await.map_err(|e| {
        ApiError::internal(&anyhow::anyhow!(
            "an encoded video cannot be read ({e}); tell the experimenter"
        ))
    })?;
    Ok((
        [
            (header::CONTENT_TYPE, "application/octet-stream".to_string()),
            (header::CONTENT_LENGTH, served.pack.bytes.to_string()),
        ],
        axum::body::Body::from_stream(super::stream::chunks(file)),
    )
        .into_response())
}
