//! View models: everything the KRL templates print, computed here from the catalog and the
//! spec, so the templates hold layout only.

use crate::catalog::number_text as krl_num;
use crate::catalog::{Interface, Param, RoutineShape, Subprogram, catalog};
use crate::spec::Spec;

use super::hex_view::{self, HexCase};

/// Package-defined status codes, looked up by symbolic name in the catalog.
#[derive(Debug, Clone)]
pub struct Codes {
    pub no_connection: u32,
    pub reply_timeout: u32,
    pub bad_reply: u32,
    pub wrong_echo: u32,
    pub too_many_points: u32,
    pub bad_serial: u32,
    pub bad_argument: u32,
    pub wrong_data_kind: u32,
    pub send_failed: u32,
}

impl Codes {
    pub fn from_catalog() -> Codes {
        let c = catalog();
        Codes {
            no_connection: c.package_code("NO_CONNECTION"),
            reply_timeout: c.package_code("REPLY_TIMEOUT"),
            bad_reply: c.package_code("BAD_REPLY"),
            wrong_echo: c.package_code("WRONG_ECHO"),
            too_many_points: c.package_code("TOO_MANY_POINTS"),
            bad_serial: c.package_code("BAD_SERIAL"),
            bad_argument: c.package_code("BAD_ARGUMENT"),
            wrong_data_kind: c.package_code("WRONG_DATA_KIND"),
            send_failed: c.package_code("SEND_FAILED"),
        }
    }
}

/// A catalog global as the data module declares it.
#[derive(Debug, Clone)]
pub struct GlobalDecl {
    pub decl: String,
    pub meaning: String,
}

fn global_decls(iface: Interface) -> Vec<GlobalDecl> {
    catalog()
        .globals_of(iface)
        .map(|g| GlobalDecl {
            decl: match g.size {
                Some(n) => format!("DECL GLOBAL {} {}[{n}]", g.ty, g.name),
                // Scalars start at 0 so a read before the first call is defined.
                None => format!("DECL GLOBAL {} {}=0", g.ty, g.name),
            },
            meaning: g.meaning.clone(),
        })
        .collect()
}

/// Sizes and settings shared by the helper module, the data module and the routines.
#[derive(Debug, Clone)]
pub struct Package {
    pub channel: String,
    pub alive_flag: u32,
    pub receive_flag: u32,
    pub connect_timeout: u32,
    pub reply_timeout: u32,
    pub timer: u32,
    pub append_cr: bool,
    pub batch_size: u32,
    /// The interface version the routines implement.
    pub interface: Interface,
    pub v2: bool,
    /// HEX framing: 4-byte fields in fixed frames (EKI RAW BYTE), packed with CAST_TO/CAST_FROM.
    pub hex: bool,
    /// HEX big-endian: every 4-byte field is byte-swapped after packing and before unpacking.
    pub big_endian: bool,
    /// HEX: the reply decoder, one case per reply layout of the commands the routines send.
    pub hex_cases: Vec<HexCase>,
    /// HEX: the INT locals of `MM_Parse_Hex` (`N`, `K` only when a case uses them: an unused
    /// local is a KRL016 finding in the generated package).
    pub hex_parse_locals: &'static str,
    /// Fields of a HEX frame (frame bytes / 4).
    pub frame_fields: u32,
    /// Commands whose reply has no status field (601): MM_Exchange returns 0 for them.
    pub no_status_cmds: Vec<u32>,
    /// Where the 8th field of a batch point is stored: `MM_Pt_Speed` (1.x) or `MM_Pt_Tool` (2.x).
    pub pt_eighth: &'static str,
    /// Fields a request has at most (`MM_Tx_Fld`).
    pub tx_fields: u32,
    /// Bytes of the receive buffer (= EKI receive record size).
    pub rx_size: u32,
    /// Bytes of the send buffer (= EKI send record size).
    pub tx_size: u32,
    /// Numbers a parsed reply can hold.
    pub field_cap: u32,
    pub point_cap: u32,
    pub user_data_len: u32,
    pub plan_results_len: u32,
    pub do_list_len: u32,
    pub out_max: u32,
    /// `(code, name, meaning)` of every package-defined status code.
    pub package_codes: Vec<(u32, String, String)>,
    /// Globals for user programs, from the catalog.
    pub globals: Vec<GlobalDecl>,
    /// Size of the channel-name buffer.
    pub channel_len: u32,
    /// Values of `MM_Pt_Kind`; joints and TCPs equal the Jps_Pos values 1 and 2.
    pub kind_joints: u32,
    pub kind_tcp: u32,
    pub kind_custom: u32,
    pub kind_plan: u32,
    pub dy_fixed: u32,
    pub plan_fixed: u32,
    pub batch_header: u32,
    pub point_fields: u32,
    /// EKI RAW element tags.
    pub rx_tag: &'static str,
    pub tx_tag: &'static str,
    /// `[U]` assumptions, one line each, repeated in the header of the data module.
    pub assumptions: Vec<String>,
    pub codes: Codes,
}

