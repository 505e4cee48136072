//! The spatio-temporal contrast sensitivity function: stelaCSF (Mantiuk, Ashraf & Chapiro
//! 2022, "stelaCSF: A unified model of contrast sensitivity as the function of
//! spatio-temporal frequency, eccentricity, luminance and area", ACM Trans. Graph. 41(4) 145).
//!
//! Why this one: the stimuli are videos whose Monte Carlo noise changes every frame, so the
//! model must weigh temporal frequency (up to half the frame rate) as well as spatial
//! frequency; the displays' luminance and the videos' size vary between studies, and stelaCSF
//! models both (the classic spatio-temporal CSFs of Kelly 1979 and Daly 1998 are fixed at one
//! luminance and, for Kelly's, at stabilised viewing). It was fitted jointly to 18 data sets
//! of published detection thresholds, and its authors publish the parameters with their code
//! (castleCSF repository, `matlab/CSF_stelaCSF.m`), which this file's values are.
//!
//! Foveal, achromatic version (eccentricity 0): two mechanisms, sustained and transient, each a
//! spatial CSF times a temporal response, added linearly:
//!
//! ```text
//! S(rho, omega, L, A) = R_S(omega) S_S(rho, L, A) + R_T(omega) S_T(rho, L, A)
//! S_X = S_max,X(L) S_LP,X(rho, L) sqrt(A_c / (1 + A_c / A)) rho
//! S_LP = 10^(-(log10 rho - log10 f_max(L))^2 / 2^b), held at 1 - a below f_max
//! A_c = A_0 / (1 + (rho / f_0)^2)          (Rovamo et al. 1993; A_0 = 270, f_0 = 0.65)
//! R_S = exp(-omega^1.3314 / sigma_S),  R_T = exp(-(omega^0.1898 - 5^0.1898)^2 / sigma_T)
//! ```
//!
//! rho in cycles per degree, omega in Hz, L in cd/m^2, A in deg^2. Sensitivity is the inverse
//! of the Michelson contrast at detection threshold.

/// One mechanism's parameters.
#[derive(Clone, Copy, Debug)]
pub struct Mechanism {
    /// Luminance dependence of the peak sensitivity (stelaCSF's `S_max`).
    pub s_max: &'static [f64],
    /// Luminance dependence of the peak frequency (`f_max`).
    pub f_max: &'static [f64],
    /// Bandwidth of the log-parabola (`bw`).
    pub bw: f64,
    /// Truncation of the log-parabola below the peak (`a`).
    pub a: f64,
}

pub const SUSTAINED: Mechanism = Mechanism {
    s_max: &[44.4763, 0.713964, 0.277857, 7.54866e-07, 8.50217e+09],
    f_max: &[1.55909, 103.604, 0.251815],
    bw: 0.177674,
    a: 1.74265e-102,
};

pub const TRANSIENT: Mechanism = Mechanism {
    s_max: &[0.411266, 211.504],
    f_max: &[0.00115423],
    bw: 2.52628,
    a: 0.000273289,
};

const SIGMA_SUSTAINED: f64 = 15.8409;
const SIGMA_TRANSIENT: f64 = 0.156257;
const BETA_SUSTAINED: f64 = 1.3314;
const BETA_TRANSIENT: f64 = 0.1898;
const OMEGA_TRANSIENT: f64 = 5.0;
const A0: f64 = 270.0;
const F0: f64 = 0.65;

/// The stelaCSF family of luminance dependences, chosen by the parameter count.
fn luminance_dependence(p: &[f64], l: f64) -> f64 {
    match *p {
        [c] => c,
        [e, c] => c * l.powf(e),
        [a, b, c] => a * (1.0 + b / l).powf(-c),
        [a, b, c, d, e] => a * (1.0 + b / l).powf(-c) * (1.0 - (1.0 + d / l).powf(-e)),
        _ => unreachable!("stelaCSF uses 1, 2, 3 or 5 parameters"),
    }
}

/// A mechanism's spatial sensitivity at `rho` cpd, luminance `l`, area `area` deg^2.
pub fn spatial(m: &Mechanism, rho: f64, l: f64, area: f64) -> f64 {
    if rho <= 0.0 {
        return 0.0;
    }
    let s_max = luminance_dependence(m.s_max, l);
    let f_max = luminance_dependence(m.f_max, l);
    let mut s_lp = 10f64.powf(-(rho.log10() - f_max.log10()).powi(2) / 2f64.powf(m.bw));
    if rho < f_max && s_lp < 1.0 - m.a {
        s_lp = 1.0 - m.a;
    }
    let ac = A0 / (1.0 + (rho / F0).powi(2));
    s_max * s_lp * (ac / (1.0 + ac / area)).sqrt() * rho
}

/// The sustained mechanism's temporal response at `omega` Hz.
pub fn sustained_response(omega: f64) -> f64 {
    (-omega.abs().powf(BETA_SUSTAINED) / SIGMA_SUSTAINED).exp()
}

/// The transient mechanism's temporal response at `omega` Hz.
pub fn transient_response(omega: f64) -> f64 {
    let d = omega.abs().powf(BETA_TRANSIENT) - OMEGA_TRANSIENT.powf(BETA_TRANSIENT);
    (-d * d / SIGMA_TRANSIENT).exp()
}

/// Contrast sensitivity of a foveal achromatic grating.
pub fn sensitivity(rho: f64, omega: f64, l: f64, area: f64) -> f64 {
    sustained_response(omega) * spatial(&SUSTAINED, rho, l, area)
        + transient_response(omega) * spatial(&TRANSIENT, rho, l, area)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (rho cpd, omega Hz, L cd/m^2, area deg^2, S) from the authors' code: castleCSF
    /// repository, `matlab/CSF_stelaCSF.m` at commit f4b0b72, run under GNU Octave 7.3
    /// (`CSF_stelaCSF().sensitivity(struct('s_frequency', rho, 't_frequency', omega,
    /// 'luminance', L, 'area', A, 'eccentricity', 0))`).
    pub(crate) const PUBLISHED: [(f64, f64, f64, f64, f64); 12] = [
        (0.5, 0.0, 100.0, 1.0, 22.12943192),
        (1.0, 0.0, 100.0, 1.0, 44.11460745),
        (2.0, 0.0, 100.0, 1.0, 81.18632784),
        (4.0, 0.0, 100.0, 1.0, 102.4435179),
        (8.0, 0.0, 100.0, 1.0, 80.20112855),
        (16.0, 0.0, 100.0, 1.0, 35.24338693),
        (0.5, 8.0, 100.0, 4.0, 93.92544054),
        (2.0, 8.0, 100.0, 4.0, 127.6287481),
        (8.0, 8.0, 100.0, 4.0, 71.55869792),
        (2.0, 2.0, 10.0, 10.0, 183.0912577),
        (2.0, 16.0, 100.0, 1.0, 26.75080668),
        (4.0, 30.0, 100.0, 20.0, 13.05012313),
    ];

    #[test]
    fn matches_the_authors_implementation() {
        for (rho, omega, l, a, s) in PUBLISHED {
            let got = sensitivity(rho, omega, l, a);
            assert!(
                (got / s - 1.0).abs() < 1e-6,
                "{rho} {omega} {l} {a}: {got} vs {s}"
            );
        }
    }

    #[test]
    fn no_sensitivity_to_a_uniform_field() {
        assert_eq!(sensitivity(0.0, 5.0, 100.0, 1.0), 0.0);
    }
}
