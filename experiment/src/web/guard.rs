//! Limits and headers on every request: token buckets (per subject link, and per client address
//! for look-ups of unknown links, which is what guessing a link looks like) and the security
//! headers of every response.

use axum::extract::{Request, State};
use axum::http::{HeaderValue, header};
use axum::middleware::Next;
use axum::response::Response;
use std::collections::HashMap;
use std::sync::Mutex;
use std::time::Instant;

/// A token bucket: `capacity` requests at once, refilled at `per_second`.
#[derive(Clone, Copy, Debug)]
pub struct Rate {
    pub capacity: f64,
    pub per_second: f64,
}

/// Per link: a trial fetches every frame of its four videos at once (4 x frames requests), so
/// the burst is large; the sustained rate is far above a person's and far below a flood's.
pub const PER_LINK: Rate = Rate {
    capacity: 1000.0,
    per_second: 200.0,
};

/// Per client address, for requests naming an unknown link: a mistyped link a few times is fine,
/// a search for links is not (at this rate, 2^128 tokens take forever anyway).
pub const PER_ADDRESS_UNKNOWN: Rate = Rate {
    capacity: 30.0,
    per_second: 0.5,
};

#[derive(Debug)]
struct Bucket {
    level: f64,
    at: Instant,
}

/// Token buckets by key.
#[derive(Debug)]
pub struct Limiter {
    rate: Rate,
    buckets: Mutex<HashMap<String, Bucket>>,
}

impl Limiter {
    pub fn new(rate: Rate) -> Self {
        Self {
            rate,
            buckets: Mutex::new(HashMap::new()),
        }
    }

    fn refilled(&self, b: &mut Bucket, now: Instant) {
        let dt = now.duration_since(b.at).as_secs_f64();
        b.level = (b.level + dt * self.rate.per_second).min(self.rate.capacity);
        b.at = now;
    }

    /// Take one request from `key`'s bucket; false when it is empty.
    pub fn take(&self, key: &str) -> bool {
        let now = Instant::now();
        let mut map = self.buckets.lock().unwrap_or_else(|e| e.into_inner());
        if map.len() > 100_000 {
            // Forget the keys whose buckets are full again: they owe nothing.
            map.retain(|_, b| {
                let dt = now.duration_since(b.at).as_secs_f64();
                b.level + dt * self.rate.per_second < self.rate.capacity
            });
        }
        let b = map.entry(key.to_string()).or_insert(Bucket {
            level: self.rate.capacity,
            at: now,
        });
        self.refilled(b, now);
        if b.level >= 1.0 {
            b.level -= 1.0;
            true
        } else {
            false
        }
    }

    /// Whether `key` has a request left, without taking it.
    pub fn has(&self, key: &str) -> bool {
        let now = Instant::now();
        let mut map = self.buckets.lock().unwrap_or_else(|e| e.into_inner());
        match map.get_mut(key) {
            Some(b) => {
                self.refilled(b, now);
                b.level >= 1.0
            }
            None => true,
        }
    }
}

/// The content security policy of every response: this origin only (and the static server of
/// `video_base`, for `fetch` only), no inline script or style, no framing; frames are decoded
/// from `fetch`ed WebP (`blob:` images) onto a canvas.
pub fn csp(video_base: Option<&str>) -> HeaderValue {
    let extra = video_base
        .map(origin)
        .map_or(String::new(), |o| format!(" {o}"));
    let text = format!(
        "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' blob: data:; \
         connect-src 'self'{extra}; object-src 'none'; base-uri 'none'; form-action 'self'; \
         frame-ancestors 'none'"
    );
    HeaderValue::from_str(&text).unwrap_or_else(|_| HeaderValue::from_static("default-src 'self'"))
}

/// `scheme://host[:port]` of a URL (the part a CSP source names).
fn origin(url: &str) -> String {
    let (scheme, rest) = url.split_once("://").unwrap_or(("https", url));
    let host = rest.split('/').next().unwrap_or("");
    format!("{scheme}://{host}")
}

/// Security headers on every response; `Cache-Control: no-store` on everything but the
/// client's static files.
pub async fn headers(State(csp): State<HeaderValue>, req: Request, next: Next) -> Response {
    let cacheable = req.uri().path().starts_with("/assets/");
    let mut res = next.run(req).await;
    let h = res.headers_mut();
    h.insert(header::CONTENT_SECURITY_POLICY, csp);
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    h.insert(
        header::REFERRER_POLICY,
        HeaderValue::from_static("no-referrer"),
    );
    h.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    h.insert(
        header::CACHE_CONTROL,
        HeaderValue::from_static(if cacheable { "no-cache" } else { "no-store" }),
    );
    res
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_policy_names_the_video_server_s_origin_only_for_fetch() {
        let p = csp(Some("https://cdn.example.org/study1/v"));
        let p = p.to_str().unwrap();
        assert!(
            p.contains("connect-src 'self' https://cdn.example.org;"),
            "{p}"
        );
        assert!(p.contains("script-src 'self';"), "{p}");
        assert!(csp(None).to_str().unwrap().contains("connect-src 'self';"));
    }

    #[test]
    fn a_bucket_empties_after_its_capacity() {
        let l = Limiter::new(Rate {
            capacity: 3.0,
            per_second: 0.001,
        });
        assert!(l.take("a") && l.take("a") && l.take("a"));
        assert!(!l.take("a"));
        assert!(!l.has("a"));
        assert!(l.take("b"), "buckets are per key");
    }
}
