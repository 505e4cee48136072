//! The radical inverse φ_b(n) (thesis Chapter II, after Pharr and Humphreys): write n in base b,
//! n = Σ d_i b^(i-1), and mirror the digits about the radix point, φ_b(n) = 0.d_1 d_2 ... d_m.
//! Also its Owen-scrambled form, where each digit is permuted by a permutation chosen by the
//! digits before it (a random nested scramble that keeps the set's stratification).

use crate::hash;

/// φ_b(n) in [0, 1).
pub fn radical_inverse(base: u64, mut n: u64) -> f64 {
    let inv = 1.0 / base as f64;
    let (mut scale, mut value) = (inv, 0.0);
    while n > 0 {
        value += (n % base) as f64 * scale;
        n /= base;
        scale *= inv;
    }
    value
}

/// Digits kept by the scrambled inverse: b^-digits < 2^-32, finer than the f32 samples use.
fn scrambled_digits(base: u64) -> u32 {
    let mut digits = 0;
    let mut left = 1.0f64;
    while left >= 1.0 / 4_294_967_296.0 {
        left /= base as f64;
        digits += 1;
    }
    digits
}

/// Owen-scrambled φ_b(n) keyed by `seed`: digit k is sent through a random permutation of
/// 0..b chosen by hashing (seed, k, digits 1..k-1), so points sharing their leading digits
/// (one stratum) keep sharing them after scrambling. Trailing zero digits are scrambled too,
/// which is what moves the first point away from 0.
pub fn owen_scrambled_radical_inverse(base: u64, mut n: u64, seed: u64) -> f64 {
    let inv = 1.0 / base as f64;
    let (mut scale, mut value) = (inv, 0.0);
    let mut prefix = hash::hash(seed, &[base]);
    for k in 0..scrambled_digits(base) {
        let digit = n % base;
        n /= base;
        let key = hash::hash(prefix, &[k as u64]);
        value += permute(digit, base, key) as f64 * scale;
        scale *= inv;
        prefix = hash::hash(prefix, &[k as u64, digit]);
    }
    value.min(1.0 - f64::EPSILON / 2.0)
}

/// Image of `digit` under the permutation of 0..base drawn by Fisher-Yates from `key`.
pub(crate) fn permute(digit: u64, base: u64, mut key: u64) -> u64 {
    debug_assert!(base <= 16, "permutations of small bases only");
    let mut perm: [u64; 16] = std::array::from_fn(|i| i as u64);
    for j in (1..base as usize).rev() {
        let r = (key % (j as u64 + 1)) as usize;
        key /= j as u64 + 1;
        perm.swap(j, r);
    }
    perm[digit as usize]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digits_are_mirrored_about_the_radix_point() {
        assert_eq!(radical_inverse(2, 0), 0.0);
        assert_eq!(radical_inverse(2, 1), 0.5);
        assert_eq!(radical_inverse(2, 6), 0.375); // 110b -> 0.011b
        assert!((radical_inverse(3, 5) - 7.0 / 9.0).abs() < 1e-15); // 12_3 -> 0.21_3
        assert!((radical_inverse(5, 7) - (2.0 / 5.0 + 1.0 / 25.0)).abs() < 1e-15); // 12_5
    }

    #[test]
    fn permutations_are_bijections() {
        for base in [2, 3, 5, 7] {
            for key in [0, 1, 12345, u64::MAX] {
                let mut img: Vec<u64> = (0..base).map(|d| permute(d, base, key)).collect();
                img.sort();
                assert_eq!(img, (0..base).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn scrambling_keeps_every_elementary_interval_filled() {
        // The first b^m points of φ_b fall one in each interval [j/b^m, (j+1)/b^m); a nested
        // (Owen) scramble permutes these intervals, so that must still hold.
        for (base, m) in [(2u64, 6u32), (3, 4), (5, 3)] {
            let n = base.pow(m);
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let x = owen_scrambled_radical_inverse(base, i, 77);
                let j = (x * n as f64) as usize;
                assert!(!seen[j], "base {base}: interval {j} twice");
                seen[j] = true;
            }
        }
    }
}
