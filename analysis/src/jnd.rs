//! The just-noticeable difference: the spp where proportion correct falls to the target
//! (0.75 by default, the thesis's choice: halfway between certain and chance).
//!
//! A threshold is never extrapolated: beyond the tested levels it is "below range" or "above
//! range" with the bound; for a step fit it is the interval between two tested levels.

use crate::psychometric::{Fit, Shape};
pub use crate::threshold::{Threshold, crossing, empirical_threshold};

/// The fitted function's threshold.
pub fn model_threshold(fit: &Fit, target: f64) -> Threshold {
    let pts = &fit.curve.points;
    let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
        return Threshold::Undefined {
            reason: "no trials".into(),
        };
    };
    match &fit.shape {
        Shape::Finite(m) => match m.x_at(target) {
            Some(x) if x < first.x() => Threshold::BelowRange { bound: first.level },
            Some(x) if x > last.x() => Threshold::AboveRange { bound: last.level },
            Some(x) => Threshold::Value { spp: x.exp() },
            // Unreachable for a validated target (guess < target <= 0.9, lapse <= 0.06), kept so
            // that no number is ever invented.
            None => Threshold::Undefined {
                reason: format!("the fitted function never reaches p = {target}"),
            },
        },
        Shape::Step(step) => {
            step_threshold(fit, step.lapse, target).unwrap_or_else(|| sides(fit, target))
        }
        // A single level: which side of the target it lies on.
        Shape::Unidentified { .. } => sides(fit, target),
    }
}

/// A step through a tested level (its fitted value strictly between the guess rate and
/// 1 - lapse) crosses every target in between exactly there: steep functions through the level
/// cross the target just below it (when the level's value is under the target) or just above
/// it, and in the limit at it. At an end of the tested range, a crossing approached from
/// outside stays out of range (never extrapolated): `None`, and the sides decide.
fn step_threshold(fit: &Fit, lapse: f64, target: f64) -> Option<Threshold> {
    let (g, top) = (fit.settings.guess, 1.0 - lapse);
    let pts = &fit.curve.points;
    let k = fit.fitted.iter().position(|&p| p > g && p < top)?;
    let p = fit.fitted[k];
    if (k == 0 && p < target) || (k + 1 == pts.len() && p > target) {
        return None;
    }
    Some(Threshold::AtLevel {
        level: pts[k].level,
        lower: pts[k.saturating_sub(1)].level,
        upper: pts[(k + 1).min(pts.len() - 1)].level,
    })
}

