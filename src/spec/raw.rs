//! The spec as written (every value optional and spanned), and its validation into [`Spec`].

use serde::Deserialize;
use toml::Spanned;

use super::{Codec, LineEnding, Spec, SpecError, TIMER_RANGE};
use crate::catalog::{Interface, catalog};

/// Every key of the spec, for "did you mean" help.
pub(crate) const KEYS: &[&str] = &[
    "channel",
    "server_ip",
    "server_port",
    "alive_flag",
    "receive_flag",
    "connect_timeout",
    "reply_timeout",
    "batch_size",
    "codec",
    "interface",
    "timer",
    "append_cr",
    "subprograms",
    "line_endings",
    "calib_wait",
    "srci_status",
    "srci_output",
    // The tables of the same file that other stages read (see `config`).
    "lint",
    "fmt",
];

pub(crate) fn nearest_key(key: &str) -> Option<&'static str> {
    crate::catalog::nearest_key(key, KEYS)
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSpec {
    channel: Option<Spanned<String>>,
    server_ip: Option<Spanned<String>>,
    server_port: Option<Spanned<i64>>,
    alive_flag: Option<Spanned<i64>>,
    receive_flag: Option<Spanned<i64>>,
    connect_timeout: Option<Spanned<i64>>,
    reply_timeout: Option<Spanned<i64>>,
    batch_size: Option<Spanned<i64>>,
    codec: Option<Spanned<Codec>>,
    interface: Option<Spanned<Interface>>,
    timer: Option<Spanned<i64>>,
    append_cr: Option<bool>,
    subprograms: Option<Spanned<Vec<Spanned<String>>>>,
    line_endings: Option<LineEnding>,
    calib_wait: Option<Spanned<i64>>,
    srci_status: Option<bool>,
    srci_output: Option<Spanned<i64>>,
    /// `[lint]` and `[fmt]`: the same `krlkit.toml` configures `check` and `fmt`; `config`
    /// reads and validates them.
    #[serde(rename = "lint")]
    _lint: Option<serde::de::IgnoredAny>,
    #[serde(rename = "fmt")]
    _fmt: Option<serde::de::IgnoredAny>,
}

/// Defaults for keys a spec leaves out. They equal the values in the default spec file (a test
/// checks that), which reproduces Mech-Mind's shipped settings.
mod default {
    pub const CHANNEL: &str = "XML_Kuka_MMIND";
    pub const SERVER_IP: std::net::Ipv4Addr = std::net::Ipv4Addr::new(192, 168, 1, 121);
    pub const SERVER_PORT: u16 = 50000;
    pub const ALIVE_FLAG: u32 = 873;
    pub const RECEIVE_FLAG: u32 = 871;
    pub const CONNECT_TIMEOUT: u32 = 60;
    pub const REPLY_TIMEOUT: u32 = 15;
    pub const TIMER: u32 = 64;
    /// Seconds; the vendor default of MM_CALIB's WaitTime.
    pub const CALIB_WAIT: u32 = 2;
    /// `$OUT[993]`..`$OUT[1024]`: a placeholder; map the group to the fieldbus.
    pub const SRCI_OUTPUT: u32 = 993;
}

struct Ctx<'a> {
    text: &'a str,
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, offset: usize, message: String, help: String) -> SpecError {
        SpecError::at(self.text, self.file, offset, message, help)
    }

    fn int_in(
        &self,
        v: &Option<Spanned<i64>>,
        key: &str,
        min: i64,
        max: i64,
        default: u32,
    ) -> Result<u32, SpecError> {
        let Some(v) = v else { return Ok(default) };
        let n = *v.get_ref();
        if n < min || n > max {
            return Err(self.err(
                v.span().start,
                format!("`{key}` = {n} is out of range"),
                format!("use a value from {min} to {max}"),
            ));
        }
        u32::try_from(n).map_err(|_| {
            self.err(
                v.span().start,
                format!("`{key}` = {n} is out of range"),
                format!("use a value from {min} to {max}"),
            )
        })
    }
}

/// A channel name must be a valid KRL string argument and a portable file stem.
fn channel_problem(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        return Some("is empty");
    }
    if name.len() > catalog().limits.krl_identifier_max {
        return Some("is longer than 24 characters");
    }
    if !name.chars().next().is_some_and(|c| c.is_ascii_alphabetic()) {
        return Some("does not start with a letter");
    }
    if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Some("contains characters other than letters, digits and `_`");
    }
    None
}

