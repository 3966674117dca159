//! The vision server a program's `MM_Init_Socket` connects to. KUKA names an EKI channel (an
//! XML file) there; the targets need the server's IP address and port themselves, taken from
//! the spec (`--spec`, or the krlkit.toml found from the working directory when it sets
//! `server_ip`/`server_port`), else from the EKI XML (`--eki-xml`, or the XML named by the call beside
//! the program or in the program's package: `--package`, else the nearest folder above it with
//! `xml/Config/User/Common/EthernetKRL/`).

use std::net::Ipv4Addr;

use super::fail::{R, fail};
use crate::catalog::Subprogram;
use crate::diag::Span;
use crate::syntax::ast::{Expr, ExprKind};
use crate::transpile::{Options, VisionServer};

/// The vision server for a call of `sub` (`MM_Init_Socket`) with `args`.
pub fn resolve(
    opts: &Options,
    sub: &Subprogram,
    args: &[Option<Expr>],
    span: Span,
    init_call: &str,
) -> R<VisionServer> {
    if let Some(s) = &opts.server {
        return Ok(s.clone());
    }
    let xml_name = sub
        .params
        .iter()
        .position(|p| p.is_array())
        .and_then(|i| args.get(i))
        .and_then(Option::as_ref)
        .and_then(|a| match &a.kind {
            ExprKind::Str(s) => Some(s.clone()),
            _ => None,
        });
    let channel = if opts.channels_given {
        opts.channels.first()
    } else {
        xml_name.as_ref().and_then(|n| {
            opts.channels.iter().find(|c| c.name == *n).or_else(|| {
                opts.channels
                    .iter()
                    .find(|c| c.name.eq_ignore_ascii_case(n))
            })
        })
    };
    let Some(ch) = channel else {
        let wanted = xml_name.map_or_else(|| "the EKI XML".to_owned(), |n| format!("{n}.xml"));
        return fail(
            span,
            format!(
                "the vision server's IP address and port are unknown: no --spec, no server_ip/server_port in a krlkit.toml, no --eki-xml, and no {wanted} beside the program or in its package (xml/Config/User/Common/EthernetKRL/ of a folder above it)"
            ),
            format!(
                "pass --spec krlkit.toml, --eki-xml FILE or --package DIR ({init_call} takes the IP address and port, not the XML name and flags)"
            ),
        );
    };
    let ip = ch.ip().and_then(|i| i.parse::<Ipv4Addr>().ok());
    match (ip, ch.config.port) {
        (Some(ip), Some(port)) => Ok(VisionServer {
            ip,
            port,
            origin: format!("EKI XML {}", ch.path),
        }),
        _ => fail(
            span,
            format!(
                "the EKI XML {} has no usable IPv4 address and port (CONFIGURATION/EXTERNAL/IP, PORT)",
                ch.path
            ),
            "fix the XML or pass --spec",
        ),
    }
}
