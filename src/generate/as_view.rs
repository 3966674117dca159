//! View models of the Kawasaki AS package: everything the templates under `templates/as/`
//! print, computed from the catalog and the spec, so the templates hold layout only.

use crate::catalog::number_text as as_num;
use crate::catalog::{AsKind, AsParam, Command, Direction, KawasakiCommand, catalog};
use crate::spec::Spec;

use super::view::Codes;

/// Longest field of a reply the package accepts (characters, blanks included).
pub const FIELD_MAX: u32 = 24;
/// Width of `$ENCODE(/F…)` for request values that are not whole numbers; blanks are trimmed.
pub const REAL_WIDTH: u32 = 16;
/// Decimals of request values that are not whole numbers (as the vendor examples print).
pub const REAL_DECIMALS: u32 = 4;
/// Comment lines are wrapped at this width (AS editors and the teach pendant show short lines).
pub const COMMENT_WIDTH: usize = 92;
/// Values of `mm_pos_kind`: joints and TCPs equal the `.getpos_type` values 1 and 2.
pub const KIND_JOINTS: u32 = 1;
pub const KIND_TCP: u32 = 2;

/// Wrap one comment text at word boundaries; continuation lines are indented by `indent`.
pub fn wrap(text: &str, indent: &str) -> Vec<String> {
    let lead = &text[..text.len() - text.trim_start().len()];
    let mut lines = Vec::new();
    let mut cur = lead.to_string();
    for word in text.trim_start().split(' ') {
        let cont = if lines.is_empty() { "" } else { indent };
        let fresh = cur.trim().is_empty();
        if !fresh && cont.len() + cur.len() + 1 + word.len() > COMMENT_WIDTH {
            lines.push(format!("{cont}{cur}"));
            cur.clear();
        }
        if !cur.trim().is_empty() {
            cur.push(' ');
        }
        cur.push_str(word);
    }
    let cont = if lines.is_empty() { "" } else { indent };
    lines.push(format!("{cont}{cur}"));
    lines
}

fn wrap_all(items: impl IntoIterator<Item = String>, indent: &str) -> Vec<String> {
    items.into_iter().flat_map(|t| wrap(&t, indent)).collect()
}

fn command(code: u32) -> &'static Command {
    catalog()
        .command(code)
        .unwrap_or_else(|| panic!("catalog has no command {code}"))
}

fn success(code: u32) -> u32 {
    command(code)
        .success
        .unwrap_or_else(|| panic!("command {code} has no success code"))
}

/// Fields of a reply before its per-point record: the echo plus the catalog's reply fields.
fn header_len(code: u32) -> u32 {
    1 + command(code).reply.len() as u32
}

/// Fields of the per-point record before its first variable-length part (`name...`).
fn record_fixed(code: u32) -> u32 {
    command(code)
        .record
        .iter()
        .take_while(|f| !f.ends_with("..."))
        .count() as u32
}

/// 1-based field index of a named reply field (echo = 1).
fn reply_index(code: u32, name: &str) -> u32 {
    let c = command(code);
    let at = c
        .reply
        .iter()
        .position(|f| f == name)
        .unwrap_or_else(|| panic!("command {code} has no reply field {name}"));
    at as u32 + 2
}

