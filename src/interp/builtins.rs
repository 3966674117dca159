//! Built-in functions: math, strings, SWRITE/SREAD, CAST_TO/CAST_FROM, messages, EKI_*.

use crate::syntax::ast::{Expr, ExprKind};

use super::format::{Piece, Scanned, format_one, parse_format, scan};
use super::machine::{Machine, R};
use super::value::Value;

/// Run built-in `name`; `Ok(None)` if there is no such built-in.
pub(crate) fn call(m: &mut Machine, name: &str, args: &[Option<Expr>]) -> R<Option<Value>> {
    let up = name.to_ascii_uppercase();
    if up.starts_with("EKI_") {
        return super::eki::call(m, &up, args).map(Some);
    }
    let real = |m: &mut Machine, i: usize| -> R<f64> {
        match m.arg_value(args, i, name)? {
            Value::Int(x) => Ok(x as f64),
            Value::Real(x) => Ok(x),
            v => Err(m.err(format!(
                "{name}: expected a number, found {}",
                v.kind_name()
            ))),
        }
    };
    let text = |m: &mut Machine, i: usize| -> R<String> {
        let v = m.arg_value(args, i, name)?;
        v.as_text()
            .ok_or_else(|| m.err(format!("{name}: argument {} must be a string", i + 1)))
    };
    let v = match up.as_str() {
        "ABS" => match m.arg_value(args, 0, name)? {
            Value::Int(i) => Value::Int(i.abs()),
            Value::Real(r) => Value::Real(r.abs()),
            v => return Err(m.err(format!("ABS of {}", v.kind_name()))),
        },
        "SQRT" => {
            let x = real(m, 0)?;
            if x < 0.0 {
                return Err(m.err("SQRT of a negative number"));
            }
            Value::Real(x.sqrt())
        }
        "SIN" => Value::Real(real(m, 0)?.to_radians().sin()),
        "COS" => Value::Real(real(m, 0)?.to_radians().cos()),
        "TAN" => Value::Real(real(m, 0)?.to_radians().tan()),
        "ASIN" | "ACOS" => {
            let x = real(m, 0)?;
            if !(-1.0..=1.0).contains(&x) {
                return Err(m.err(format!("{up} of {x} is undefined")));
            }
            Value::Real(if up == "ASIN" { x.asin() } else { x.acos() }.to_degrees())
        }
        "ATAN2" => {
            let y = real(m, 0)?;
            let x = real(m, 1)?;
            Value::Real(y.atan2(x).to_degrees())
        }
        "EXP" => Value::Real(real(m, 0)?.exp()),
        "LN" => Value::Real(real(m, 0)?.ln()),
        "INV_POS" => {
            let v = m.arg_value(args, 0, name)?;
            super::frame::inverse(&v).ok_or_else(|| m.err("INV_POS needs a frame"))?
        }
        "STRLEN" => Value::Int(text(m, 0)?.len() as i64),
        "STRDECLLEN" => match m.arg_value(args, 0, name)? {
            Value::Array { items, .. } => Value::Int(items.len() as i64),
            Value::Str(s) => Value::Int(s.len() as i64),
            _ => return Err(m.err("StrDeclLen needs a CHAR array")),
        },
        "STRCLEAR" => {
            let p = m.arg_place(args, 0, name)?;
            let len = char_len(m, &p)?;
            m.assign(&p, Value::char_array(b"", len))?;
            Value::Bool(true)
        }
        "STRCOPY" => {
            let p = m.arg_place(args, 0, name)?;
            let src = text(m, 1)?;
            let len = char_len(m, &p)?;
            // StrCopy cuts what does not fit and says so (FALSE), unlike an assignment.
            m.assign(&p, Value::char_array(src.as_bytes(), len))?;
            Value::Bool(src.len() <= len)
        }
        "STRADD" => {
            let p = m.arg_place(args, 0, name)?;
            let cur = m.read_value(&p)?.as_text().unwrap_or_default();
            let add = text(m, 1)?;
            let len = char_len(m, &p)?;
            let joined = format!("{cur}{add}");
            m.assign(&p, Value::char_array(joined.as_bytes(), len))?;
            Value::Int(joined.len().min(len) as i64)
        }
        "STRCOMP" => {
            let a = text(m, 0)?;
            let b = text(m, 1)?;
            let ignore_case = match args.get(2).and_then(|a| a.as_ref()) {
                Some(e) => m.eval_bool(e)?,
                None => false,
            };
            Value::Bool(if ignore_case {
                a.eq_ignore_ascii_case(&b)
            } else {
                a == b
            })
        }
        "STRFIND" => {
            let start = m.eval_int(
                args.first()
                    .and_then(|a| a.as_ref())
                    .ok_or_else(|| m.err("StrFind: start missing"))?,
            )?;
            let hay = text(m, 1)?;
            let needle = text(m, 2)?;
            let ignore_case = match args.get(3).and_then(|a| a.as_ref()) {
                Some(e) => m.eval_bool(e)?,
                None => false,
            };
            let (h, n) = if ignore_case {
                (hay.to_ascii_uppercase(), needle.to_ascii_uppercase())
            } else {
                (hay, needle)
            };
            let from = (start.max(1) - 1) as usize;
            Value::Int(match h.get(from..).and_then(|s| s.find(&n)) {
                Some(i) => (from + i + 1) as i64,
                None => 0,
            })
        }
        "STRTOINT" | "STRTOREAL" | "STRTOBOOL" => {
            let s = text(m, 0)?;
            let p = m.arg_place(args, 1, name)?;
            let s = s.trim();
            let v = match up.as_str() {
                "STRTOINT" => s.parse::<i64>().ok().map(Value::Int),
                "STRTOREAL" => s.parse::<f64>().ok().map(Value::Real),
                _ => match s.to_ascii_uppercase().as_str() {
                    "TRUE" | "1" => Some(Value::Bool(true)),
                    "FALSE" | "0" => Some(Value::Bool(false)),
                    _ => None,
                },
            };
            match v {
                Some(v) => {
                    m.assign(&p, v)?;
                    Value::Bool(true)
                }
                None => Value::Bool(false),
            }
        }
        "SWRITE" => swrite(m, args)?,
        "SREAD" => sread(m, args)?,
        "MSGNOTIFY" | "MSGQUIT" | "MSGSTATE" | "MSGDIALOG" => {
            let t = text(m, 0)?;
            m.message(t);
            Value::Int(0)
        }
        "SET_KRLMSG" => {
            // Set_KrlMsg(#TYPE, msg, par[], opt): the message text with %1..%3 filled in.
            let text = krl_msg_text(m, args, 1, 2, name)?;
            m.message(text);
            next_handle(m)
        }
        "SET_KRLDLG" => {
            // Set_KrlDlg(msg, par[], softkeys[], opt): nobody is there to answer, so the dialog
            // is answered at once with its first softkey (Exists_KrlDlg reports it).
            let text = krl_msg_text(m, args, 0, 1, name)?;
            let key = match m.arg_value(args, 2, name) {
                Ok(Value::Array { items, .. }) => items
                    .first()
                    .and_then(|k| k.field("SK_TXT"))
                    .and_then(|t| t.as_text())
                    .unwrap_or_default(),
                _ => String::new(),
            };
            m.message(format!("{text} [dialog answered: {}]", key.trim()));
            next_handle(m)
        }
        // Messages are printed, not kept: none is pending, every dialog was answered (softkey 1).
        "EXISTS_KRLMSG" => {
            m.arg_value(args, 0, name)?;
            Value::Bool(false)
        }
        "EXISTS_KRLDLG" => {
            m.arg_value(args, 0, name)?;
            if args.get(1).and_then(|a| a.as_ref()).is_some() {
                let p = m.arg_place(args, 1, name)?;
                m.assign(&p, Value::Int(1))?;
            }
            Value::Bool(false)
        }
        "CLEAR_KRLMSG" => {
            m.arg_value(args, 0, name)?;
            Value::Bool(true)
        }
        "BAS" => m.bas(args)?,
        // KRL system functions a simulation without kinematics or serial channels cannot give.
        "CAST_TO" => super::cast::cast_to(m, args)?,
        "CAST_FROM" => super::cast::cast_from(m, args)?,
        "CWRITE" | "CREAD" | "FORWARD" | "INVERSE" => {
            return Err(m.err(format!("{name} is not supported by krlkit run")));
        }
        // #DECLARED while any part was never assigned (a CHAR array counts as assigned).
        // Names are bound at load, so the name must be written there: a literal.
        "VARSTATE" => {
            let Some(Some(Expr {
                kind: ExprKind::Str(literal),
                span,
            })) = args.first()
            else {
                return Err(m.err(
                    "VARSTATE needs the variable's name as a literal string (krlkit binds \
                     names when the program is loaded, not while it runs)",
                ));
            };
            Value::Enum(match m.variable_assigned(*span, literal.trim()) {
                Some(true) => "INITIALIZED".into(),
                Some(false) => "DECLARED".into(),
                None => "UNKNOWN".into(),
            })
        }
        _ => return m.form_function(&up, args),
    };
    Ok(Some(v))
}