/// Tags of the EKI RAW elements (as in Mech-Mind's shipped XML).
pub const RX_TAG: &str = "MMRecv";
pub const TX_TAG: &str = "MMSend";

/// Requests are at most 16 fields (101 with joints and flange pose: 4 + 12), each at most
/// `ascii_bytes_per_point / 8` characters including the comma.
const MAX_REQUEST_FIELDS: u32 = 16;

/// Fields of a 210 reply before the Vision Move data: echo, status, all-sent, waypoint type,
/// six pose values, motion type, tool, speed.
pub const PLAN_FIXED_FIELDS: u32 = 13;
/// Fields of a 110 reply before the custom values: echo, status, all-sent, n, pose, label.
pub const DY_FIXED_FIELDS: u32 = 11;
/// Fields of a 102/105/205 reply before the points: echo, status, all-sent, count, 5th header.
pub const BATCH_HEADER_FIELDS: u32 = 5;
/// Fields per point in a 102/105/205 reply.
pub const POINT_FIELDS: u32 = 8;
/// `MM_Pt_Kind` of stored TCP poses (also the `Jps_Pos` value asking for TCP waypoints), and
/// of stored path-planning waypoints (then `MM_Plan_Jps_Pos` says joints or TCP). The
/// interpreter reads the store with these to trace the poses the vision server sent.
pub const KIND_TCP: u32 = 2;
pub const KIND_PLAN: u32 = 4;

impl Package {
    pub fn new(spec: &Spec) -> Package {
        let cat = catalog();
        let l = &cat.limits;
        let iface = spec.interface;
        let hex = spec.codec.is_hex();
        let plan_results_len = cat.plan_results_len_in(iface);
        let frame_fields = cat.hex_frame_bytes(spec.batch_size) / 4;
        let field_cap = [
            BATCH_HEADER_FIELDS + POINT_FIELDS * spec.batch_size,
            2 + l.do_list_len,
            PLAN_FIXED_FIELDS + plan_results_len + 1 + l.user_data_len,
            DY_FIXED_FIELDS + l.user_data_len,
            if hex { frame_fields } else { 0 },
        ]
        .into_iter()
        .max()
        .unwrap_or_default();
        let sent: Vec<u32> = cat
            .subprograms_of(iface)
            .iter()
            .filter(|s| spec.emits(&s.name))
            .flat_map(|s| s.commands.iter().copied())
            .collect();
        let mut no_status_cmds: Vec<u32> = sent
            .iter()
            .copied()
            .filter(|c| {
                cat.command_in(iface, *c)
                    .is_some_and(|c| c.reply.first().is_none_or(|f| f != "status"))
            })
            .collect();
        no_status_cmds.sort_unstable();
        no_status_cmds.dedup();
        let hex_cases = if hex {
            hex_view::decoder(&sent, iface, spec.receive_size())
        } else {
            Vec::new()
        };
        let package_codes = cat.package_statuses();
        Package {
            channel: spec.channel.clone(),
            alive_flag: spec.alive_flag,
            receive_flag: spec.receive_flag,
            connect_timeout: spec.connect_timeout,
            reply_timeout: spec.reply_timeout,
            timer: spec.timer,
            append_cr: spec.append_cr,
            batch_size: spec.batch_size,
            interface: iface,
            v2: iface == Interface::V2,
            hex,
            big_endian: spec.codec == crate::spec::Codec::HexBe,
            hex_parse_locals: hex_view::parse_locals(&hex_cases),
            hex_cases,
            frame_fields,
            no_status_cmds,
            tx_fields: MAX_REQUEST_FIELDS,
            pt_eighth: match iface {
                Interface::V1 => "MM_Pt_Speed",
                Interface::V2 => "MM_Pt_Tool",
            },
            rx_size: spec.receive_size(),
            // HEX requests are padded to the frame in both directions.
            tx_size: if hex {
                spec.receive_size()
            } else {
                MAX_REQUEST_FIELDS * (l.ascii_bytes_per_point / POINT_FIELDS)
            },
            field_cap,
            point_cap: l.point_capacity,
            user_data_len: l.user_data_len,
            plan_results_len,
            do_list_len: l.do_list_len,
            out_max: l.out_max,
            package_codes,
            globals: global_decls(iface),
            channel_len: 32,
            kind_joints: 1,
            kind_tcp: KIND_TCP,
            kind_custom: 3,
            kind_plan: KIND_PLAN,
            dy_fixed: DY_FIXED_FIELDS,
            plan_fixed: PLAN_FIXED_FIELDS,
            batch_header: BATCH_HEADER_FIELDS,
            point_fields: POINT_FIELDS,
            rx_tag: RX_TAG,
            tx_tag: TX_TAG,
            assumptions: assumptions(spec),
            codes: Codes::from_catalog(),
        }
    }
}

