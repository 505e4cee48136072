//! Every number of a scene within what the tracer's 32-bit floats can carry
//! ([`crate::limits::MAX_MAGNITUDE`]): a sphere of radius 1e20 would square to infinity and
//! vanish from the render, an environment intensity of 1e38 would turn samples into infinity.
//! One walk over the scene's JSON model covers every field, present and future, and names it;
//! velocities are also checked multiplied by the animation's largest |time|, since the tracer
//! evaluates positions as location + velocity x time.

use super::file::SceneFile;
use crate::limits::MAX_MAGNITUDE;
use serde_json::Value;

/// The first field out of range, as (field path, what is wrong).
pub(super) fn check(f: &SceneFile) -> Result<(), (String, String)> {
    let s = &f.settings;
    let end = s.start_time as f64 + s.frames as f64 * s.frame_time as f64;
    let time = (s.start_time as f64).abs().max(end.abs());
    // The times first: a `frame_time` of 3e38 would otherwise be blamed on the first velocity.
    if time > MAX_MAGNITUDE {
        // Blame the factor that is out of range alone: `frames: 4294967295` of 0.04 s each is
        // the frame count's fault, a frame_time of 3e38 the frame time's.
        let field = if (s.start_time as f64).abs() > MAX_MAGNITUDE {
            "settings.start_time"
        } else if (s.frame_time as f64).abs() > MAX_MAGNITUDE {
            "settings.frame_time"
        } else {
            "settings.frames"
        };
        return Err((
            field.to_string(),
            format!(
                "makes the animation's times reach |t| = {time:.3e} (start_time {}, {} frames \
                 of frame_time {:e}); expected times of magnitude at most {MAX_MAGNITUDE:e} \
                 (docs/limits.md)",
                s.start_time, s.frames, s.frame_time
            ),
        ));
    }
    let value = serde_json::to_value(f).map_err(|e| (String::new(), e.to_string()))?;
    walk(&value, "", &|x, at| number(x, at, time))
}

/// The first number of a scene's JSON text that 32-bit floats round to 0 (`1e-50`): read as
/// written, since the parsed scene already holds the 0. Larger numbers have their limit above.
pub(super) fn check_tiny(text: &str) -> Result<(), (String, String)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Ok(value) = serde_json::from_str::<Value>(text) else {
        return Ok(()); // the typed parse has named the syntax error
    };
    walk(&value, "", &|v, field| {
        let x = v.as_f64().unwrap_or(0.0);
        if x != 0.0 && x as f32 == 0.0 {
            return Err((
                field.to_string(),
                format!(
                    "holds {x:e}, which 32-bit floats round to 0; expected 0 or a magnitude of \
                     at least {:e} (docs/limits.md)",
                    f32::MIN_POSITIVE
                ),
            ));
        }
        Ok(())
    })
}

type Visit<'a> = &'a dyn Fn(&Value, &str) -> Result<(), (String, String)>;

/// `visit` every number of `v` with its field path; the first error stops the walk.
fn walk(v: &Value, field: &str, visit: Visit) -> Result<(), (String, String)> {
    match v {
        Value::Object(m) => m.iter().try_for_each(|(k, v)| {
            let at = if field.is_empty() {
                k.clone()
            } else {
                format!("{field}.{k}")
            };
            walk(v, &at, visit)
        }),
        Value::Array(a) if a.iter().all(Value::is_number) => {
            a.iter().try_for_each(|x| visit(x, field))
        }
        Value::Array(a) => a
            .iter()
            .enumerate()
            .try_for_each(|(i, v)| walk(v, &format!("{field}[{i}]"), visit)),
        Value::Number(_) => visit(v, field),
        _ => Ok(()),
    }
}

fn number(v: &Value, field: &str, time: f64) -> Result<(), (String, String)> {
    let x = v.as_f64().unwrap_or(f64::INFINITY).abs();
    // The scene's numbers are f32: show them as written, not widened to f64.
    let value = v.as_f64().unwrap_or(f64::INFINITY) as f32;
    if x > MAX_MAGNITUDE {
        return Err((
            field.to_string(),
            format!(
                "holds {value:e}; expected numbers of magnitude at most {MAX_MAGNITUDE:e} \
                 (32-bit floats lose the scene's detail beyond it; docs/limits.md)"
            ),
        ));
    }
    if field.ends_with("velocity") && x * time > MAX_MAGNITUDE {
        return Err((
            field.to_string(),
            format!(
                "holds {value:e}, which over the animation's times (|t| up to {}) moves \
                 {:e} units; expected velocity x time of at most {MAX_MAGNITUDE:e} \
                 (docs/limits.md)",
                time as f32,
                (x * time) as f32
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn walk(v: &Value, field: &str, time: f64) -> Result<(), (String, String)> {
        super::walk(v, field, &|x, at| number(x, at, time))
    }

    #[test]
    fn numbers_that_round_to_zero_are_named_by_field() {
        let tiny = r#"{"objects": [{"radius": 1.0, "location": [0, 1e-50, 0]}]}"#;
        let (field, what) = check_tiny(tiny).unwrap_err();
        assert_eq!(field, "objects[0].location");
        assert!(
            what.contains("1e-50") && what.contains("round to 0"),
            "{what}"
        );
        assert!(check_tiny(r#"{"a": [0, 0.0, 1e-40, -2.5]}"#).is_ok());
    }

    #[test]
    fn out_of_range_numbers_are_named_by_field() {
        let ok = json!({"objects": [{"radius": 1e6, "location": [0, 1, 2]}]});
        assert!(walk(&ok, "", 10.0).is_ok());
        let big = json!({"objects": [{"radius": 1.0}, {"radius": 1e20}]});
        let (field, what) = walk(&big, "", 10.0).unwrap_err();
        assert_eq!(field, "objects[1].radius");
        assert!(
            what.contains("1e20") || what.contains("100000000000000000000"),
            "{what}"
        );
        let env = json!({"settings": {"environment": {"intensity": 1e38}}});
        assert_eq!(
            walk(&env, "", 1.0).unwrap_err().0,
            "settings.environment.intensity"
        );
        let fast = json!({"camera": {"location_velocity": [2e6, 0, 0]}});
        assert!(walk(&fast, "", 1.0).is_ok());
        let (field, what) = walk(&fast, "", 10.0).unwrap_err();
        assert_eq!(field, "camera.location_velocity");
        assert!(what.contains("velocity x time"), "{what}");
    }
}
