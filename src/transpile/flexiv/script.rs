//! The whole script from `templates/py/script.py`: header, runtime (version-dependent I/O
//! calls, joint map), the Mech-Mind client, the translated program and `main()`.

use askama::Template;

use super::options::{Api, JointSource, PtpPrimitive};
use super::{Tx, format, motion};
use crate::catalog::catalog;

/// Motion defaults the script starts with (and `BAS(#INITMOV)` sets): a conservative path
/// speed in m/s and joint speed in percent, stated in the script.
const DEFAULT_VEL: &str = "0.1";
const DEFAULT_PTP: &str = "10";

pub struct ScriptView {
    pub name: String,
    pub source: String,
    pub rdk: String,
    pub header: Vec<String>,
    /// A Python literal: the serial number or `None`.
    pub serial: String,
    pub input_offset: i64,
    pub output_offset: i64,
    pub zones: String,
    pub default_vel: &'static str,
    pub default_ptp: &'static str,
    pub flag_max: i64,
    pub list_outputs: bool,
    pub move_ptp: bool,
    pub joint_map: String,
    /// The JPos list for `to_jpos(j)`, when a joint map is given.
    pub joints: Option<String>,
    /// The Axis arguments for `axis_act()`, when the joint map gives every axis one joint.
    pub axes: Option<String>,
    pub client: Option<String>,
    pub program: String,
    pub entry: Option<String>,
}

#[derive(Template)]
#[template(path = "py/script.py", escape = "none")]
struct Script<'a> {
    s: &'a ScriptView,
}

pub(super) fn render(tx: &Tx<'_>, program: String) -> String {
    let fx = tx.fx;
    let source = crate::transpile::render::file_name(&tx.src.src.path);
    let name = std::path::Path::new(&source)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("program")
        .to_ascii_lowercase();
    let joints = fx.joint_map.as_ref().map(|m| {
        m.0.iter()
            .map(|s| match *s {
                JointSource::Axis {
                    axis,
                    negate,
                    offset,
                } => {
                    let a = if negate {
                        format!("-j.a{axis}")
                    } else {
                        format!("j.a{axis}")
                    };
                    match offset {
                        0.0 => a,
                        o => format!("{a} + {}", format::real(o)),
                    }
                }
                JointSource::Fixed(v) => format::real(v),
            })
            .collect::<Vec<_>>()
            .join(", ")
    });
    // The inverse: a KUKA axis from the one joint that carries it.
    let axes = fx.joint_map.as_ref().filter(|m| m.invertible()).map(|m| {
        (1..=6)
            .filter_map(|a| m.joint_of(a))
            .map(|(i, s)| match s {
                JointSource::Axis { negate, offset, .. } => {
                    let q = match offset {
                        0.0 => format!("q[{i}]"),
                        o => format!("(q[{i}] - {})", format::real(o)),
                    };
                    if negate { format!("-{q}") } else { q }
                }
                JointSource::Fixed(_) => format!("q[{i}]"),
            })
            .collect::<Vec<_>>()
            .join(", ")
    });
    let client = (!tx.mm_used.is_empty()).then(|| {
        super::client::render(&tx.mm_used, fx)
            .unwrap_or_else(|e| format!("# the Mech-Mind client could not be rendered: {e}"))
    });
    let view = ScriptView {
        name: format::ascii(&name),
        source: format::ascii(&source),
        rdk: fx.rdk.to_string(),
        header: tx.header_comment(),
        serial: fx
            .serial
            .as_deref()
            .map_or_else(|| "None".to_owned(), format::string),
        input_offset: fx.input_offset,
        output_offset: fx.output_offset,
        zones: motion::ZONES
            .iter()
            .map(|z| z.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        default_vel: DEFAULT_VEL,
        default_ptp: DEFAULT_PTP,
        flag_max: catalog().limits.flag_max,
        list_outputs: fx.rdk.api() == Api::V16,
        move_ptp: fx.ptp == PtpPrimitive::MovePtp,
        joint_map: fx
            .joint_map
            .as_ref()
            .map(|m| m.to_string())
            .unwrap_or_default(),
        joints,
        axes,
        client,
        program,
        entry: tx.entry.clone(),
    };
    // Sized for the program and the runtime around it, so the text is not grown by doubling.
    let mut text = String::with_capacity(view.program.len() + (256 << 10));
    if let Err(e) = (Script { s: &view }).render_into(&mut text) {
        text = format!("# the script could not be rendered: {e}");
    }
    text.push('\n');
    text
}
