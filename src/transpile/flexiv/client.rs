//! The Mech-Mind client of the translated script: a Python class with one method per KUKA
//! `MM_*` subprogram the program calls, rendered from the askama templates under
//! `templates/py/` (`mm_client.py` and one template per method shape under `py/mm/`, all
//! extending `py/mm/method.py`). Everything the templates print that the catalog knows
//! (command numbers, success codes, reply layouts, argument ranges, status codes, limits) is
//! computed here from the catalog; the templates hold Python layout and the per-shape logic.

use std::collections::BTreeSet;

use askama::Template;

use super::options::FlexivOptions;
use crate::catalog::{Command, Direction, Param, RoutineShape, Subprogram, catalog};

/// A status code the client sets itself (catalog origin `package`).
pub struct Code {
    pub name: String,
    pub code: u32,
    pub meaning: String,
}

/// Everything `mm_client.py` prints besides the methods.
pub struct ClientView {
    pub codes: Vec<Code>,
    pub reply_timeout: u32,
    pub batch_size: u32,
    pub point_cap: usize,
    pub user_data_len: usize,
    pub plan_results_len: usize,
    pub do_list_len: usize,
    pub out_max: u32,
    pub kind_joints: u32,
    pub kind_tcp: u32,
    pub kind_custom: u32,
    pub kind_plan: u32,
    /// Rendered methods.
    pub methods: Vec<String>,
}

/// Where the fields of a reply sit (0-based, the echo is field 0), from the catalog's
/// `reply` and `record` lists. 0 for a field the command does not have.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Layout {
    /// First field of the (first) record: 1 + the fixed reply fields.
    pub head: usize,
    /// Fields per record (batch replies).
    pub record: usize,
    /// Fields before the first variable-length part of a record.
    pub fixed: usize,
    /// `count` (batch replies) or `n` (custom values).
    pub count_at: usize,
    pub all_sent_at: usize,
    pub vispos_at: usize,
    pub wtype_at: usize,
    pub label_at: usize,
    pub speed_at: usize,
    pub move_at: usize,
    pub tool_at: usize,
}

impl Layout {
    pub fn of(cmd: &Command) -> Layout {
        let fixed_reply: Vec<&str> = cmd
            .reply
            .iter()
            .map(String::as_str)
            .filter(|f| !f.ends_with("..."))
            .collect();
        let head = 1 + fixed_reply.len();
        let fixed_record = cmd
            .record
            .iter()
            .position(|f| f.ends_with("..."))
            .unwrap_or(cmd.record.len());
        let reply_at = |name: &str| {
            fixed_reply
                .iter()
                .position(|f| *f == name)
                .map_or(0, |i| i + 1)
        };
        let record_at = |name: &str| {
            cmd.record[..fixed_record]
                .iter()
                .position(|f| f == name)
                .map_or(0, |i| head + i)
        };
        Layout {
            head,
            record: cmd.record.len(),
            fixed: head + fixed_record,
            count_at: reply_at("count").max(reply_at("n")),
            all_sent_at: reply_at("all_sent"),
            vispos_at: reply_at("vision_move_pos"),
            wtype_at: reply_at("waypoint_type"),
            label_at: record_at("label"),
            speed_at: record_at("speed"),
            move_at: record_at("motion_type"),
            tool_at: record_at("tool"),
        }
    }
}

/// One method as the shape templates see it.
pub struct Method {
    /// Python name, e.g. `get_visdata`.
    pub name: String,
    /// KUKA name, e.g. `MM_Get_VisData`.
    pub krl: String,
    /// Which template renders it.
    pub shape: RoutineShape,
    pub summary: String,
    /// Docstring lines after the summary.
    pub doc: Vec<String>,
    /// Python parameter names.
    pub ins: Vec<String>,
    /// `return` expression: the OUT values in order (empty when there are none).
    pub ret: String,
    /// What a failed copy returns: `None` for every output.
    pub none_ret: String,
    pub cmd: u32,
    pub ok: u32,
    /// Python condition that is true when an argument is outside its documented range.
    pub bad: String,
    pub has_bad: bool,
    /// The request fields after the command, as Python list items.
    pub tx: String,
    /// Storage kind: a Python expression (batch) or a class constant name (copies).
    pub kind: String,
    /// `Pose` or `Axis` for copies.
    pub value: &'static str,
    pub lay: Layout,
}

