//! Reading a `krlkit run --trace` file (JSON Lines, format in README) back into typed records.
//! Unknown event kinds and unknown keys are skipped, so traces of later versions still load.

use serde_json::Value as J;

/// A pose `X,Y,Z,A,B,C` (mm, degrees).
pub type Pose = [f64; 6];

#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    Cartesian(Pose),
    /// `A1…A6` (degrees).
    Axis([f64; 6]),
}

#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    Source {
        file: String,
        text: String,
    },
    Motion {
        kind: String,
        target: Target,
        aux: Option<[f64; 3]>,
    },
    Call {
        name: String,
    },
    Return {
        name: String,
        out: serde_json::Map<String, J>,
        status: Option<i64>,
    },
    Message {
        text: String,
    },
    Io {
        signal: String,
        index: u64,
        value: bool,
    },
    Wait {
        kind: String,
        ms: f64,
    },
    /// The poses the vision server sent, as the package stored them after `routine`.
    Vision {
        routine: String,
        poses: Vec<(Pose, Option<i64>)>,
    },
    Srci {
        word: u32,
    },
    Coverage {
        file: String,
        lines: Vec<(usize, u64)>,
    },
    End {
        status: String,
        message: Option<String>,
        time_ms: f64,
    },
}

/// One trace line.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub t: f64,
    pub file: Option<String>,
    pub line: Option<usize>,
    pub kind: Kind,
}

#[derive(Debug, thiserror::Error, PartialEq)]
#[error("line {line}: {message}")]
pub struct TraceError {
    pub line: usize,
    pub message: String,
}

const CART: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
const AXES: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];

fn num(v: &J, key: &str) -> Option<f64> {
    v.get(key).and_then(J::as_f64)
}

fn string(v: &J, key: &str) -> Option<String> {
    v.get(key).and_then(J::as_str).map(str::to_string)
}

fn six(obj: &J, keys: [&str; 6]) -> Option<[f64; 6]> {
    let mut out = [0.0; 6];
    for (slot, k) in out.iter_mut().zip(keys) {
        *slot = obj.get(k)?.as_f64()?;
    }
    Some(out)
}

/// A Cartesian pose in a JSON object (`{"X":…,…,"C":…}`, other keys allowed).
pub fn pose_of(v: &J) -> Option<Pose> {
    six(v, CART)
}

fn kind_of(v: &J) -> Result<Option<Kind>, String> {
    let need = |k: &str| format!("`{k}` is missing or has the wrong type");
    let event = v
        .get("event")
        .and_then(J::as_str)
        .ok_or_else(|| need("event"))?;
    Ok(Some(match event {
        "source" => Kind::Source {
            file: string(v, "file").ok_or_else(|| need("file"))?,
            text: string(v, "text").ok_or_else(|| need("text"))?,
        },
        "motion" => {
            let t = v.get("target").ok_or_else(|| need("target"))?;
            let target = match (six(t, CART), six(t, AXES)) {
                (Some(p), _) => Target::Cartesian(p),
                (None, Some(a)) => Target::Axis(a),
                _ => return Err(need("target")),
            };
            let aux = v
                .get("aux")
                .and_then(|a| Some([num(a, "X")?, num(a, "Y")?, num(a, "Z")?]));
            Kind::Motion {
                kind: string(v, "kind").ok_or_else(|| need("kind"))?,
                target,
                aux,
            }
        }
        "call" => Kind::Call {
            name: string(v, "name").ok_or_else(|| need("name"))?,
        },
        "return" => Kind::Return {
            name: string(v, "name").ok_or_else(|| need("name"))?,
            out: v
                .get("out")
                .and_then(J::as_object)
                .cloned()
                .unwrap_or_default(),
            status: v.get("status").and_then(J::as_i64),
        },
        "message" => Kind::Message {
            text: string(v, "text").ok_or_else(|| need("text"))?,
        },
        "io" => Kind::Io {
            signal: string(v, "signal").ok_or_else(|| need("signal"))?,
            index: v
                .get("index")
                .and_then(J::as_u64)
                .ok_or_else(|| need("index"))?,
            value: v
                .get("value")
                .and_then(J::as_bool)
                .ok_or_else(|| need("value"))?,
        },
        "wait" => Kind::Wait {
            kind: string(v, "kind").ok_or_else(|| need("kind"))?,
            ms: num(v, "ms").ok_or_else(|| need("ms"))?,
        },
        "vision" => Kind::Vision {
            routine: string(v, "routine").ok_or_else(|| need("routine"))?,
            poses: v
                .get("poses")
                .and_then(J::as_array)
                .ok_or_else(|| need("poses"))?
                .iter()
                .map(|p| Some((pose_of(p)?, p.get("label").and_then(J::as_i64))))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| need("poses"))?,
        },
        "srci" => Kind::Srci {
            word: v
                .get("word")
                .and_then(J::as_u64)
                .and_then(|w| u32::try_from(w).ok())
                .ok_or_else(|| need("word"))?,
        },
        "coverage" => Kind::Coverage {
            file: string(v, "file").ok_or_else(|| need("file"))?,
            lines: v
                .get("lines")
                .and_then(J::as_array)
                .ok_or_else(|| need("lines"))?
                .iter()
                .map(|pair| {
                    let line = pair.get(0)?.as_u64()? as usize;
                    Some((line, pair.get(1)?.as_u64()?))
                })
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| need("lines"))?,
        },
        "end" => Kind::End {
            status: string(v, "status").ok_or_else(|| need("status"))?,
            message: string(v, "message"),
            time_ms: num(v, "time_ms").unwrap_or(0.0),
        },
        _ => return Ok(None),
    }))
}

