//! What a browser sends, checked before it reaches a session: tab ids, display facts (the
//! ranges stated once in `experiment::display`) and answers (times in order, counts within the
//! frames the trial shows). Each refusal is a 400 naming the field.

use super::error::ApiError;
use super::wire::{Answer, DisplayFacts};
use crate::display;
use crate::log::Timing;

/// A tab id is the client's random string: 1 to 64 letters, digits, `-` or `_`.
pub(super) fn check_tab_id(tab: &str) -> Result<(), ApiError> {
    if tab.is_empty()
        || tab.len() > 64
        || !tab
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
    {
        return Err(ApiError::bad_request(
            "field `tab`: expected 1 to 64 letters, digits, `-` or `_`",
        ));
    }
    Ok(())
}

fn finite_nonnegative(name: &str, x: f64) -> Result<(), ApiError> {
    if x.is_finite() && x >= 0.0 {
        Ok(())
    } else {
        Err(ApiError::bad_request(format!(
            "field `{name}` is {x}; expected a finite number >= 0"
        )))
    }
}

pub(super) fn check_display(f: &DisplayFacts, need: [u32; 2]) -> Result<(), ApiError> {
    display::BrowserGeometry {
        device_pixel_ratio: f.device_pixel_ratio,
        px_per_mm: f.px_per_mm,
        viewing_distance_mm: f.viewing_distance_mm,
        pixels_per_degree: f.pixels_per_degree,
    }
    .check()
    .and_then(|()| {
        display::check_range(
            "refresh_interval_ms",
            f.refresh_interval_ms,
            display::REFRESH_INTERVAL_MS,
        )
    })
    .map_err(ApiError::bad_request)?;
    for (name, [w, h]) in [("screen_px", f.screen_px), ("window_px", f.window_px)] {
        if w == 0 || h == 0 || w > MAX_SCREEN_PX || h > MAX_SCREEN_PX {
            return Err(ApiError::bad_request(format!(
                "field `{name}` is [{w}, {h}]; expected [width, height] in device pixels, 1 to \
                 {MAX_SCREEN_PX} each"
            )));
        }
    }
    let ([sw, sh], [ww, wh]) = (f.screen_px, f.window_px);
    if ww > sw || wh > sh {
        return Err(ApiError::bad_request(format!(
            "field `window_px` is [{ww}, {wh}], larger than `screen_px` [{sw}, {sh}]; expected a \
             window inside its screen (both in device pixels)"
        )));
    }
    if ww < need[0] || wh < need[1] {
        return Err(ApiError::new(
            axum::http::StatusCode::UNPROCESSABLE_ENTITY,
            format!(
                "the window is {ww}x{wh} device pixels, but a trial needs {}x{} at 1:1; use a \
                 larger screen or window (full screen), or a lower browser zoom",
                need[0], need[1]
            ),
        ));
    }
    Ok(())
}

/// The widest screen side accepted, device pixels (an 8K screen is 7,680).
const MAX_SCREEN_PX: u32 = 16_384;
/// The longest response time accepted, milliseconds: a day. (A subject may leave the response
/// screen open; a larger number is not a time.)
const MAX_RT_MS: f64 = 86_400_000.0;

/// An answer's fields in range. `shown` is how many video frames the trial shows
/// ([`Study::frames_shown`]): no more can be timed, dropped or late.
pub(super) fn check_answer(a: &Answer, shown: u64) -> Result<(), ApiError> {
    if a.response != 1 && a.response != 2 {
        return Err(ApiError::bad_request(format!(
            "field `response` is {}; expected 1 or 2",
            a.response
        )));
    }
    check_timing(&a.timing, shown)
}