/// The threshold read from the fitted values at the tested levels: the interval between the
/// last level at or above the target and the next one, or out of range.
fn sides(fit: &Fit, target: f64) -> Threshold {
    let pts = &fit.curve.points;
    let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
        return Threshold::Undefined {
            reason: "no trials".into(),
        };
    };
    let n_above = fit.fitted.iter().take_while(|&&p| p >= target).count();
    if n_above == 0 {
        Threshold::BelowRange { bound: first.level }
    } else if n_above == pts.len() {
        Threshold::AboveRange { bound: last.level }
    } else {
        Threshold::Between {
            lower: pts[n_above - 1].level,
            upper: pts[n_above].level,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Curve;
    use crate::psychometric::{FitSettings, LapseMode, Model, fit};
    use crate::sigmoid::Sigmoid;

    #[test]
    fn empirical_crossing_interpolates_in_log_spp() {
        // 0.875 at 27 and 0.625 at 64: the target 0.75 is halfway, at sqrt(27 * 64) spp.
        let c = Curve::from_counts([(8, 8, 8), (27, 7, 8), (64, 5, 8), (125, 6, 8)]);
        match empirical_threshold(&c, 0.75) {
            Threshold::Value { spp } => assert!((spp - (27.0f64 * 64.0).sqrt()).abs() < 1e-9),
            t => panic!("{t:?}"),
        }
        // First crossing counts, even if the curve comes back up.
        let c = Curve::from_counts([(8, 4, 4), (27, 2, 4), (64, 4, 4)]);
        assert!(matches!(
            empirical_threshold(&c, 0.75),
            Threshold::Value { spp } if (spp - 8f64.powf(0.5) * 27f64.powf(0.5)).abs() < 1e-9
        ));
    }

    #[test]
    fn empirical_out_of_range_is_reported_with_bound() {
        let all = Curve::from_counts([(8, 4, 4), (27, 4, 4)]);
        assert_eq!(
            empirical_threshold(&all, 0.75),
            Threshold::AboveRange { bound: 27 }
        );
        let none = Curve::from_counts([(8, 2, 4), (27, 1, 4)]);
        assert_eq!(
            empirical_threshold(&none, 0.75),
            Threshold::BelowRange { bound: 8 }
        );
        assert_eq!(
            empirical_threshold(&Curve::default(), 0.75).kind(),
            "undefined"
        );
    }

    #[test]
    fn finite_threshold_is_alpha_for_logistic_at_075_and_never_extrapolated() {
        let m = Model {
            sigmoid: Sigmoid::Logistic,
            alpha: 40f64.ln(),
            beta: 2.0,
            lapse: 0.0,
            guess: 0.5,
        };
        assert!((m.x_at(0.75).unwrap() - 40f64.ln()).abs() < 1e-12);
        // Weibull (Gumbel form): S(z) = 1/2 at z = ln ln 2, so x = alpha - ln(ln 2)/beta.
        let w = Model {
            sigmoid: Sigmoid::Weibull,
            ..m
        };
        assert!((w.x_at(0.75).unwrap() - (40f64.ln() - 2f64.ln().ln() / 2.0)).abs() < 1e-12);
        // A fit whose threshold would be at 2000 spp with levels up to 512 is "above range".
        let n = 1_000_000;
        let far = Model {
            alpha: 2000f64.ln(),
            beta: 0.8,
            ..m
        };
        let c = Curve::from_counts(
            [1u32, 8, 27, 64, 125, 216, 343, 512]
                .iter()
                .map(|&l| (l, (far.p((l as f64).ln()) * n as f64).round() as u32, n)),
        );
        let f = fit(&c, &FitSettings::default());
        assert_eq!(
            model_threshold(&f, 0.75),
            Threshold::AboveRange { bound: 512 }
        );
    }

    #[test]
    fn step_fits_give_intervals_and_single_levels_give_sides() {
        let c = Curve::from_counts([(1, 4, 4), (8, 4, 4), (27, 4, 4), (64, 2, 4), (125, 2, 4)]);
        let f = fit(&c, &FitSettings::default());
        assert_eq!(f.kind(), "step");
        assert_eq!(
            model_threshold(&f, 0.75),
            Threshold::Between {
                lower: 27,
                upper: 64
            }
        );
        let one = fit(&Curve::from_counts([(64, 4, 4)]), &FitSettings::default());
        assert_eq!(
            model_threshold(&one, 0.75),
            Threshold::AboveRange { bound: 64 }
        );
        let one = fit(&Curve::from_counts([(64, 2, 4)]), &FitSettings::default());
        assert_eq!(
            model_threshold(&one, 0.75),
            Threshold::BelowRange { bound: 64 }
        );
    }

    #[test]
    fn a_step_through_one_level_is_that_level_with_its_bracket() {
        // Plateau at 1 and 8 spp, 3 of 4 at 27, chance above: the likelihood is maximised by a
        // step through 27 spp at 0.75, which crosses every target between 0.5 and 1 there.
        let c = Curve::from_counts([(1, 4, 4), (8, 4, 4), (27, 3, 4), (64, 2, 4), (125, 2, 4)]);
        for lapse in [LapseMode::Fixed, LapseMode::Free] {
            let f = fit(
                &c,
                &FitSettings {
                    lapse,
                    ..FitSettings::default()
                },
            );
            assert_eq!(f.kind(), "step", "{lapse:?}");
            let at_27 = Threshold::AtLevel {
                level: 27,
                lower: 8,
                upper: 64,
            };
            for target in [0.6, 0.75, 0.9] {
                assert_eq!(model_threshold(&f, target), at_27, "{lapse:?} {target}");
            }
            assert_eq!(at_27.display(), "27 [8-64]");
            assert_eq!(at_27.ln_bounds(), Some((27f64.ln(), 27f64.ln())));
        }
        // The same counts with 2 of 4 at 27 spp: at chance for two alternatives (the level is
        // on the lower plateau, the step lies between 8 and 27), but above the guess rate 1/4
        // of four alternatives (a step through 27).
        let c = Curve::from_counts([(1, 4, 4), (8, 4, 4), (27, 2, 4), (64, 1, 4), (125, 1, 4)]);
        let two = fit(&c, &FitSettings::default());
        assert_eq!(
            model_threshold(&two, 0.75),
            Threshold::Between {
                lower: 8,
                upper: 27
            }
        );
        let four = fit(
            &c,
            &FitSettings {
                guess: 0.25,
                ..FitSettings::default()
            },
        );
        assert_eq!(four.kind(), "step");
        assert_eq!(
            model_threshold(&four, 0.625),
            Threshold::AtLevel {
                level: 27,
                lower: 8,
                upper: 64
            }
        );
        // A step through the lowest level: its bracket starts at the level itself. Steep
        // functions through 3/4 at 8 spp cross 0.75 at 8 spp and 0.7 just above it (inside
        // the range), but 0.8 just below it: below the range, never extrapolated.
        let c = Curve::from_counts([(8, 3, 4), (27, 2, 4), (64, 2, 4)]);
        let f = fit(&c, &FitSettings::default());
        let at_8 = Threshold::AtLevel {
            level: 8,
            lower: 8,
            upper: 27,
        };
        assert_eq!(model_threshold(&f, 0.75), at_8);
        assert_eq!(model_threshold(&f, 0.7), at_8);
        assert_eq!(model_threshold(&f, 0.8), Threshold::BelowRange { bound: 8 });
        // Through the highest level, the mirror image.
        let c = Curve::from_counts([(8, 4, 4), (27, 4, 4), (64, 3, 4)]);
        let f = fit(&c, &FitSettings::default());
        let at_64 = Threshold::AtLevel {
            level: 64,
            lower: 27,
            upper: 64,
        };
        assert_eq!(model_threshold(&f, 0.75), at_64);
        assert_eq!(model_threshold(&f, 0.8), at_64);
        assert_eq!(
            model_threshold(&f, 0.7),
            Threshold::AboveRange { bound: 64 }
        );
    }
}