fn char_len(m: &mut Machine, p: &super::machine::Place) -> R<usize> {
    match m.read_value(p)? {
        Value::Array { items, .. } if matches!(items.first(), Some(Value::Char(_))) => {
            Ok(items.len())
        }
        v => Err(m.err(format!("expected a CHAR array, found {}", v.kind_name()))),
    }
}

fn set_state(
    m: &mut Machine,
    p: &super::machine::Place,
    ok: bool,
    hits: usize,
    length: usize,
) -> R<()> {
    let ret = if ok { "CMD_OK" } else { "CMD_ABORT" };
    m.assign(
        p,
        Value::Partial(vec![
            ("RET1".into(), Value::Enum(ret.into())),
            ("HITS".into(), Value::Int(hits as i64)),
            ("LENGTH".into(), Value::Int(length as i64)),
        ]),
    )
}

/// SWRITE(buffer[], state, offset, format, values…): write formatted text at `offset`.
fn swrite(m: &mut Machine, args: &[Option<Expr>]) -> R<Value> {
    let buf = m.arg_place(args, 0, "SWRITE")?;
    let state = m.arg_place(args, 1, "SWRITE")?;
    let off_p = m.arg_place(args, 2, "SWRITE")?;
    let fmt = m
        .arg_value(args, 3, "SWRITE")?
        .as_text()
        .ok_or_else(|| m.err("SWRITE: the format must be a string"))?;
    let pieces = parse_format(&fmt).map_err(|e| m.err(format!("SWRITE: {e}")))?;
    let mut out = String::new();
    let mut next = 4;
    let mut hits = 0;
    for p in &pieces {
        match p {
            Piece::Lit(l) => out.push_str(l),
            conv => {
                let v = m.arg_value(args, next, "SWRITE")?;
                next += 1;
                out.push_str(&format_one(conv, &v).map_err(|e| m.err(format!("SWRITE: {e}")))?);
                hits += 1;
            }
        }
    }
    let offset = match m.read_value(&off_p)? {
        Value::Int(i) if i >= 0 => i as usize,
        v => return Err(m.err(format!("SWRITE: bad offset {v:?}"))),
    };
    let (mut items, dims) = match m.read_value(&buf)? {
        Value::Array { items, dims } if matches!(items.first(), Some(Value::Char(_))) => {
            (items, dims)
        }
        v => {
            return Err(m.err(format!(
                "SWRITE: buffer must be a CHAR array, found {}",
                v.kind_name()
            )));
        }
    };
    let fits = offset + out.len() <= items.len();
    for (i, b) in out.bytes().enumerate() {
        if let Some(slot) = items.get_mut(offset + i) {
            *slot = Value::Char(b);
        }
    }
    let end = (offset + out.len()).min(items.len());
    if let Some(slot) = items.get_mut(end) {
        *slot = Value::Char(0);
    }
    m.assign(&buf, Value::Array { dims, items })?;
    m.assign(&off_p, Value::Int(end as i64))?;
    set_state(m, &state, fits, hits, end)?;
    Ok(Value::Bool(fits))
}