/// A browser's timing: times finite, non-negative and in order, counts within the frames the
/// trial shows. Messages name the field as `timing.<name>`.
fn check_timing(t: &Timing, shown: u64) -> Result<(), ApiError> {
    finite_nonnegative("timing.rt_ms", t.rt_ms)?;
    if t.rt_ms > MAX_RT_MS {
        return Err(ApiError::bad_request(format!(
            "field `timing.rt_ms` is {}; expected at most {MAX_RT_MS} (a day)",
            t.rt_ms
        )));
    }
    if t.pauses != 0 {
        return Err(ApiError::bad_request(format!(
            "field `timing.pauses` is {}; expected 0 (a browser session does not pause)",
            t.pauses
        )));
    }
    let refresh = t.refresh_interval_ms.unwrap_or(0.0);
    finite_nonnegative("timing.refresh_interval_ms", refresh)?;
    finite_nonnegative("timing.preload_ms", t.preload_ms)?;
    for (name, v) in [
        ("onsets_ms", &t.onsets_ms),
        ("frame_times_ms", &t.frame_times_ms),
    ] {
        if let Some(x) = v.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
            return Err(ApiError::bad_request(format!(
                "field `timing.{name}` holds {x}; expected finite times >= 0"
            )));
        }
        if let Some(w) = v.windows(2).find(|w| w[1] < w[0]) {
            return Err(ApiError::bad_request(format!(
                "field `timing.{name}` goes back from {} to {}; expected times in the order \
                 they happened",
                w[0], w[1]
            )));
        }
    }
    for (name, n) in [
        ("frame_times_ms", t.frame_times_ms.len() as u64),
        ("dropped_frames", u64::from(t.dropped_frames)),
        ("late_frames", u64::from(t.late_frames.unwrap_or(0))),
    ] {
        if n > shown {
            return Err(ApiError::bad_request(format!(
                "field `timing.{name}` counts {n} frames, but the trial shows {shown}; expected \
                 at most {shown}"
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts() -> DisplayFacts {
        DisplayFacts {
            tab: "t".into(),
            screen_px: [1920, 1080],
            window_px: [1920, 1000],
            device_pixel_ratio: 1.0,
            px_per_mm: 3.78,
            viewing_distance_mm: 600.0,
            pixels_per_degree: display::pixels_per_degree(3.78, 600.0),
            refresh_interval_ms: 16.7,
            user_agent: "test".into(),
            fullscreen: true,
        }
    }

    fn answer() -> Answer {
        Answer {
            tab: "t".into(),
            session: 1,
            practice: false,
            trial: 0,
            response: 1,
            timing: Timing {
                rt_ms: 800.0,
                onsets_ms: vec![10.0, 500.0],
                frame_times_ms: vec![10.0, 26.7, 43.3],
                dropped_frames: 0,
                pauses: 0,
                preload_ms: 5.0,
                late_frames: Some(0),
                refresh_interval_ms: Some(16.7),
            },
        }
    }

    /// A change that puts one field out of range.
    type Spoil<T> = fn(&mut T);

    fn message(e: ApiError) -> String {
        format!("{} {}", e.status, e.message)
    }

    /// Issue 51 item 4: each display fact out of range is refused naming its field.
    #[test]
    fn display_facts_out_of_range_are_refused_by_field() {
        check_display(&facts(), [200, 100]).unwrap();
        let cases: [(&str, Spoil<DisplayFacts>); 8] = [
            ("device_pixel_ratio", |f| f.device_pixel_ratio = 0.0),
            ("px_per_mm", |f| f.px_per_mm = -3.0),
            ("viewing_distance_mm", |f| f.viewing_distance_mm = 1e308),
            ("refresh_interval_ms", |f| f.refresh_interval_ms = 0.0),
            ("pixels_per_degree", |f| f.pixels_per_degree = 80.0),
            ("window_px", |f| f.window_px = [4000, 1000]),
            ("screen_px", |f| f.screen_px = [0, 1080]),
            ("window_px", |f| f.window_px = [u32::MAX, 1]),
        ];
        for (field, spoil) in cases {
            let mut f = facts();
            spoil(&mut f);
            let m = message(check_display(&f, [200, 100]).unwrap_err());
            assert!(
                m.starts_with("400") && m.contains(&format!("`{field}`")),
                "{field}: {m}"
            );
        }
        let m = message(check_display(&facts(), [4000, 100]).unwrap_err());
        assert!(m.starts_with("422") && !m.contains("  "), "{m}");
    }

    #[test]
    fn answers_out_of_range_are_refused_by_field() {
        check_answer(&answer(), 12).unwrap();
        let cases: [(&str, Spoil<Timing>); 9] = [
            ("rt_ms", |t| t.rt_ms = 1e300),
            ("frame_times_ms", |t| t.frame_times_ms = vec![30.0, 20.0]),
            ("frame_times_ms", |t| t.frame_times_ms = vec![-1.0]),
            ("onsets_ms", |t| t.onsets_ms = vec![500.0, 10.0]),
            ("dropped_frames", |t| t.dropped_frames = 13),
            ("late_frames", |t| t.late_frames = Some(u32::MAX)),
            ("frame_times_ms", |t| {
                t.frame_times_ms = (0..13).map(f64::from).collect()
            }),
            ("pauses", |t| t.pauses = 1),
            ("refresh_interval_ms", |t| {
                t.refresh_interval_ms = Some(f64::NAN)
            }),
        ];
        for (field, spoil) in cases {
            let mut a = answer();
            spoil(&mut a.timing);
            let m = message(check_answer(&a, 12).unwrap_err());
            assert!(
                m.starts_with("400") && m.contains(&format!("`timing.{field}`")),
                "{field}: {m}"
            );
        }
    }

    #[test]
    fn unknown_fields_of_display_and_answer_are_refused() {
        let mut v = serde_json::to_value(facts()).unwrap();
        v["extra"] = 1.into();
        assert!(serde_json::from_value::<DisplayFacts>(v).is_err());
        let mut v = serde_json::to_value(answer()).unwrap();
        v["extra"] = 1.into();
        assert!(serde_json::from_value::<Answer>(v).is_err());
        let mut v = serde_json::to_value(answer()).unwrap();
        v["timing"]["extra"] = 1.into();
        assert!(serde_json::from_value::<Answer>(v).is_err());
    }
}