/// The unverified assumptions the generated package makes (also listed in INSTALL.md).
pub fn assumptions(spec: &Spec) -> Vec<String> {
    let cat = catalog();
    let mut out: Vec<String> = Vec::new();
    if spec.codec.is_hex() {
        let order = match spec.codec {
            crate::spec::Codec::HexBe => "big-endian (the package swaps the bytes of every field)",
            _ => "little-endian",
        };
        out.push(format!(
            "[U] Mech-Vision is set to HEX {order}; requests and replies are {}-byte frames (a 102 reply of {} points), zero-padded",
            spec.receive_size(),
            spec.batch_size.max(cat.hex.frame_min_points)
        ));
        out.push(format!("[U] HEX field kinds: {}", cat.hex.assumption));
        out.push("[U] EKI_Send(channel, buffer, length) sends the whole frame, zeros included (EthernetKRL 3.x; on EKI 2.2 a RAW BYTE element is assumed to send its Size)".into());
        out.push("[U] a HEX reply whose status field is not a 4-digit code (1000..9999) is garbled (BAD_REPLY); a reply shorter than the frame never completes the EKI record (REPLY_TIMEOUT)".into());
    } else {
        let cr = if spec.append_cr {
            "the KRL appends CR (13) to every request itself (append_cr = true)"
        } else {
            "EKI appends the STREAM end string (CR) to every request (append_cr = false)"
        };
        out.push("[U] Mech-Vision is set to ASCII format; replies end in CR; EKI_GetString may or may not strip it (both parse)".into());
        out.push(format!("[U] {cr}"));
        out.push("[U] EKI_Send on a RAW STREAM sends the CHAR array up to its first NUL (buffers are cleared with StrClear first)".into());
    }
    if spec.interface == Interface::V2 {
        out.push("[U] 2.x interface: signatures from a public note compiled from Mech-Mind's 2.2.1 KUKA page (the vendor page itself was not read); MM_Get_VisData, MM_Get_VizData and MM_Get_VisPath repeat their command until the server reports all sent".into());
        out.push("[U] 2.x status codes: the 2.x table (codes that exist or mean something else only in 2.x) is the same note's copy of the vendor's 2.2.1 status page; the package passes them on as the server sends them".into());
    }
    out.extend([
        "[U] flange pose = $BASE:$POS_ACT:INV_POS($TOOL), i.e. in WORLD (equal to ROBROOT on a fixed robot)".into(),
        "[U] returned E6POS targets only get X,Y,Z,A,B,C; S, T and E1..E6 of the caller's variable are left untouched".into(),
        format!("[U] Do_Port entries are $OUT numbers; entries outside 1..{} (0, -1) switch nothing; outputs are not cleared first", cat.limits.out_max),
        "[U] MM_CALIB moves the flange (TOOL and BASE = $NULLFRAME during the move); E1 is written to the target's E1 and not sent".into(),
        format!("[U] $TIMER[{}] is reserved for the package", spec.timer),
    ]);
    out
}