/// SREAD(buffer[], state, offset, format, vars…): scan from `offset` into the variables.
fn sread(m: &mut Machine, args: &[Option<Expr>]) -> R<Value> {
    let text = m
        .arg_value(args, 0, "SREAD")?
        .as_text()
        .ok_or_else(|| m.err("SREAD: the buffer must be a CHAR array"))?;
    let state = m.arg_place(args, 1, "SREAD")?;
    let off_p = m.arg_place(args, 2, "SREAD")?;
    let fmt = m
        .arg_value(args, 3, "SREAD")?
        .as_text()
        .ok_or_else(|| m.err("SREAD: the format must be a string"))?;
    let pieces = parse_format(&fmt).map_err(|e| m.err(format!("SREAD: {e}")))?;
    let wanted = pieces
        .iter()
        .filter(|p| !matches!(p, Piece::Lit(_)))
        .count();
    let offset = match m.read_value(&off_p)? {
        Value::Int(i) if i >= 0 => i as usize,
        v => return Err(m.err(format!("SREAD: bad offset {v:?}"))),
    };
    let (vals, pos) = scan(text.as_bytes(), offset.min(text.len()), &pieces);
    let hits = vals.len();
    for (i, s) in vals.into_iter().enumerate() {
        let p = m.arg_place(args, 4 + i, "SREAD")?;
        let v = match s {
            Scanned::Int(i) => Value::Int(i),
            Scanned::Real(r) => Value::Real(r),
            Scanned::Char(c) => Value::Char(c),
            // A %s field fills the target as far as it goes.
            Scanned::Text(t) => match char_len(m, &p) {
                Ok(len) => Value::char_array(t.as_bytes(), len),
                Err(_) => Value::Str(t),
            },
        };
        m.assign(&p, v)?;
    }
    m.assign(&off_p, Value::Int(pos as i64))?;
    set_state(m, &state, hits == wanted, hits, pos)?;
    Ok(Value::Bool(hits == wanted))
}