/// Sizes, settings and codes shared by the helper programs and the `mm_*` programs.
#[derive(Debug, Clone)]
pub struct AsPackage {
    pub server_ip: String,
    /// `192,168,1,121` for the `mm_init_skt` call in the notes.
    pub ip_args: String,
    pub server_port: u16,
    pub connect_timeout: u32,
    pub reply_timeout: u32,
    pub batch_size: u32,
    pub calib_wait: u32,
    /// Numbers one reply may carry.
    pub field_cap: u32,
    pub field_max: u32,
    /// Bound on received characters (plus one per string element) before a reply is refused.
    pub reply_max: u32,
    /// Longest request piece before the closing CR (one `$mm_tx[]` element).
    pub piece_max: u32,
    pub recv_chunk: u32,
    pub real_format: String,
    pub point_cap: u32,
    pub user_data_len: u32,
    pub plan_len: u32,
    pub do_list_len: u32,
    pub do_value_max: u32,
    pub kind_joints: u32,
    pub kind_tcp: u32,
    /// 102/105/205 layout: header fields, fields per point, field of the Vision Move position.
    pub batch_header: u32,
    pub point_fields: u32,
    /// 110 layout: fields before the custom values.
    pub dy_fixed: u32,
    /// 210/111 layout: fields before the Vision Move data.
    pub plan_fixed: u32,
    /// 206/106: echo, status, the DO list.
    pub do_reply_len: u32,
    /// 701 layout.
    pub calib_cmd: u32,
    pub calib_ok: u32,
    pub calib_reply_len: u32,
    pub calib_done: u32,
    pub calib_j1: u32,
    pub codes: Codes,
    /// `(code, name, meaning)` of every package-defined status code.
    pub package_codes: Vec<(u32, String, String)>,
    /// The same as wrapped comment lines.
    pub code_lines: Vec<String>,
    /// Catalog globals as `name[size]: meaning` lines.
    pub globals: Vec<String>,
    /// Unverified AS and protocol facts the package relies on, one line each.
    pub assumptions: Vec<String>,
    /// `globals` and `assumptions` wrapped as comment lines.
    pub global_lines: Vec<String>,
    pub assumption_lines: Vec<String>,
}

impl AsPackage {
    pub fn new(spec: &Spec) -> AsPackage {
        let cat = catalog();
        let l = &cat.limits;
        let kl = &cat.kawasaki_limits;
        let plan_len = cat.kawasaki_plan_len();
        let batch_header = header_len(102);
        let point_fields = record_fixed(102);
        let dy_fixed = header_len(110) + record_fixed(110);
        let plan_fixed = header_len(210) + record_fixed(210);
        let do_reply_len = header_len(206) - 1 + l.do_list_len;
        let field_cap = [
            batch_header + point_fields * spec.batch_size,
            do_reply_len,
            plan_fixed + plan_len + 1 + l.user_data_len,
            header_len(111) + record_fixed(111) + plan_len,
            dy_fixed + l.user_data_len,
            header_len(701),
        ]
        .into_iter()
        .max()
        .unwrap_or_default();
        let package_codes = cat.package_statuses();
        let globals: Vec<String> = cat
            .kawasaki_globals
            .iter()
            .map(|g| {
                let dims = match g.size.as_slice() {
                    [] => String::new(),
                    [n] => format!("[1..{n}]"),
                    [n, m] => format!("[1..{n},1..{m}]"),
                    more => format!("{more:?}"),
                };
                format!("{}{dims}: {}", g.name, g.meaning)
            })
            .collect();
        let code_lines = wrap_all(
            package_codes
                .iter()
                .map(|(c, n, m)| format!("{c} {n}: {m}")),
            "  ",
        );
        let octets = spec.server_ip.octets();
        AsPackage {
            code_lines,
            server_ip: spec.server_ip.to_string(),
            ip_args: octets.map(|o| o.to_string()).join(","),
            server_port: spec.server_port,
            connect_timeout: spec.connect_timeout,
            reply_timeout: spec.reply_timeout,
            batch_size: spec.batch_size,
            calib_wait: spec.calib_wait,
            field_cap,
            field_max: FIELD_MAX,
            reply_max: 2 * field_cap * (FIELD_MAX + 1),
            piece_max: kl.string_max - FIELD_MAX - 2,
            recv_chunk: kl.recv_chunk,
            real_format: format!("/F{REAL_WIDTH}.{REAL_DECIMALS}"),
            point_cap: l.point_capacity,
            user_data_len: l.user_data_len,
            plan_len,
            do_list_len: l.do_list_len,
            do_value_max: kl.do_value_max,
            kind_joints: KIND_JOINTS,
            kind_tcp: KIND_TCP,
            batch_header,
            point_fields,
            dy_fixed,
            plan_fixed,
            do_reply_len,
            calib_cmd: 701,
            calib_ok: success(701),
            calib_reply_len: header_len(701),
            calib_done: reply_index(701, "done"),
            calib_j1: reply_index(701, "j1"),
            codes: Codes::from_catalog(),
            package_codes,
            global_lines: wrap_all(globals.clone(), "  "),
            assumption_lines: wrap_all(assumptions(spec), "  "),
            globals,
            assumptions: assumptions(spec),
        }
    }
}