/// The catalog's unverified facts about the emitted routines and the commands they send, one
/// line each (`[U] MM_Set_DoList: ...`), for the install note.
pub fn routine_assumptions(spec: &Spec) -> Vec<String> {
    let cat = catalog();
    let iface = spec.interface;
    let mut out = Vec::new();
    let mut commands: Vec<u32> = Vec::new();
    for sp in cat
        .subprograms_of(iface)
        .iter()
        .filter(|s| spec.emits(&s.name))
    {
        if let Some(src) = &sp.source {
            out.push(format!("[U] {} signature: {src}", sp.name));
        }
        if let Some(a) = &sp.assumption {
            out.push(format!("[U] {}: {a}", sp.name));
        }
        commands.extend(&sp.commands);
    }
    commands.sort_unstable();
    commands.dedup();
    for c in commands {
        if let Some(a) = cat.command_in(iface, c).and_then(|c| c.assumption.as_ref()) {
            out.push(format!("[U] command {c}: {a}"));
        }
    }
    // The package's own codes are krlkit's decisions, listed with their meaning above.
    for s in cat
        .statuses_of(iface)
        .filter(|s| s.origin != crate::catalog::Origin::Package)
    {
        if let Some(a) = &s.assumption {
            out.push(format!("[U] status {}: {a}", s.code));
        }
    }
    out
}

/// One `MM_*` routine as the templates see it.
#[derive(Debug, Clone)]
pub struct Routine {
    pub name: String,
    /// Which template renders it.
    pub shape: RoutineShape,
    /// `Job:IN,Last_Data:OUT,...` as the seed writes it.
    pub params: String,
    pub decls: Vec<String>,
    /// Comment lines (without the leading `; `).
    pub header: Vec<String>,
    /// The first protocol command it sends (0 for local copies).
    pub cmd: u32,
    /// Success status of that command.
    pub ok: u32,
    /// KRL condition that is TRUE when an IN argument is out of its documented range.
    pub bad_args: String,
    /// KRL statement prefix that stores a status: `MM_Status` or `MM_Last_Status`.
    pub status_var: String,
    pub has_status_param: bool,
    /// Whether any IN argument has a documented range (`bad_args` is not just `FALSE`).
    pub has_bad_args: bool,
    /// Statements appending the IN arguments to the request, in order.
    pub tx: Vec<String>,
    /// Extra local declarations.
    pub locals: Vec<String>,
    /// Variable receiving the Vision Move position of a batch (a local when not an output).
    pub vispos: String,
    /// Kind of stored points for batch fetches (`Jps_Pos` or the TCP kind).
    pub kind: String,
    /// Fields of a full reply (echo + reply fields of the catalog).
    pub reply_len: usize,
    /// The second command of a routine with a `Resource` choice (2.x MM_Get_DoList: 106,
    /// MM_Get_PlanData: 111) and its success code; 0 otherwise.
    pub alt_cmd: u32,
    pub alt_ok: u32,
    /// The output that receives the 8th field of a point (`MM_Speed` in 1.x, `MM_ToolId` in
    /// 2.x), empty when the routine has none.
    pub eighth_out: String,
    /// 2.x batch fetches repeat their command until the server reports all sent.
    pub fetch_all: bool,
    /// Waypoint replies (210, 111): fields before the Vision Move data (echo included) of the
    /// first and the second command, and the 1-based field of the speed in the second's reply
    /// (0 when its layout has none: 2.x 111).
    pub plan_fixed: u32,
    pub alt_plan_fixed: u32,
    pub alt_speed_at: u32,
}