/// The text of a KrlMsg_T (argument `msg`) with `%1`..`%3` replaced by the KrlMsgPar_T array
/// (argument `par`): a text parameter, else a non-zero REAL, else the INT; #EMPTY is blank.
fn krl_msg_text(
    m: &mut Machine,
    args: &[Option<Expr>],
    msg: usize,
    par: usize,
    name: &str,
) -> R<String> {
    let msg = m.arg_value(args, msg, name)?;
    let mut t = msg
        .field("MSG_TXT")
        .and_then(|v| v.as_text())
        .ok_or_else(|| m.err(format!("{name}: the message must be a KrlMsg_T")))?;
    if let Some(Ok(Value::Array { items, .. })) = args
        .get(par)
        .and_then(|a| a.as_ref())
        .map(|_| m.arg_value(args, par, name))
    {
        for (i, p) in items.iter().enumerate() {
            let empty = matches!(p.field("PAR_TYPE"), Some(Value::Enum(e)) if e == "EMPTY");
            let txt = p
                .field("PAR_TXT")
                .and_then(|v| v.as_text())
                .unwrap_or_default();
            let val = if empty {
                String::new()
            } else if !txt.trim().is_empty() {
                txt
            } else {
                match (p.field("PAR_REAL"), p.field("PAR_INT")) {
                    (Some(Value::Real(r)), _) if *r != 0.0 => r.to_string(),
                    (_, Some(Value::Int(n))) => n.to_string(),
                    _ => String::new(),
                }
            };
            t = t.replace(&format!("%{}", i + 1), &val);
        }
    }
    Ok(t)
}

/// Message handles count up from 1, like the controller's (0 and below mean failure).
fn next_handle(m: &mut Machine) -> Value {
    Value::Int(m.next_message_handle())
}
