//! `blurlab serve`: subjects' sessions in their browsers (`experiment::web`; docs/web.md).

use clap::Args;
use experiment::web::budget::{Budget, Limits, gb};
use experiment::web::wire::ClientSettings;
use std::net::SocketAddr;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ServeArgs {
    /// The design file (`blurlab-design/1`).
    #[arg(long)]
    pub design: PathBuf,
    /// The study's folder: session logs in `OUT/sessions/`, links in `OUT/links.csv`, tokens in
    /// `OUT/web/tokens.json` (a restarted server reads them and continues every session).
    #[arg(long)]
    pub out: PathBuf,
    /// Address to listen on. Keep it on 127.0.0.1 behind a TLS reverse proxy to go online.
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub addr: SocketAddr,
    /// Make sure N subject links exist (w001...) and write them to OUT/links.csv.
    #[arg(long, value_name = "N", conflicts_with = "open_enrolment",
          allow_hyphen_values = true, value_parser = parse_subject_count)]
    pub enrol: Option<u32>,
    /// Open enrolment: print a /join link that creates a subject per visit, up to CAP.
    #[arg(long, value_name = "CAP", allow_hyphen_values = true,
          value_parser = parse_subject_count)]
    pub open_enrolment: Option<u32>,
    /// The URL subjects reach the server at, for the links (behind a proxy: its https URL):
    /// absolute http(s), without query or fragment.
    #[arg(long, value_parser = parse_base_url)]
    pub base_url: Option<String>,
    /// Seconds a connection may take to send a request's head, and may stay idle between
    /// requests, before it is closed.
    #[arg(long, value_name = "SECONDS", default_value_t = 30.0,
          value_parser = renderer::limits::real(0.1, 3600.0, false, "seconds"))]
    pub header_timeout: f64,
    /// Do not read every frame at start to compare the manifest's content hash (the other
    /// checks stay: every stimulus there, with its size and frame count).
    #[arg(long)]
    pub skip_hash_check: bool,
    /// Most connections open at once; more are closed as they arrive.
    #[arg(long, value_name = "N", default_value_t = 1024,
          value_parser = clap::value_parser!(u32).range(8..=65_536))]
    pub max_connections: u32,
    /// Encode the videos (if not yet), print what a session costs a browser, and stop; exits
    /// with an error for a design no browser can hold.
    #[arg(long)]
    pub check: bool,
    /// Copy the encoded videos under opaque names into DIR for a static server, and stop.
    #[arg(long, value_name = "DIR", conflicts_with = "check")]
    pub export_videos: Option<PathBuf>,
    /// Browsers fetch videos from this URL (a static server holding an --export-videos folder)
    /// instead of from this server; answers still come here.
    #[arg(long, value_name = "URL", value_parser = parse_base_url)]
    pub video_base_url: Option<String>,
    /// Frames decoded ahead of the one shown, per video playing.
    #[arg(long, default_value_t = ClientSettings::default().lookahead_frames)]
    pub lookahead_frames: u32,
    /// Most encoded video the browser keeps, in MB (Cache Storage; in memory where it is
    /// unavailable, at most 768 MB).
    #[arg(long, default_value_t = ClientSettings::default().cache_bytes / 1_000_000)]
    pub cache_mb: u64,
    /// Trials ahead whose videos the browser fetches while the current one plays.
    #[arg(long, default_value_t = ClientSettings::default().fetch_ahead_trials)]
    pub fetch_ahead_trials: u32,
    /// Warn when a session moves more than this many GB.
    #[arg(long, default_value_t = 3.0)]
    pub budget_gb: f64,
    /// Warn when a trial takes more browser memory than this many GB.
    #[arg(long, default_value_t = 1.2)]
    pub memory_budget_gb: f64,
}

pub fn run(args: &ServeArgs) -> anyhow::Result<()> {
    let config = config(args)?;
    let mut progress = |k: usize, n: usize, id: &str| {
        eprintln!("encoding video {} of {n} as lossless WebP: {id}", k + 1);
    };
    if args.check {
        let (_, budget) = experiment::web::measure_study(&config, &mut progress)?;
        print_budget(&budget);
        if let Some(why) = budget.refusal() {
            anyhow::bail!("{}: {why}", args.design.display());
        }
        println!("no browser limit is passed");
        return Ok(());
    }
    if let Some(dir) = &args.export_videos {
        let e = experiment::web::export::export(&config, dir, &mut progress)?;
        println!(
            "exported {} videos ({}; {} already there) to {}",
            e.videos,
            gb(e.bytes),
            e.kept,
            dir.display()
        );
        println!(
            "serve that folder with CORS and cache headers (docs/web.md), then start with \
             --video-base-url URL and the same --out"
        );
        return Ok(());
    }
    experiment::web::serve_until_interrupted(&config, &mut progress, |s| {
        print_budget(&s.budget);
        println!(
            "serving on http://{} ({} subjects enrolled)",
            s.addr, s.subjects
        );
        if let Some(links) = &s.links_csv {
            println!("subject links: {}", links.display());
        }
        if let Some(join) = &s.join_url {
            println!("open enrolment: {join}");
        }
        if let Some(study) = &s.study_url {
            println!("study URL for the recruitment platform: {study}");
        }
        println!("sessions:      {}", s.sessions_dir.display());
        println!("admin:         {}", s.admin_url);
        println!("stop with Ctrl-C; a restart continues every session");
    })
}

