//! Speed against error: `render report stimuli/<job>` tabulates every stimulus's error against
//! its reference next to its sampling density and render time (`convergence.csv`), fits the
//! convergence slope of each scene x point set x time filter by least squares in log-log
//! (`convergence_slopes.csv`), and draws log-log plots of RMSE against spp and against seconds,
//! one per scene, as SVG and PNG.
//!
//! A stimulus that is its own reference (the highest level when the job's reference is
//! `highest_level`) has zero error by construction: `convergence.csv` lists it with
//! `own_reference = true`, zero errors and the capped PSNR, and neither the slopes nor the plots
//! use it (a log-log fit through a zero would be meaningless).

mod plot;

use crate::condition::{PointSetKind, TimeFilter};
use crate::manifest::{Manifest, Stimulus};
use anyhow::{Context, Result, anyhow};
use plot::{Axis, plot};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Font family name registered for plot text.
pub(crate) const FONT: &str = "blurlab-sans";

/// One stimulus with an error.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Row {
    pub scene: String,
    pub point_set: PointSetKind,
    pub time_filter: TimeFilter,
    pub spp: u32,
    pub id: String,
    pub render_seconds: f64,
    pub rmse: f64,
    pub rel_mse: f64,
    pub psnr: f64,
    pub flip: f64,
    /// The stimulus the error is measured against.
    pub reference_id: String,
    /// The stimulus is its own reference: zero error by construction, not measured.
    pub own_reference: bool,
}

/// The fitted convergence of one group.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Slope {
    pub scene: String,
    pub point_set: PointSetKind,
    pub time_filter: TimeFilter,
    /// Number of levels in the fit.
    pub levels: usize,
    /// d log(RMSE) / d log(spp); -0.5 is plain Monte Carlo.
    pub rmse_vs_spp: f64,
    /// d log(RMSE) / d log(render seconds).
    pub rmse_vs_seconds: f64,
    /// d log(relMSE) / d log(spp); -1 is plain Monte Carlo.
    pub rel_mse_vs_spp: f64,
    pub flip_vs_spp: f64,
}

/// Files a report wrote.
#[derive(Clone, Debug, Default)]
pub struct ReportFiles {
    pub csv: PathBuf,
    pub slopes_csv: PathBuf,
    /// SVG and PNG plots.
    pub figures: Vec<PathBuf>,
}

/// Least-squares slope of `ln y` against `ln x` over points with positive, finite x and y.
/// `None` with fewer than two usable points or no spread in x.
pub fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 1e-12 * n).then(|| sxy / sxx)
}

/// The rows of a manifest: every non-reference stimulus with a measured error, sorted by group
/// and spp.
pub fn rows(m: &Manifest) -> Vec<Row> {
    sorted(
        m.stimuli
            .iter()
            .filter(|s| !s.reference)
            .filter_map(|s: &Stimulus| {
                let e = s.error.as_ref()?;
                Some(row(m, s, e.rmse, e.rel_mse, e.psnr, e.flip))
            })
            .collect(),
    )
}

/// The stimuli that are their own reference, as rows of zero error (PSNR at its cap).
pub fn own_reference_rows(m: &Manifest) -> Vec<Row> {
    sorted(
        m.stimuli
            .iter()
            .filter(|s| s.own_reference())
            .map(|s| row(m, s, 0.0, 0.0, crate::metrics::PSNR_CAP_DB, 0.0))
            .collect(),
    )
}

fn row(m: &Manifest, s: &Stimulus, rmse: f64, rel_mse: f64, psnr: f64, flip: f64) -> Row {
    Row {
        scene: s.scene.clone(),
        point_set: s.point_set,
        time_filter: s.time_filter,
        spp: s.spp,
        id: s.id.clone(),
        render_seconds: s.render_seconds,
        rmse,
        rel_mse,
        psnr,
        flip,
        reference_id: m.reference_of(s).map(|r| r.id.clone()).unwrap_or_default(),
        own_reference: s.own_reference(),
    }
}

fn sorted(mut rows: Vec<Row>) -> Vec<Row> {
    rows.sort_by(|a, b| {
        (&a.scene, &a.point_set, &a.time_filter, a.spp).cmp(&(
            &b.scene,
            &b.point_set,
            &b.time_filter,
            b.spp,
        ))
    });
    rows
}