/// The out-of-range condition of one IN parameter, or None when it has no range.
fn range_condition(p: &Param, spec: &Spec) -> Option<String> {
    let id = p.ident();
    if !p.values.is_empty() {
        let ors: Vec<String> = p.values.iter().map(|v| format!("({id} == {v})")).collect();
        return Some(format!("NOT ({})", ors.join(" OR ")));
    }
    let mut parts = Vec::new();
    if let Some(m) = p.min {
        parts.push(format!("({id} < {})", krl_num(m)));
    }
    // Pos_Num_Need may go up to the configured batch when the batch is raised.
    let max = match (p.max, id) {
        (Some(m), "Pos_Num_Need") => Some(m.max(f64::from(spec.batch_size))),
        (m, _) => m,
    };
    if let Some(m) = max {
        parts.push(format!("({id} > {})", krl_num(m)));
    }
    if let Some(m) = p.min_exclusive {
        parts.push(format!("({id} <= {})", krl_num(m)));
    }
    (!parts.is_empty()).then(|| parts.join(" OR "))
}

fn param_line(p: &Param, spec: &Spec) -> String {
    let mut s = format!(
        "{} ({}, {}",
        p.ident(),
        p.dir.krl(),
        p.ty.trim_end_matches("[]")
    );
    if let Some(u) = &p.unit {
        s.push_str(&format!(", {u}"));
    }
    if let Some(r) = p.range_text() {
        let r = if p.ident() == "Pos_Num_Need" && spec.batch_size > p.max.unwrap_or(0.0) as u32 {
            format!("0 to {}", spec.batch_size)
        } else {
            r
        };
        s.push_str(&format!(", {r}"));
    }
    s.push_str(&format!("): {}", p.meaning));
    s
}