/// The Python method name of a KUKA subprogram: `MM_Get_VisData` → `get_visdata`.
pub fn method_name(krl: &str) -> String {
    let bare = if crate::catalog::has_interface_prefix(krl) {
        &krl[crate::catalog::NAME_PREFIX.len()..]
    } else {
        krl
    };
    bare.to_ascii_lowercase()
}

/// A KUKA parameter's Python name.
pub fn param_name(p: &Param) -> String {
    p.ident().to_ascii_lowercase()
}

/// The subprograms the client supports: not those that move the robot (`MM_CALIB` moves it
/// through the KUKA package's own motions and is left to the user).
pub fn supported(sub: &Subprogram) -> bool {
    !sub.shape.moves()
}

/// The Python condition for one IN parameter outside its documented range.
fn range_condition(p: &Param, batch: u32) -> Option<String> {
    let id = param_name(p);
    if !p.values.is_empty() {
        let v: Vec<String> = p.values.iter().map(|v| v.to_string()).collect();
        return Some(match v.as_slice() {
            [one] => format!("{id} != {one}"),
            _ => format!("{id} not in ({})", v.join(", ")),
        });
    }
    let n = super::format::num;
    let mut parts = Vec::new();
    if let Some(m) = p.min {
        parts.push(format!("{id} < {}", n(m)));
    }
    // Pos_Num_Need may go up to the configured batch when the batch is raised (as the KUKA
    // package does).
    let max = match (p.max, p.ident()) {
        (Some(m), "Pos_Num_Need") => Some(m.max(f64::from(batch))),
        (m, _) => m,
    };
    if let Some(m) = max {
        parts.push(format!("{id} > {}", n(m)));
    }
    if let Some(m) = p.min_exclusive {
        parts.push(format!("{id} <= {}", n(m)));
    }
    (!parts.is_empty()).then(|| parts.join(" or "))
}

fn request_field(p: &Param) -> Option<String> {
    let id = param_name(p);
    Some(match p.ty.as_str() {
        "INT" => format!("_mm_int({id})"),
        "REAL" => format!("_mm_real({id})"),
        "E6POS" => format!("*_mm_pose({id})"),
        _ => return None,
    })
}

fn method(sub: &Subprogram, fx: &FlexivOptions) -> Method {
    let cat = catalog();
    let cmd = sub.commands.first().copied().unwrap_or(0);
    let command = cat.command(cmd);
    let ok = command.and_then(|c| c.success).unwrap_or(0);
    let init = sub.shape == RoutineShape::InitSocket;
    let ins: Vec<String> = if init {
        // The host program connects by address; the KUKA XML name and EKI flags have no role.
        vec!["ip".into(), "port".into(), "time_out".into()]
    } else {
        sub.params
            .iter()
            .filter(|p| p.dir == Direction::In)
            .map(param_name)
            .collect()
    };
    let bad: Vec<String> = sub
        .params
        .iter()
        .filter(|p| p.dir == Direction::In && p.ident() != "Serial")
        .filter(|p| ins.contains(&param_name(p)))
        .filter_map(|p| range_condition(p, fx.batch_size))
        .collect();
    let outs: Vec<String> = sub
        .params
        .iter()
        .filter(|p| p.dir == Direction::Out)
        .map(|p| {
            if p.status {
                "status".to_owned()
            } else {
                param_name(p)
            }
        })
        .collect();
    let ret = outs.join(", ");
    let none_ret = vec!["None"; outs.len()].join(", ");
    let tx: Vec<String> = sub
        .params
        .iter()
        .filter(|p| p.dir == Direction::In)
        .filter_map(request_field)
        .collect();
    let mut doc = Vec::new();
    for p in &sub.params {
        if init && p.dir == Direction::In && p.ident() != "Time_Out" {
            continue;
        }
        let mut line = format!(
            "{} ({}{}",
            param_name(p),
            if p.dir == Direction::In {
                "in"
            } else {
                "returned"
            },
            p.unit
                .as_ref()
                .map(|u| format!(", {u}"))
                .unwrap_or_default()
        );
        if let Some(r) = p.range_text() {
            line.push_str(&format!(", {r}"));
        }
        line.push_str(&format!("): {}", p.meaning));
        doc.push(line);
    }
    if init {
        doc.insert(
            0,
            "ip, port: the vision server (KUKA names an EKI channel here instead).".into(),
        );
    }
    let mut status = Vec::new();
    if ok != 0 {
        status.push(format!("{ok} OK, the server's codes"));
    }
    if cmd != 0 {
        status.push("NO_CONNECTION, SEND_FAILED, REPLY_TIMEOUT, BAD_REPLY, WRONG_ECHO".into());
    }
    if !bad.is_empty() {
        status.push("BAD_ARGUMENT".into());
    }
    if sub.param("Serial").is_some() {
        status.push("BAD_SERIAL, WRONG_DATA_KIND".into());
    }
    if cmd != 0 && command.is_some_and(|c| !c.record.is_empty()) {
        status.push("TOO_MANY_POINTS".into());
    }
    if !status.is_empty() {
        doc.push(format!("Status (last_status): {}.", status.join("; ")));
    }
    let kind = match (sub.param("Jps_Pos"), sub.shape) {
        (_, RoutineShape::GetJps) => "KIND_JOINTS".to_owned(),
        (_, RoutineShape::GetPose) => "KIND_TCP".to_owned(),
        (Some(_), _) => "jps_pos".to_owned(),
        (None, _) => "self.KIND_TCP".to_owned(),
    };
    let value = if sub
        .params
        .iter()
        .any(|p| p.ty == "E6AXIS" && p.dir == Direction::Out)
    {
        "Axis"
    } else {
        "Pose"
    };
    let summary = if init {
        "Stores the vision server's address and the connect timeout that every other call uses."
            .to_owned()
    } else {
        sub.summary.clone()
    };
    Method {
        name: method_name(&sub.name),
        krl: sub.name.clone(),
        shape: sub.shape,
        summary,
        doc,
        ins,
        ret,
        none_ret,
        cmd,
        ok,
        has_bad: !bad.is_empty(),
        bad: if bad.is_empty() {
            "False".into()
        } else {
            bad.join(" or ")
        },
        tx: tx.join(", "),
        kind,
        value,
        lay: command.map(Layout::of).unwrap_or_default(),
    }
}

