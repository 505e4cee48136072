//! `blurlab serve`: subjects' sessions in their browsers (`experiment::web`; docs/web.md).

use clap::Args;
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
    #[arg(long, value_name = "N", conflicts_with = "open_enrolment")]
    pub enrol: Option<u32>,
    /// Open enrolment: print a /join link that creates a subject per visit, up to CAP.
    #[arg(long, value_name = "CAP")]
    pub open_enrolment: Option<u32>,
    /// The URL subjects reach the server at, for the links (behind a proxy: its https URL).
    #[arg(long)]
    pub base_url: Option<String>,
}

pub fn run(args: &ServeArgs) -> anyhow::Result<()> {
    let config = experiment::web::Config {
        design: args.design.clone(),
        out: args.out.clone(),
        addr: args.addr,
        enrol: args.enrol,
        open_enrolment: args.open_enrolment,
        base_url: args.base_url.clone(),
    };
    experiment::web::serve_until_interrupted(&config, |s| {
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
        println!("sessions:      {}", s.sessions_dir.display());
        println!("admin:         {}", s.admin_url);
        println!("stop with Ctrl-C; a restart continues every session");
    })
}
