//! Property tests of the command line's value parsers (`renderer::limits`, issue 29): every
//! count flag accepts exactly its documented range, negative numbers and junk included (clap
//! hands them over because the flags set `allow_hyphen_values`), every real-range flag accepts
//! exactly its interval, and a refusal says what was expected — never a panic.

use proptest::prelude::*;
use renderer::limits::{
    MAX_IMAGE_SIDE, MAX_REPLICATIONS, MAX_RESAMPLES, MAX_SPP, MAX_SUBJECTS, parse_replications,
    parse_side, parse_spp, parse_subjects, real, resamples,
};

/// Values near every range's ends as well as anywhere in i64.
fn whole_numbers() -> impl Strategy<Value = i64> {
    prop_oneof![any::<i64>(), -3i64..70_000, 99_990i64..100_010]
}

fn inside(v: i64, lo: u64, hi: u64) -> bool {
    v >= lo as i64 && v as u64 <= hi
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn count_flags_accept_exactly_their_range(v in whole_numbers(), pad in any::<bool>()) {
        let s = if pad { format!(" {v} ") } else { v.to_string() };
        prop_assert_eq!(parse_subjects(&s).is_ok(), inside(v, 1, MAX_SUBJECTS as u64));
        prop_assert_eq!(parse_replications(&s).is_ok(), inside(v, 1, MAX_REPLICATIONS));
        prop_assert_eq!(parse_spp(&s).is_ok(), inside(v, 1, MAX_SPP as u64));
        prop_assert_eq!(parse_side(&s).is_ok(), inside(v, 1, MAX_IMAGE_SIDE as u64));
        prop_assert_eq!(resamples(0)(&s).is_ok(), inside(v, 0, MAX_RESAMPLES as u64));
        if let Ok(n) = parse_subjects(&s) {
            prop_assert_eq!(n as i64, v);
        }
    }

    #[test]
    fn real_flags_accept_exactly_their_interval(
        v in prop_oneof![any::<f64>(), -2.0f64..3.0, Just(0.0), Just(1.0)],
    ) {
        let open = real(0.0, 1.0, true, "a probability");
        let closed = real(0.0, 1.0, false, "a proportion");
        let s = v.to_string();
        prop_assert_eq!(open(&s).is_ok(), v > 0.0 && v < 1.0);
        prop_assert_eq!(closed(&s).is_ok(), (0.0..=1.0).contains(&v));
        if let Err(m) = open(&s) {
            prop_assert!(m.contains("expected a probability in (0, 1)"), "{}", m);
        }
    }

    #[test]
    fn flag_parsers_never_panic_and_say_what_they_expected(s in ".{0,40}") {
        let whole: [Result<(), String>; 4] = [
            parse_subjects(&s).map(drop),
            parse_replications(&s).map(drop),
            parse_spp(&s).map(drop),
            parse_side(&s).map(drop),
        ];
        for r in whole {
            if let Err(m) = r {
                prop_assert!(m.contains("expected a whole number of"), "{}", m);
            }
        }
        if let Err(m) = real(1.0, 1e6, true, "a ratio")(&s) {
            prop_assert!(m.contains("expected a ratio in (1, 1000000)"), "{}", m);
        }
    }
}