impl Routine {
    pub fn new(sp: &Subprogram, spec: &Spec) -> Routine {
        let cat = catalog();
        let codes = Codes::from_catalog();
        let iface = sp.interface;
        let cmd = sp.commands.first().copied().unwrap_or(0);
        let ok = cat
            .command_in(iface, cmd)
            .and_then(|c| c.success)
            .unwrap_or(0);
        let alt_cmd = sp.commands.get(1).copied().unwrap_or(0);
        let alt_ok = cat
            .command_in(iface, alt_cmd)
            .and_then(|c| c.success)
            .unwrap_or(0);
        let params = sp
            .params
            .iter()
            .map(|p| format!("{}:{}", p.name, p.dir.krl()))
            .collect::<Vec<_>>()
            .join(",");
        let decls = sp
            .params
            .iter()
            .map(|p| {
                let ty = p.ty.trim_end_matches("[]");
                let arr = if p.is_array() { "[]" } else { "" };
                format!("DECL {ty} {}{arr}", p.ident())
            })
            .collect();
        // Serial is checked against the stored count (BAD_SERIAL), not its catalog range.
        let bad: Vec<String> = sp
            .params
            .iter()
            .filter(|p| p.dir == crate::catalog::Direction::In && p.ident() != "Serial")
            .filter_map(|p| range_condition(p, spec))
            .collect();
        let bad_args = if bad.is_empty() {
            "FALSE".to_string()
        } else {
            bad.join(" OR ")
        };
        let status_param = sp.status_param();
        let status_var =
            status_param.map_or("MM_Last_Status".to_string(), |p| p.ident().to_string());

        let mut header = vec![format!("{}: {}", sp.name, sp.summary)];
        if sp.params.is_empty() {
            header.push("Parameters: none".into());
        } else {
            header.push("Parameters:".into());
            header.extend(
                sp.params
                    .iter()
                    .map(|p| format!("  {}", param_line(p, spec))),
            );
        }
        let mut status = Vec::new();
        if cmd != 0 {
            if alt_cmd != 0 {
                status.push(format!("{ok} or {alt_ok} OK"));
            } else if cat
                .command_in(iface, cmd)
                .is_some_and(|c| c.reply.first().is_none_or(|f| f != "status"))
            {
                status.push("0 OK".into());
            } else {
                status.push(format!("{ok} OK"));
            }
            status.push("server codes (catalog)".into());
            status.push(format!("{} NO_CONNECTION", codes.no_connection));
            status.push(format!("{} SEND_FAILED", codes.send_failed));
            status.push(format!("{} REPLY_TIMEOUT", codes.reply_timeout));
            status.push(format!("{} BAD_REPLY", codes.bad_reply));
            status.push(format!("{} WRONG_ECHO", codes.wrong_echo));
        }
        if cmd == 0 && sp.param("Serial").is_none() {
            status.push("0 done".into());
        }
        if !bad.is_empty() {
            status.push(format!("{} BAD_ARGUMENT", codes.bad_argument));
        }
        if sp.param("Serial").is_some() {
            status.push(format!("{} BAD_SERIAL", codes.bad_serial));
            status.push(format!("{} WRONG_DATA_KIND", codes.wrong_data_kind));
        }
        if cat.command_in(iface, cmd).is_some_and(|c| c.is_paged()) {
            status.push(format!("{} TOO_MANY_POINTS", codes.too_many_points));
        }
        if sp.shape == RoutineShape::SetDoList {
            status.push(format!(
                "{} WRONG_DATA_KIND (no DO list stored)",
                codes.wrong_data_kind
            ));
        }
        if !status.is_empty() {
            let target = match status_param {
                Some(p) => format!("{} and MM_Last_Status", p.ident()),
                None => "MM_Last_Status".into(),
            };
            header.push(format!("Status ({target}): {}", status.join(", ")));
        }
        if sp.commands.is_empty()
            && !matches!(sp.shape, RoutineShape::InitSocket | RoutineShape::SetDoList)
        {
            header.push(
                "On success MM_Last_Status keeps the status of the call that stored the data."
                    .into(),
            );
        }
        if let Some(a) = &sp.assumption {
            header.push(format!("[U] {a}"));
        }
        if let Some(src) = &sp.source {
            header.push(format!("[U] signature: {src}"));
        }
        for c in &sp.commands {
            if let Some(a) = cat
                .command_in(iface, *c)
                .and_then(|c| c.assumption.as_ref())
            {
                header.push(format!("[U] {a}"));
            }
        }
        let tx = sp
            .params
            .iter()
            .filter(|p| p.dir == crate::catalog::Direction::In)
            .filter_map(|p| {
                let f = match p.ty.as_str() {
                    "INT" => "MM_Tx_Int",
                    "REAL" => "MM_Tx_Real",
                    "E6POS" => "MM_Tx_Pose",
                    _ => return None,
                };
                Some(format!("{f}({})", p.ident()))
            })
            .collect();
        let has_vispos = sp.param("VisPos_Num").is_some();
        let vispos = if has_vispos {
            "VisPos_Num"
        } else {
            "Vis_Dummy"
        }
        .to_string();
        let locals = if has_vispos {
            vec![]
        } else {
            vec!["DECL INT Vis_Dummy".to_string()]
        };
        let kind = if sp.param("Jps_Pos").is_some() {
            "Jps_Pos".to_string()
        } else {
            "2".to_string()
        };
        let reply_len = cat.command_in(iface, cmd).map_or(0, |c| 1 + c.reply.len());
        let eighth_out = ["MM_Speed", "MM_ToolId"]
            .into_iter()
            .find(|n| sp.param(n).is_some())
            .unwrap_or_default()
            .to_string();
        // Paged point replies (a count and an all-sent flag, per the catalog): 2.x routines
        // fetch every batch themselves.
        let fetch_all = iface == Interface::V2
            && cat
                .command_in(iface, cmd)
                .is_some_and(|c| c.is_counted_pages());
        // Echo + reply fields + record fields before the Vision Move data.
        let plan_fixed_of = |code: u32| {
            cat.command_in(iface, code).map_or(0, |c| {
                let before = c
                    .record
                    .iter()
                    .position(|f| f == "plan_results...")
                    .unwrap_or(c.record.len());
                (1 + c.reply.len() + before) as u32
            })
        };
        let alt_speed_at = cat.command_in(iface, alt_cmd).map_or(0, |c| {
            c.record
                .iter()
                .position(|f| f == "speed")
                .map_or(0, |i| (2 + c.reply.len() + i) as u32)
        });
        Routine {
            shape: sp.shape,
            plan_fixed: plan_fixed_of(cmd),
            alt_plan_fixed: plan_fixed_of(alt_cmd),
            alt_speed_at,
            alt_cmd,
            alt_ok,
            eighth_out,
            fetch_all,
            tx,
            locals,
            vispos,
            kind,
            reply_len,
            name: sp.name.clone(),
            params,
            decls,
            header,
            cmd,
            ok,
            bad_args,
            status_var,
            has_status_param: status_param.is_some(),
            has_bad_args: !bad.is_empty(),
        }
    }
}
