use std::net::{SocketAddr, ToSocketAddrs};
use std::sync::mpsc;

use anyhow::{Context, bail};

use super::Outcome;
use super::args::{ServeArgs, SimArgs, SimCommand};
use crate::sim::{Scenario, Server};

pub fn run(args: SimArgs) -> anyhow::Result<Outcome> {
    match args.command {
        SimCommand::Serve(a) => serve(a),
    }
}

fn serve(args: ServeArgs) -> anyhow::Result<Outcome> {
    let mut scenario = match &args.scenario {
        None => Scenario::default_embedded(),
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read scenario {}", path.display()))?;
            Scenario::from_toml_str(&text, &path.display().to_string())?
        }
    };
    if let Some(iface) = args.interface {
        scenario = scenario.with_interface(iface).map_err(anyhow::Error::msg)?;
    }
    if let Some(codec) = args.codec {
        scenario.server.codec = codec;
    }
    let addrs: Vec<SocketAddr> = args
        .listen
        .to_socket_addrs()
        .with_context(|| {
            format!(
                "invalid listen address {:?} (expected HOST:PORT)",
                args.listen
            )
        })?
        .collect();
    if addrs.is_empty() {
        bail!("listen address {:?} resolves to nothing", args.listen);
    }
    if !args.allow_remote && addrs.iter().any(|a| !a.ip().is_loopback()) {
        bail!(
            "refusing to listen on non-loopback address {}; pass --allow-remote to serve a real robot cell",
            args.listen
        );
    }
    let summary = summary(&scenario);
    let (tx, rx) = mpsc::channel();
    let server = Server::start_with_observer(
        scenario,
        addrs.as_slice(),
        Box::new(move |r| {
            let _ = tx.send(r.to_string());
        }),
    )
    .with_context(|| format!("cannot listen on {}", args.listen))?;
    let source = args
        .scenario
        .as_ref()
        .map_or("embedded default scenario".to_string(), |p| {
            p.display().to_string()
        });
    println!(
        "krlkit sim: listening on {} ({source}); Ctrl-C stops",
        server.addr()
    );
    println!("krlkit sim: {summary}");
    // Runs until the process is interrupted; the server thread owns the socket.
    for line in rx {
        println!("{line}");
    }
    server.shutdown();
    Ok(Outcome::Success)
}

fn summary(s: &Scenario) -> String {
    let projects: Vec<String> = s
        .projects
        .iter()
        .map(|p| {
            format!(
                "{} ({} points, {} path waypoints)",
                p.id,
                p.points.len(),
                p.path.len()
            )
        })
        .collect();
    let viz = s.viz.as_ref().map_or("none".to_string(), |v| {
        format!(
            "{} waypoints, DO list {}",
            v.path.len(),
            if v.do_list.is_some() { "yes" } else { "no" }
        )
    });
    let wire = match s.server.codec {
        crate::catalog::Codec::Ascii => "ascii".to_string(),
        hex => format!("{hex}, {}-byte replies", s.server.hex_reply_bytes()),
    };
    format!(
        "interface {}, {wire}; projects: {}; viz: {viz}; calibration points: {}; faults: {}; batch {}",
        s.interface,
        if projects.is_empty() {
            "none".to_string()
        } else {
            projects.join(", ")
        },
        s.calibration.len(),
        s.faults.len(),
        s.server.batch
    )
}