macro_rules! method_templates {
    ($($ty:ident => $path:literal),* $(,)?) => {
        $(
            #[derive(Template)]
            #[template(path = $path, escape = "none")]
            struct $ty<'a> {
                m: &'a Method,
                // Not every shape prints something of the client view.
                #[allow(dead_code)]
                v: &'a ClientView,
            }
        )*
    };
}

method_templates! {
    InitSocket => "py/mm/init_socket.py",
    Simple => "py/mm/simple.py",
    StartVis => "py/mm/start_vis.py",
    StartViz => "py/mm/start_viz.py",
    Batch => "py/mm/batch.py",
    GetPose => "py/mm/get_pose.py",
    GetDyData => "py/mm/get_dy_data.py",
    GetDyPose => "py/mm/get_dypose.py",
    GetPlanData => "py/mm/get_plandata.py",
    GetPlanPoint => "py/mm/get_plan_point.py",
    GetDoList => "py/mm/get_dolist.py",
    SetDoList => "py/mm/set_dolist.py",
}

#[derive(Template)]
#[template(path = "py/mm_client.py", escape = "none")]
struct ClientTemplate<'a> {
    v: &'a ClientView,
}

fn render_method(m: &Method, v: &ClientView) -> askama::Result<String> {
    match m.shape {
        RoutineShape::InitSocket => InitSocket { m, v }.render(),
        RoutineShape::StartVis => StartVis { m, v }.render(),
        RoutineShape::StartViz => StartViz { m, v }.render(),
        RoutineShape::Batch => Batch { m, v }.render(),
        RoutineShape::GetPose | RoutineShape::GetJps => GetPose { m, v }.render(),
        RoutineShape::GetDyData => GetDyData { m, v }.render(),
        RoutineShape::GetDyPose => GetDyPose { m, v }.render(),
        RoutineShape::GetPlanData => GetPlanData { m, v }.render(),
        RoutineShape::GetPlanJps | RoutineShape::GetPlanPose => GetPlanPoint { m, v }.render(),
        RoutineShape::GetDoList => GetDoList { m, v }.render(),
        RoutineShape::SetDoList => SetDoList { m, v }.render(),
        // Send the IN arguments, keep the status. The client serves the 1.x interface, which
        // has no GetProperty/GetNotify/GetWobj routine; Calib is never rendered (`supported`).
        RoutineShape::Simple
        | RoutineShape::GetProperty
        | RoutineShape::GetNotify
        | RoutineShape::GetWobj
        | RoutineShape::Calib => Simple { m, v }.render(),
    }
}