/// The unverified facts the generated AS relies on (also listed in `as/INSTALL.md`).
pub fn assumptions(spec: &Spec) -> Vec<String> {
    let kl = &catalog().kawasaki_limits;
    vec![
        "[?] Mech-Vision is set to ASCII format: fields separated by ',', every message ends in CR".into(),
        format!("[?] TCP_RECV's last argument is the most bytes per received string element; the package passes {}", kl.recv_chunk),
        format!("[?] AS string variables hold at least {} characters; requests are sent as pieces shorter than that", kl.string_max),
        "[?] TCP_CONNECT returns a socket number < 0 and TCP_SEND / TCP_RECV a result < 0 on failure or timeout".into(),
        "[?] $DECODE(s, d, 0) returns the text of s before the first d and removes it from s, leaving d; s is empty when d is absent".into(),
        format!("[?] $ENCODE(/L, v) prints a whole number without blanks; $ENCODE({}, v) prints 4 decimals padded with blanks (trimmed)", format_args!("/F{REAL_WIDTH}.{REAL_DECIMALS}")),
        "[?] VAL() reads an optional sign, digits and one '.'; the package checks every field's characters before calling it".into(),
        "[?] DECOMPOSE gives X, Y, Z, O, A, T of a pose and J1..J6 of a joint value in elements 1..6".into(),
        "[?] the flange pose sent (.sendpos_type 1 and 2, calibrate) is HERE of the active TOOL in the active BASE: run with TOOL NULL and BASE NULL for the flange in robot base".into(),
        "[?] mm_do_list entries are AS output signal numbers; 0 and -1 switch nothing; outputs are not switched off first".into(),
        format!("[?] calibrate moves with JMOVE at the caller's SPEED to the joints the server sends and waits {} s (spec calib_wait) after BREAK", spec.calib_wait),
        "[?] the package's globals are shared: call mm_ programs from one task at a time".into(),
    ]
}

/// Which template renders a program: its catalog shape.
pub use crate::catalog::ProgramShape as Shape;

/// One `mm_*` program as the templates see it.
#[derive(Debug, Clone)]
pub struct AsProgram {
    pub name: String,
    pub shape: Shape,
    /// `.job,.pos_num,.ret` exactly as seed 001 writes it.
    pub params: String,
    /// Comment lines (without the leading `; `).
    pub header: Vec<String>,
    /// The protocol command it sends (the Mech-Viz one for `.resource` programs); 0 for none.
    pub cmd: u32,
    pub ok: u32,
    /// The Mech-Vision command and its success code for `.resource > 0`; 0 when none.
    pub alt_cmd: u32,
    pub alt_ok: u32,
    /// AS condition that is TRUE when an IN value is outside its documented range.
    pub bad_args: String,
    pub has_bad_args: bool,
    /// Where the status goes: `.ret` (when the program has one) and `mm_status`.
    pub status_sets: Vec<String>,
    /// Body references of the parameters by seed name (see [`AsProgram::arg`]).
    pub args: Vec<(String, String)>,
    /// `CALL mm_tx_add(...)` arguments, in request order (real IN parameters).
    pub tx: Vec<String>,
    /// Batch fetches: the arguments of `mm_fetch` after the command and success code.
    pub fetch_args: String,
    /// Real outputs (and the fetch's own Vision Move local) set to 0 before anything can fail.
    pub zero_outs: Vec<String>,
    /// The OUT value of `mm_get_property` and its reply field (empty / 0 when none).
    pub out_name: String,
    pub out_field: u32,
}

/// The reference to a parameter inside the program body: the local with its sigil, except
/// for poses, which carry `&` in parameter lists only.
fn body_ref(p: &AsParam) -> String {
    match p.kind {
        AsKind::Pose => format!(".{}", p.ident()),
        k => format!(".{}{}", k.sigil(), p.ident()),
    }
}