/// Parse a whole trace. Blank lines are skipped; a line that is not a JSON object, or an event
/// missing a key it needs, is an error naming the line.
pub fn parse(text: &str) -> Result<Vec<Entry>, TraceError> {
    let mut entries = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let err = |message: String| TraceError {
            line: i + 1,
            message,
        };
        let v: J =
            serde_json::from_str(line).map_err(|e| err(format!("not a JSON object: {e}")))?;
        if !v.is_object() {
            return Err(err("not a JSON object".into()));
        }
        let Some(kind) = kind_of(&v).map_err(err)? else {
            continue;
        };
        entries.push(Entry {
            t: num(&v, "t").unwrap_or(0.0),
            file: string(&v, "file"),
            line: v.get("line").and_then(J::as_u64).map(|l| l as usize),
            kind,
        });
    }
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_kind_and_skips_unknown_ones() {
        let text = r#"{"event":"source","file":"a.src","t":0,"text":"DEF a()\nEND\n"}
{"event":"motion","kind":"LIN","t":1.5,"file":"a.src","line":2,"target":{"X":1,"Y":2,"Z":3,"A":4,"B":5,"C":6}}
{"aux":{"X":1,"Y":1,"Z":0},"event":"motion","kind":"CIRC","t":2,"target":{"X":1,"Y":2,"Z":3,"A":4,"B":5,"C":6}}
{"event":"motion","kind":"PTP","t":2,"target":{"A1":0,"A2":-90,"A3":90,"A4":0,"A5":0,"A6":0}}

{"event":"future_kind","t":3}
{"event":"io","signal":"$OUT","index":5,"value":true,"t":3}
{"event":"vision","routine":"MM_Get_VisData","t":3,"poses":[{"X":1,"Y":2,"Z":3,"A":4,"B":5,"C":6,"label":7},{"X":1,"Y":2,"Z":3,"A":4,"B":5,"C":6}]}
{"event":"end","status":"ok","message":null,"steps":3,"time_ms":3,"t":3}
"#;
        let e = parse(text).unwrap();
        assert_eq!(e.len(), 7);
        assert_eq!(e[1].t, 1.5);
        assert_eq!(e[1].line, Some(2));
        assert!(matches!(
            &e[2].kind,
            Kind::Motion {
                aux: Some([1.0, 1.0, 0.0]),
                ..
            }
        ));
        assert!(matches!(
            &e[3].kind,
            Kind::Motion {
                target: Target::Axis(_),
                ..
            }
        ));
        assert!(matches!(&e[5].kind, Kind::Vision { poses, .. }
            if poses == &vec![([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], Some(7)), ([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], None)]));
        assert!(matches!(&e[6].kind, Kind::End { message: None, .. }));
    }

    #[test]
    fn bad_lines_are_named() {
        assert_eq!(
            parse("{\"event\":\"end\",\"status\":\"ok\"}\nnot json\n")
                .unwrap_err()
                .line,
            2
        );
        let e = parse("{\"event\":\"motion\",\"kind\":\"LIN\"}").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 1: `target` is missing or has the wrong type"
        );
    }
}