/// The client with the methods for `used` (KUKA names), in catalog order.
pub fn render(used: &BTreeSet<String>, fx: &FlexivOptions) -> askama::Result<String> {
    let cat = catalog();
    let codes = cat
        .package_statuses()
        .into_iter()
        .map(|(code, name, meaning)| Code {
            name,
            code,
            meaning,
        })
        .collect();
    let l = &cat.limits;
    let mut v = ClientView {
        codes,
        reply_timeout: fx.reply_timeout,
        batch_size: fx.batch_size,
        point_cap: l.point_capacity as usize,
        user_data_len: l.user_data_len as usize,
        plan_results_len: l.plan_results_len as usize,
        do_list_len: l.do_list_len as usize,
        out_max: l.out_max,
        kind_joints: 1,
        kind_tcp: 2,
        kind_custom: 3,
        kind_plan: 4,
        methods: Vec::new(),
    };
    let mut methods = Vec::new();
    for sub in cat
        .subprograms
        .iter()
        .filter(|s| used.contains(&s.name) && supported(s))
    {
        let m = method(sub, fx);
        methods.push(render_method(&m, &v)?);
    }
    v.methods = methods;
    ClientTemplate { v: &v }.render()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_come_from_the_catalog() {
        let cat = catalog();
        let l = Layout::of(cat.command_named("get_vision_result").expect("102"));
        assert_eq!((l.head, l.record, l.count_at, l.all_sent_at), (5, 8, 3, 2));
        // The shared batch store reads label and speed right after the six values.
        for name in ["get_vision_result", "get_vision_path", "get_viz_path"] {
            let c = cat.command_named(name).expect("batch command");
            assert_eq!(&c.record[6..], ["label", "speed"], "{name}");
            assert_eq!(Layout::of(c).head, 5, "{name}");
        }
        let l = Layout::of(cat.command_named("get_custom_data").expect("110"));
        assert_eq!((l.head, l.fixed, l.count_at, l.label_at), (4, 11, 3, 10));
        let l = Layout::of(cat.command_named("get_plan_waypoint").expect("210"));
        assert_eq!(
            (
                l.head, l.fixed, l.wtype_at, l.move_at, l.tool_at, l.speed_at
            ),
            (4, 13, 3, 10, 11, 12)
        );
        let l = Layout::of(cat.command_named("get_do_list").expect("206"));
        assert_eq!(l.head, 2);
        let l = Layout::of(cat.command_named("get_viz_path").expect("205"));
        assert_eq!(l.vispos_at, 4);
    }

    #[test]
    fn ranges_become_python_conditions() {
        let cat = catalog();
        let sub = cat.subprogram("MM_Start_Vis").expect("sub");
        let m = method(sub, &FlexivOptions::default());
        assert_eq!(
            m.bad,
            "job < 1 or job > 99 or pos_num_need < 0 or pos_num_need > 20 or sendpos_type < 0 or sendpos_type > 3"
        );
        let sub = cat.subprogram("MM_Get_PlanJps").expect("sub");
        let m = method(sub, &FlexivOptions::default());
        assert_eq!(m.bad, "jps_pos not in (1, 3)");
        assert_eq!(m.ret, "mm_j, mm_movetype, mm_toolnum, mm_speed");
        let sub = cat.subprogram("MM_Get_VisData").expect("sub");
        let m = method(sub, &FlexivOptions::default());
        assert_eq!(m.ret, "last_data, pos_num, status");
        assert_eq!(m.tx, "_mm_int(job)");
    }

    #[test]
    fn every_supported_subprogram_renders() {
        let all: BTreeSet<String> = catalog()
            .subprograms
            .iter()
            .map(|s| s.name.clone())
            .collect();
        let text = render(&all, &FlexivOptions::default()).expect("renders");
        for sub in catalog().subprograms.iter().filter(|s| supported(s)) {
            assert!(
                text.contains(&format!("    def {}(self", method_name(&sub.name))),
                "{}",
                sub.name
            );
        }
        assert!(text.is_ascii());
        assert!(!text.contains("    def calib("));
    }
}