/// The out-of-range condition of one real IN parameter, or None when it has no range.
fn range_condition(p: &AsParam) -> Option<String> {
    let id = body_ref(p);
    if !p.values.is_empty() {
        let ands: Vec<String> = p.values.iter().map(|v| format!("({id} <> {v})")).collect();
        return Some(group(ands, "AND"));
    }
    let mut parts = Vec::new();
    if let Some(m) = p.min {
        parts.push(format!("({id} < {})", as_num(m)));
    }
    if let Some(m) = p.max {
        parts.push(format!("({id} > {})", as_num(m)));
    }
    if let Some(m) = p.min_exclusive {
        parts.push(format!("({id} <= {})", as_num(m)));
    }
    (!parts.is_empty()).then(|| group(parts, "OR"))
}

/// Join conditions with one operator; more than one gets parentheses, so that joining groups
/// never depends on the precedence of AND over OR.
fn group(parts: Vec<String>, op: &str) -> String {
    if parts.len() == 1 {
        parts.into_iter().next().unwrap_or_default()
    } else {
        format!("({})", parts.join(&format!(" {op} ")))
    }
}

fn param_line(p: &AsParam) -> String {
    let dir = match p.dir {
        Direction::In => "in",
        Direction::Out => "out",
    };
    let mut s = format!("{} ({dir}", p.name);
    if let Some(u) = &p.unit {
        s.push_str(&format!(", {u}"));
    }
    if let Some(r) = p.range_text() {
        s.push_str(&format!(", {r}"));
    }
    s.push_str(&format!("): {}", p.meaning));
    s
}