type GroupKey = (String, PointSetKind, TimeFilter);

fn groups(rows: &[Row]) -> BTreeMap<GroupKey, Vec<&Row>> {
    let mut g: BTreeMap<GroupKey, Vec<&Row>> = BTreeMap::new();
    for r in rows {
        g.entry((r.scene.clone(), r.point_set, r.time_filter))
            .or_default()
            .push(r);
    }
    g
}

/// Fitted slopes per scene x point set x time filter; a slope that cannot be fitted is NaN
/// here and written as an empty CSV cell.
pub fn slopes(rows: &[Row]) -> Vec<Slope> {
    groups(rows)
        .into_iter()
        .map(|((scene, point_set, time_filter), rs)| {
            let fit = |f: &dyn Fn(&Row) -> (f64, f64)| {
                log_log_slope(&rs.iter().map(|r| f(r)).collect::<Vec<_>>()).unwrap_or(f64::NAN)
            };
            Slope {
                scene,
                point_set,
                time_filter,
                levels: rs.len(),
                rmse_vs_spp: fit(&|r| (r.spp as f64, r.rmse)),
                rmse_vs_seconds: fit(&|r| (r.render_seconds, r.rmse)),
                rel_mse_vs_spp: fit(&|r| (r.spp as f64, r.rel_mse)),
                flip_vs_spp: fit(&|r| (r.spp as f64, r.flip)),
            }
        })
        .collect()
}

/// Write the report of the stimulus set in `stimuli_dir` into `out_dir`.
pub fn write_report(stimuli_dir: &Path, out_dir: &Path) -> Result<ReportFiles> {
    let m = Manifest::load(stimuli_dir)?;
    let rows = rows(&m);
    if rows.is_empty() {
        return Err(anyhow!(
            "{}: no stimulus has an error against a reference; is the job finished \
             (`blurlab render job ... --finalize`)?",
            crate::manifest::manifest_file(stimuli_dir).display()
        ));
    }
    let slopes = slopes(&rows);
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create folder {}", out_dir.display()))?;
    let mut files = ReportFiles {
        csv: out_dir.join("convergence.csv"),
        slopes_csv: out_dir.join("convergence_slopes.csv"),
        figures: Vec::new(),
    };
    let mut listed = rows.clone();
    listed.extend(own_reference_rows(&m));
    write_csv(&files.csv, &sorted(listed))?;
    write_slopes_csv(&files.slopes_csv, &slopes)?;
    register_font()?;
    let scenes: Vec<String> = {
        let mut s: Vec<String> = rows.iter().map(|r| r.scene.clone()).collect();
        s.dedup();
        s
    };
    for scene in &scenes {
        for axis in [Axis::Spp, Axis::Seconds] {
            let name = format!("rmse_vs_{}_{scene}", axis.slug());
            let svg = out_dir.join(format!("{name}.svg"));
            let png = out_dir.join(format!("{name}.png"));
            plot(&rows, &slopes, scene, axis, &svg, (720, 520))?;
            plot(&rows, &slopes, scene, axis, &png, (720, 520))?;
            files.figures.extend([svg, png]);
        }
    }
    Ok(files)
}

fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    crate::atomic::write_atomic_with(path, |w| {
        let mut c = csv::Writer::from_writer(w);
        for r in rows {
            c.serialize(r)?;
        }
        c.flush()?;
        Ok(())
    })
}

fn write_slopes_csv(path: &Path, slopes: &[Slope]) -> Result<()> {
    crate::atomic::write_atomic_with(path, |w| {
        let mut c = csv::Writer::from_writer(w);
        c.write_record([
            "scene",
            "point_set",
            "time_filter",
            "levels",
            "rmse_vs_spp",
            "rmse_vs_seconds",
            "rel_mse_vs_spp",
            "flip_vs_spp",
        ])?;
        let cell = |v: f64| {
            if v.is_finite() {
                format!("{v:.4}")
            } else {
                String::new()
            }
        };
        for s in slopes {
            c.write_record([
                s.scene.clone(),
                s.point_set.to_string(),
                s.time_filter.to_string(),
                s.levels.to_string(),
                cell(s.rmse_vs_spp),
                cell(s.rmse_vs_seconds),
                cell(s.rel_mse_vs_spp),
                cell(s.flip_vs_spp),
            ])?;
        }
        c.flush()?;
        Ok(())
    })
}

