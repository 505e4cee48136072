//! A thesis-size study (12 subjects x 2 scenes x 3 point sets x 8 levels x 4 repeats) analyzed
//! end to end in memory: 11 pooled fits with 2000 bootstrap resamples each, 132 per-subject
//! fits, the t-test families. Figures and files are left out (see docs/benchmarks/analysis.md
//! for the timed CLI run that includes them).

use analysis::data::Dataset;
use analysis::psychometric::{FitSettings, fit};
use analysis::report::{Settings, analyze};
use analysis::simulate::StudySpec;
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

fn settings(resamples: usize) -> Settings {
    let mut s = Settings::default();
    s.bootstrap.resamples = resamples;
    s
}

fn bench(c: &mut Criterion) {
    let ds = Dataset::from_observations(&StudySpec::thesis().observations());
    let pooled = ds.groups[0].pooled.clone();
    c.bench_function("fit_pooled_condition", |b| {
        b.iter(|| fit(black_box(&pooled), &FitSettings::default()))
    });
    let mut g = c.benchmark_group("thesis_study");
    g.sample_size(10);
    g.bench_function("analyze_2000_resamples", |b| {
        b.iter(|| analyze(black_box(&ds), &settings(2000)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
