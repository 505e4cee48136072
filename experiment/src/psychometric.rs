//! The two-pair task's psychometric function: the probability of a correct answer at a level,
//! for a threshold, a slope and a lapse rate. The simulated observers answer with it
//! (`observer`), QUEST+ places its trials by it (`procedure::quest_plus`), and the analysis's
//! logistic fit is its lapse-0 case.
//!
//! p(spp) = 0.5 + (0.5 - lapse) S(slope (ln T - ln spp) + c),   S(z) = 1 / (1 + e^-z),
//!
//! with c = logit(0.25 / (0.5 - lapse)) so that p(T) = 0.75 exactly: T *is* the JND the
//! analysis should recover (with lapse = 0, c = 0 and this is the plain logistic of the
//! analysis crate).

/// Proportion correct at the threshold.
pub const TARGET: f64 = 0.75;

/// The probability of a correct two-pair answer at `ln_spp` for a threshold `ln_threshold`
/// (where p = [`TARGET`]), a `slope` per ln spp and a `lapse` rate (the formula at the top of
/// this module). With lapse 0 this is the plain logistic 1/2 + 1/2 S(slope (ln T - ln spp)).
pub fn p_correct(slope: f64, lapse: f64, ln_threshold: f64, ln_spp: f64) -> f64 {
    let q = (TARGET - 0.5) / (0.5 - lapse);
    let c = (q / (1.0 - q)).ln();
    let z = slope * (ln_threshold - ln_spp) + c;
    0.5 + (0.5 - lapse) * logistic(z)
}

fn logistic(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}
