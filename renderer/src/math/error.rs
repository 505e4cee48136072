//! Error of an f32 result against an f64 reference, for the tests of [`super`].

/// |got - want| in units in the last place of `want` rounded to f32 (the spacing of the f32
/// around it; subnormal spacing below the normal range). A NaN where the reference is not (or
/// the reverse) counts as infinitely wrong.
pub fn ulps(got: f32, want: f64) -> f64 {
    if got.is_nan() || want.is_nan() {
        return if got.is_nan() && want.is_nan() {
            0.0
        } else {
            f64::INFINITY
        };
    }
    (got as f64 - want).abs() / ulp(want)
}

/// The spacing of the f32 values around |x|.
pub fn ulp(x: f64) -> f64 {
    let x = x.abs().max(f32::MIN_POSITIVE as f64);
    2f64.powi(x.log2().floor() as i32 - 23)
}

/// The largest error seen, with its input.
#[derive(Default)]
pub struct Worst {
    pub ulps: f64,
    pub at: f32,
    pub count: usize,
}

impl Worst {
    pub fn add(&mut self, at: f32, ulps: f64) {
        self.count += 1;
        if ulps > self.ulps || ulps.is_nan() {
            (self.ulps, self.at) = (ulps, at);
        }
    }
}

impl std::fmt::Display for Worst {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:.3} ulp at {:e} ({} values)",
            self.ulps, self.at, self.count
        )
    }
}