pub(crate) fn register_font() -> Result<()> {
    crate::plot_font::register(FONT)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::ErrorMetrics;

    #[test]
    fn slope_of_a_power_law_is_its_exponent() {
        let pts: Vec<(f64, f64)> = [1.0, 8.0, 27.0, 64.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(-0.5)))
            .collect();
        assert!((log_log_slope(&pts).unwrap() + 0.5).abs() < 1e-12);
        assert!(log_log_slope(&pts[..1]).is_none());
        assert!(log_log_slope(&[(2.0, 1.0), (2.0, 3.0)]).is_none());
        assert!(log_log_slope(&[(0.0, 1.0), (1.0, f64::NAN)]).is_none());
    }

    fn manifest() -> Manifest {
        let mut m = Manifest::new("t");
        for (ps, k) in [("hammersley", -0.75), ("random", -0.5)] {
            for spp in [1u32, 8, 27, 64] {
                let rmse = 0.4 * (spp as f64).powf(k);
                m.stimuli.push(Stimulus {
                    id: format!("plane-{ps}-box-{spp:04}"),
                    scene: "plane".into(),
                    point_set: ps.parse().unwrap(),
                    time_filter: TimeFilter::Box,
                    spp,
                    reference: false,
                    reference_id: Some(format!("plane-{ps}-box-0125")),
                    seed: 1,
                    width: 8,
                    height: 8,
                    frames: 2,
                    fps: 30.0,
                    frame_paths: vec![],
                    exr_paths: vec![],
                    content_hash: String::new(),
                    render_seconds: 0.01 * spp as f64,
                    error: Some(ErrorMetrics {
                        rmse,
                        rel_mse: rmse * rmse,
                        psnr: 30.0,
                        flip: rmse / 2.0,
                    }),
                });
            }
            // The highest level as the condition's own reference: listed, not fitted.
            {
                let mut top = m.stimuli.last().unwrap().clone();
                top.id = format!("plane-{ps}-box-0125");
                top.spp = 125;
                top.reference_id = Some(top.id.clone());
                top.error = None;
                m.stimuli.push(top);
            }
        }
        m
    }

    #[test]
    fn report_writes_csvs_and_figures_with_the_fitted_slopes() {
        let dir = tempfile::tempdir().unwrap();
        manifest().save(dir.path()).unwrap();
        let out = dir.path().join("report");
        let files = write_report(dir.path(), &out).unwrap();
        let csv = std::fs::read_to_string(&files.csv).unwrap();
        assert_eq!(csv.lines().count(), 1 + 10);
        assert!(csv.starts_with("scene,point_set,time_filter,spp,id,render_seconds,rmse"));
        assert!(
            csv.lines()
                .next()
                .unwrap()
                .ends_with(",reference_id,own_reference")
        );
        let own: Vec<&str> = csv.lines().filter(|l| l.ends_with(",true")).collect();
        assert_eq!(own.len(), 2, "{csv}");
        assert!(own[0].starts_with("plane,hammersley,box,125,plane-hammersley-box-0125,"));
        assert!(
            own[0].contains(",0.0,0.0,100.0,0.0,plane-hammersley-box-0125,true"),
            "{}",
            own[0]
        );
        let slopes = std::fs::read_to_string(&files.slopes_csv).unwrap();
        assert!(slopes.contains("plane,hammersley,box,4,-0.7500,-0.7500,-1.5000,-0.7500"));
        assert!(slopes.contains("plane,random,box,4,-0.5000,-0.5000,-1.0000,-0.5000"));
        assert_eq!(files.figures.len(), 4);
        for f in &files.figures {
            assert!(
                std::fs::metadata(f).unwrap().len() > 1000,
                "{}",
                f.display()
            );
        }
        let svg = std::fs::read_to_string(out.join("rmse_vs_spp_plane.svg")).unwrap();
        assert!(svg.contains("slope -0.75"), "legend shows the slope");
    }

    #[test]
    fn a_manifest_without_errors_is_refused_with_a_hint() {
        let dir = tempfile::tempdir().unwrap();
        Manifest::new("t").save(dir.path()).unwrap();
        let e = write_report(dir.path(), &dir.path().join("r")).unwrap_err();
        assert!(format!("{e:#}").contains("--finalize"));
    }
}