impl AsProgram {
    pub fn new(k: &KawasakiCommand) -> AsProgram {
        let cat = catalog();
        let codes = Codes::from_catalog();
        let shape = k.shape;
        let cmd = k.commands.first().copied().unwrap_or(0);
        let ok = cat.command(cmd).and_then(|c| c.success).unwrap_or(0);
        let alt_cmd = k.commands.get(1).copied().unwrap_or(0);
        let alt_ok = cat.command(alt_cmd).and_then(|c| c.success).unwrap_or(0);
        let params = k
            .params
            .iter()
            .map(|p| p.name.as_str())
            .collect::<Vec<_>>()
            .join(",");
        let ins = || {
            k.params
                .iter()
                .filter(|p| p.dir == Direction::In && p.kind == AsKind::Real)
        };
        // The index is checked against the stored count (BAD_SERIAL), not only its range.
        let bad: Vec<String> = ins()
            .filter(|_| !matches!(shape, Shape::GetPose | Shape::GetJps))
            .filter_map(range_condition)
            .collect();
        let has_bad_args = !bad.is_empty();
        let bad_args = if has_bad_args {
            bad.join(" OR ")
        } else {
            "FALSE".into()
        };
        let ret = k.status_param().map(body_ref);
        let mut status_sets: Vec<String> = ret.iter().cloned().collect();
        status_sets.push("mm_status".into());
        let args = k
            .params
            .iter()
            .map(|p| (p.name.clone(), body_ref(p)))
            .collect();
        let tx = ins().map(body_ref).collect();

        let mut header = vec![format!("{}: {}", k.name, k.summary)];
        if k.params.is_empty() {
            header.push("Parameters: none".into());
        } else {
            header.push("Parameters:".into());
            header.extend(k.params.iter().map(|p| format!("  {}", param_line(p))));
        }
        for c in &k.commands {
            let c = command(*c);
            let ok = c
                .success
                .map_or("no status field".to_string(), |s| format!("OK {s}"));
            let when = match (k.commands.len(), c.code == alt_cmd) {
                (1, _) => String::new(),
                (_, false) => " when .resource = 0".into(),
                (_, true) => " when .resource > 0".into(),
            };
            header.push(format!("Sends {} {} ({ok}){when}", c.code, c.name));
        }
        let mut status = Vec::new();
        if cmd != 0 {
            if cat.command(cmd).is_some_and(|c| c.success.is_none()) {
                status.push("0 done".into());
            } else {
                status.push("server codes (catalog)".into());
            }
            status.push(format!("{} NO_CONNECTION", codes.no_connection));
            status.push(format!("{} SEND_FAILED", codes.send_failed));
            status.push(format!("{} REPLY_TIMEOUT", codes.reply_timeout));
            status.push(format!("{} BAD_REPLY", codes.bad_reply));
            status.push(format!("{} WRONG_ECHO", codes.wrong_echo));
            status.push(format!("{} TOO_MANY_POINTS", codes.too_many_points));
        } else if shape != Shape::InitSkt {
            status.push("0 done".into());
        }
        if shape == Shape::InitSkt {
            status.push("0 connected".into());
            status.push(format!("{} NO_CONNECTION", codes.no_connection));
        }
        if has_bad_args || shape == Shape::PlanData {
            status.push(format!("{} BAD_ARGUMENT", codes.bad_argument));
        }
        if matches!(shape, Shape::GetPose | Shape::GetJps) {
            status.push(format!("{} BAD_SERIAL", codes.bad_serial));
            status.push(format!("{} WRONG_DATA_KIND", codes.wrong_data_kind));
        }
        if shape == Shape::SetDoList {
            status.push(format!(
                "{} WRONG_DATA_KIND (no DO list stored)",
                codes.wrong_data_kind
            ));
        }
        let target = match &ret {
            Some(r) => format!("{r} and mm_status"),
            None => "mm_status".into(),
        };
        header.push(format!("Status ({target}): {}", status.join(", ")));
        match k.kuka_subprogram() {
            Some(sp) => header.push(format!("KUKA counterpart: {}", sp.signature())),
            None => header.push("KUKA counterpart: none".into()),
        }
        if let Some(a) = &k.assumption {
            header.push(format!("[?] {a}"));
        }
        for c in &k.commands {
            if let Some(a) = &command(*c).assumption {
                header.push(format!("[?] {a}"));
            }
        }

        let fetch_args = if shape == Shape::Fetch {
            let arg = |n: &str| k.param(n).map(body_ref);
            let args: Vec<String> = [arg(".job"), arg(".getpos_type")]
                .into_iter()
                .flatten()
                .collect();
            let nargs = args.len();
            let mut padded = args.clone();
            padded.resize(2, "0".into());
            let kind = arg(".getpos_type").unwrap_or_else(|| KIND_TCP.to_string());
            let pos_num = arg(".pos_num").unwrap_or_else(|| ".pos_num".into());
            // mm_get_visdata has no Vision Move output: a local takes it.
            let vispos = arg(".vispos_num").unwrap_or_else(|| ".vispos".into());
            format!(
                "{nargs},{},{},{kind},{pos_num},{vispos},.st",
                padded[0], padded[1]
            )
        } else {
            String::new()
        };
        let mut zero_outs: Vec<String> = k
            .params
            .iter()
            .filter(|p| p.dir == Direction::Out && !p.status && p.kind == AsKind::Real)
            .map(body_ref)
            .collect();
        if shape == Shape::Fetch && k.param(".vispos_num").is_none() {
            zero_outs.push(".vispos".into());
        }
        let out = k
            .params
            .iter()
            .find(|p| p.dir == Direction::Out && !p.status && shape == Shape::Simple);
        AsProgram {
            name: k.name.clone(),
            shape,
            params,
            header: header
                .into_iter()
                .flat_map(|h| {
                    let indent = if h.starts_with("  ") { "    " } else { "  " };
                    wrap(&h, indent)
                })
                .collect(),
            cmd,
            ok,
            alt_cmd,
            alt_ok,
            bad_args,
            has_bad_args,
            status_sets,
            args,
            tx,
            fetch_args,
            zero_outs,
            out_name: out.map(body_ref).unwrap_or_default(),
            out_field: out.map_or(0, |_| reply_index(cmd, "value")),
        }
    }

    /// The body reference of a parameter named as seed 001 writes it (`.#start_vis` →
    /// `.#start_vis`, `.&targetpos` → `.targetpos`).
    ///
    /// # Panics
    /// If the program has no such parameter (a template defect the package tests catch).
    pub fn arg(&self, seed_name: &str) -> &str {
        self.args
            .iter()
            .find(|(n, _)| n == seed_name)
            .map(|(_, r)| r.as_str())
            .unwrap_or_else(|| panic!("{} has no parameter {seed_name}", self.name))
    }
}