impl RawSpec {
    pub(crate) fn validate(self, text: &str, file: &str) -> Result<Spec, SpecError> {
        let cx = Ctx { text, file };
        let lim = &catalog().limits;

        let channel = match &self.channel {
            None => default::CHANNEL.to_string(),
            Some(c) => {
                if let Some(p) = channel_problem(c.get_ref()) {
                    return Err(cx.err(
                        c.span().start,
                        format!("channel name `{}` {p}", c.get_ref()),
                        "use 1 to 24 ASCII letters, digits or `_`, starting with a letter \
                         (it is the XML file stem and the KRL string passed to MM_Init_Socket)"
                            .into(),
                    ));
                }
                c.get_ref().clone()
            }
        };

        let server_ip = match &self.server_ip {
            None => default::SERVER_IP,
            Some(ip) => {
                let addr: std::net::Ipv4Addr = ip.get_ref().parse().map_err(|_| {
                    cx.err(
                        ip.span().start,
                        format!("`server_ip` = \"{}\" is not an IPv4 address", ip.get_ref()),
                        "write the vision PC's address as four dotted numbers, e.g. \"192.168.1.121\""
                            .into(),
                    )
                })?;
                if addr.is_unspecified() || addr.is_broadcast() || addr.is_multicast() {
                    return Err(cx.err(
                        ip.span().start,
                        format!(
                            "`server_ip` = \"{addr}\" is not an address the robot can connect to (it names {} hosts, not the vision PC)",
                            if addr.is_unspecified() { "any or no" } else { "many" }
                        ),
                        "write the vision PC's own address, e.g. \"192.168.1.121\"".into(),
                    ));
                }
                addr
            }
        };

        let server_port = cx.int_in(
            &self.server_port,
            "server_port",
            1,
            i64::from(lim.eki_port_max),
            u32::from(default::SERVER_PORT),
        )? as u16;
        let (fmin, fmax) = (lim.flag_min, lim.flag_max);
        let alive_flag = cx.int_in(
            &self.alive_flag,
            "alive_flag",
            fmin,
            fmax,
            default::ALIVE_FLAG,
        )?;
        let receive_flag = cx.int_in(
            &self.receive_flag,
            "receive_flag",
            fmin,
            fmax,
            default::RECEIVE_FLAG,
        )?;
        if alive_flag == receive_flag {
            let at = self
                .receive_flag
                .as_ref()
                .or(self.alive_flag.as_ref())
                .map_or(0, |s| s.span().start);
            return Err(cx.err(
                at,
                format!("`alive_flag` and `receive_flag` are both {alive_flag}"),
                "use two different $FLAG numbers: EKI sets the alive flag while connected and \
                 the receive flag when a reply arrived"
                    .into(),
            ));
        }
        let connect_timeout = cx.int_in(
            &self.connect_timeout,
            "connect_timeout",
            1,
            3600,
            default::CONNECT_TIMEOUT,
        )?;
        let reply_timeout = cx.int_in(
            &self.reply_timeout,
            "reply_timeout",
            1,
            3600,
            default::REPLY_TIMEOUT,
        )?;
        let batch_size = cx.int_in(
            &self.batch_size,
            "batch_size",
            1,
            i64::from(lim.batch_max),
            lim.batch_default,
        )?;
        let codec = self.codec.as_ref().map_or(Codec::Ascii, |c| *c.get_ref());
        let interface = self
            .interface
            .as_ref()
            .map_or(Interface::V1, |i| *i.get_ref());
        let timer = cx.int_in(
            &self.timer,
            "timer",
            i64::from(TIMER_RANGE.0),
            i64::from(TIMER_RANGE.1),
            default::TIMER,
        )?;

        let calib_wait = cx.int_in(&self.calib_wait, "calib_wait", 1, 60, default::CALIB_WAIT)?;
        // 32 outputs from `srci_output` on, all within $OUT[1..out_max].
        let srci_output = cx.int_in(
            &self.srci_output,
            "srci_output",
            1,
            i64::from(lim.out_max) - 31,
            default::SRCI_OUTPUT,
        )?;

        let subprograms = match &self.subprograms {
            None => catalog()
                .subprograms_of(interface)
                .iter()
                .map(|s| s.name.clone())
                .collect(),
            Some(list) => select_subprograms(&cx, list.get_ref(), interface)?,
        };

        let spec = Spec {
            channel,
            server_ip,
            server_port,
            alive_flag,
            receive_flag,
            connect_timeout,
            reply_timeout,
            batch_size,
            codec,
            interface,
            timer,
            append_cr: self.append_cr.unwrap_or(false),
            subprograms,
            line_endings: self.line_endings.unwrap_or(LineEnding::Crlf),
            calib_wait,
            srci_status: self.srci_status.unwrap_or(false),
            srci_output,
        };
        if spec.receive_size() > lim.eki_raw_size_max {
            let at = self
                .batch_size
                .as_ref()
                .map(|s| s.span().start)
                .or(self.codec.as_ref().map(|s| s.span().start))
                .unwrap_or(0);
            return Err(cx.err(
                at,
                format!(
                    "a batch of {} points needs a {}-byte EKI record ({}), more than EKI's {}",
                    spec.batch_size,
                    spec.receive_size(),
                    spec.codec,
                    lim.eki_raw_size_max
                ),
                "lower `batch_size`".into(),
            ));
        }
        Ok(spec)
    }
}

/// Resolve names against the catalog of `iface` (case-insensitive), keep catalog order, always
/// include `MM_Init_Socket` (every other routine needs it).
fn select_subprograms(
    cx: &Ctx<'_>,
    list: &[Spanned<String>],
    iface: Interface,
) -> Result<Vec<String>, SpecError> {
    let cat = catalog();
    let subs = cat.subprograms_of(iface);
    let mut wanted = Vec::new();
    for item in list {
        let name = item.get_ref();
        if name == "all" {
            return Ok(subs.iter().map(|s| s.name.clone()).collect());
        }
        match cat.subprogram_in(iface, name) {
            Some(s) => wanted.push(s.name.as_str()),
            None => {
                let other = Interface::ALL.into_iter().find(|&i| i != iface);
                let help = match (cat.nearest_subprogram_in(iface, name), other) {
                    (_, Some(o)) if cat.subprogram_in(o, name).is_some() => format!(
                        "`{name}` belongs to the {o} interface; remove it or set \
                         `interface = \"{o}\"`"
                    ),
                    (Some(s), _) => format!("did you mean `{}`?", s.name),
                    (None, _) => format!(
                        "valid names: {}, or \"all\"",
                        subs.iter()
                            .map(|s| s.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                };
                return Err(cx.err(
                    item.span().start,
                    format!("unknown {iface} subprogram `{name}`"),
                    help,
                ));
            }
        }
    }
    let init = &subs[0].name;
    Ok(subs
        .iter()
        .filter(|s| &s.name == init || wanted.contains(&s.name.as_str()))
        .map(|s| s.name.clone())
        .collect())
}
