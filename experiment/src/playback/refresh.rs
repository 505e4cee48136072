//! The display's refresh interval as the app sees it: the median interval between consecutive
//! repaints while repainting continuously (with vsync on, one refresh; without, the repaint
//! loop's own pace). The median ignores the odd late repaint (window mapping, first upload).

/// Collects repaint times and reports the median interval.
#[derive(Clone, Debug, Default)]
pub struct RefreshMeter {
    last: Option<f64>,
    intervals: Vec<f64>,
}

/// Intervals needed before the median is trusted (about a second at 60 Hz).
pub const SAMPLES: usize = 60;

impl RefreshMeter {
    /// Record a repaint at `t` seconds.
    pub fn repaint(&mut self, t: f64) {
        if let Some(last) = self.last
            && t > last
            && self.intervals.len() < SAMPLES
        {
            self.intervals.push(t - last);
        }
        self.last = Some(t);
    }

    pub fn done(&self) -> bool {
        self.intervals.len() >= SAMPLES
    }

    /// Median interval in milliseconds, once enough repaints were seen.
    pub fn median_ms(&self) -> Option<f64> {
        if !self.done() {
            return None;
        }
        let mut v = self.intervals.clone();
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let m = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Some(m * 1000.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_ignores_outliers_and_waits_for_enough_samples() {
        let mut m = RefreshMeter::default();
        let mut t = 0.0;
        m.repaint(t);
        for i in 0..SAMPLES {
            // Every tenth repaint is 50 ms late; the rest 1/64 s apart.
            t += if i % 10 == 0 { 0.05 } else { 1.0 / 64.0 };
            assert!(m.median_ms().is_none());
            m.repaint(t);
        }
        assert_eq!(m.median_ms(), Some(1000.0 / 64.0));
        // A repeated time stamp adds no zero interval.
        let mut z = RefreshMeter::default();
        z.repaint(1.0);
        z.repaint(1.0);
        assert!(z.intervals.is_empty());
    }
}