fn config(args: &ServeArgs) -> anyhow::Result<experiment::web::Config> {
    for (name, x) in [
        ("--budget-gb", args.budget_gb),
        ("--memory-budget-gb", args.memory_budget_gb),
    ] {
        anyhow::ensure!(
            x.is_finite() && x > 0.0,
            "{name} is {x}; expected a number of GB above 0"
        );
    }
    Ok(experiment::web::Config {
        design: args.design.clone(),
        out: args.out.clone(),
        addr: args.addr,
        enrol: args.enrol,
        open_enrolment: args.open_enrolment,
        base_url: args.base_url.clone(),
        client: ClientSettings {
            lookahead_frames: args.lookahead_frames,
            cache_bytes: args.cache_mb.saturating_mul(1_000_000),
            fetch_ahead_trials: args.fetch_ahead_trials,
            video_base: args
                .video_base_url
                .as_ref()
                .map(|u| u.trim_end_matches('/').to_string()),
        },
        limits: Limits {
            session_bytes: (args.budget_gb * 1e9) as u64,
            memory_bytes: (args.memory_budget_gb * 1e9) as u64,
        },
        check_hashes: !args.skip_hash_check,
        connections: experiment::web::connections::Limits {
            header_read_timeout: std::time::Duration::from_secs_f64(args.header_timeout),
            max_connections: args.max_connections as usize,
        },
    })
}

/// `--enrol` and `--open-enrolment`: 1 to `renderer::limits::MAX_SUBJECTS` subjects (a
/// negative or zero count gets this range, not clap's "unexpected argument").
fn parse_subject_count(s: &str) -> Result<u32, String> {
    let n = renderer::limits::parse_subjects(s)?;
    u32::try_from(n).map_err(|_| format!("`{s}`: too large"))
}

/// `--base-url` and `--video-base-url`: addresses links and fetches start with, so an absolute
/// http(s) URL with a host (`is_plain_url`, the rule for the platform's URLs) without a query
/// or fragment, which what is appended would break.
fn parse_base_url(s: &str) -> Result<String, String> {
    use experiment::design::online::{PLAIN_URL, is_plain_url};
    if !is_plain_url(s) {
        return Err(format!("{s:?}: expected {PLAIN_URL}"));
    }
    if s.contains(['?', '#']) {
        return Err(format!(
            "{s:?} has a query or fragment; expected the server's address alone (links add \
             /s/TOKEN)"
        ));
    }
    Ok(s.to_string())
}

fn print_budget(b: &Budget) {
    println!("a session, as a browser gets it:");
    for line in b.lines() {
        println!("  {line}");
    }
    for w in b.warnings() {
        println!("warning: {w}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    fn serve(flags: &[&str]) -> Result<ServeArgs, String> {
        let mut argv = vec!["blurlab", "serve", "--design", "d.json", "--out", "o"];
        argv.extend(flags);
        match super::super::Cli::try_parse_from(argv) {
            Ok(cli) => match cli.command {
                super::super::Command::Serve(a) => Ok(a),
                _ => unreachable!("the serve command"),
            },
            Err(e) => Err(e.to_string()),
        }
    }

    /// Issue 51 item 3: counts out of range get the range, whatever their sign.
    #[test]
    fn subject_counts_out_of_range_get_the_range() {
        for flag in ["--enrol", "--open-enrolment"] {
            for bad in ["0", "-1", "1001", "x"] {
                let e = serve(&[flag, bad]).unwrap_err();
                assert!(e.contains("from 1 to 1000"), "{flag} {bad}: {e}");
            }
            assert!(serve(&[flag, "5"]).is_ok());
        }
    }

    #[test]
    fn the_base_url_must_be_an_absolute_http_url_without_query() {
        for bad in [
            "javascript:alert(1)",
            "study.example.org",
            "https://",
            "https://a b.org",
            "https://study.example.org/?x=1",
            "https://study.example.org/#top",
        ] {
            let e = serve(&["--base-url", bad]).unwrap_err();
            assert!(e.contains("--base-url"), "{bad}: {e}");
        }
        let a = serve(&["--base-url", "https://study.example.org/lab"]).unwrap();
        assert_eq!(a.base_url.as_deref(), Some("https://study.example.org/lab"));
    }
}
