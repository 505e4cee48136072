//! Where the browser goes after the last screen (issue 49): the design's completion URL once
//! done, its screen-out URL once screened out, with the code and the participant's id filled
//! in. Apart from `participant.rs` so that the subject's state can name it without a cycle.

use super::study::Study;
use crate::design::online::Online;
use crate::log::Participant;

/// The participant's id on the platform (for `{id}` in the URLs), else the subject's name.
pub fn platform_id(study: &Study, participant: &Participant, subject: &str) -> String {
    study
        .design
        .file
        .online
        .as_ref()
        .and_then(|o| participant.ids.get(&o.id_param()).cloned())
        .unwrap_or_else(|| subject.to_string())
}

/// The URL for `phase` (`done` or `screened_out`), when the design's `online` names one.
pub fn redirect(
    study: &Study,
    participant: &Participant,
    subject: &str,
    phase: &str,
) -> Option<String> {
    let o = study.design.file.online.as_ref()?;
    let (url, code) = match phase {
        "screened_out" => (o.screen_out_url.as_ref()?, &o.screen_out_code),
        "done" => (o.completion_url.as_ref()?, &o.completion_code),
        _ => return None,
    };
    Some(Online::fill(
        url,
        code.as_deref(),
        &platform_id(study, participant, subject),
    ))
}
