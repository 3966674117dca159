//! The joint map: how KUKA's axis values become another robot's joint values. Makers differ in
//! joint zeros, directions and count, so the same six numbers are another posture elsewhere;
//! a target never copies axis values written in the program without this map (`--joint-map`).
//!
//! Each target joint is a KUKA axis, optionally negated and shifted (`A1`, `-A3`, `A2+90`,
//! `-A5-180`), or a fixed angle in degrees (`0`).

use std::fmt;

/// Where one target joint's value comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointSource {
    /// `sign * A<axis> + offset` (axis 1-based, sign ±1, offset in degrees).
    Axis { axis: u8, negate: bool, offset: f64 },
    /// A fixed angle in degrees.
    Fixed(f64),
}

impl JointSource {
    /// The plain axis `A<axis>`.
    pub fn axis(axis: u8) -> JointSource {
        JointSource::Axis {
            axis,
            negate: false,
            offset: 0.0,
        }
    }

    /// This joint's value for KUKA axis values `a` (A1…A6).
    pub fn value(&self, a: &[f64; 6]) -> f64 {
        match *self {
            JointSource::Axis {
                axis,
                negate,
                offset,
            } => {
                let v = a[usize::from(axis) - 1];
                if negate { offset - v } else { v + offset }
            }
            JointSource::Fixed(v) => v,
        }
    }
}

/// KUKA's six axes → the target's joints, one source per joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMap(pub Vec<JointSource>);

impl JointMap {
    /// Reads `A1,-A2+90,…` for a robot with `joints` joints (`robot` names it in errors).
    pub fn parse(s: &str, joints: usize, robot: &str, example: &str) -> Result<JointMap, String> {
        let items: Vec<&str> = s.split(',').map(str::trim).collect();
        if items.len() != joints {
            return Err(format!(
                "the joint map needs {joints} entries (one per {robot} joint), `{s}` has {}; e.g. {example}",
                items.len()
            ));
        }
        let mut out = Vec::with_capacity(joints);
        for (i, it) in items.iter().enumerate() {
            out.push(source(it).ok_or_else(|| {
                format!(
                    "joint {} of the map: `{it}` is neither A1..A6 (optionally negated and shifted, e.g. -A3+90) nor a number of degrees",
                    i + 1
                )
            })?);
        }
        Ok(JointMap(out))
    }

    /// The joint (0-based) that carries KUKA axis `axis` (1-based), if exactly one does.
    pub fn joint_of(&self, axis: u8) -> Option<(usize, JointSource)> {
        let mut it = self
            .0
            .iter()
            .enumerate()
            .filter(|(_, s)| matches!(s, JointSource::Axis { axis: a, .. } if *a == axis));
        let (i, s) = it.next()?;
        it.next().is_none().then_some((i, *s))
    }

    /// Every KUKA axis is carried by exactly one joint, so joints can be read back as axes.
    pub fn invertible(&self) -> bool {
        (1..=6).all(|a| self.joint_of(a).is_some())
    }

    /// The joint values for KUKA axis values `a`.
    pub fn apply(&self, a: &[f64; 6]) -> Vec<f64> {
        self.0.iter().map(|s| s.value(a)).collect()
    }
}

/// One entry: a number, or `[-]A<n>[(+|-)<number>]`.
fn source(it: &str) -> Option<JointSource> {
    if let Ok(v) = it.parse::<f64>() {
        return v.is_finite().then_some(JointSource::Fixed(v));
    }
    let upper = it.to_ascii_uppercase().replace(' ', "");
    let (negate, rest) = match upper.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, upper.strip_prefix('+').unwrap_or(&upper)),
    };
    let rest = rest.strip_prefix('A')?;
    let digits = rest.chars().take_while(char::is_ascii_digit).count();
    let axis: u8 = rest[..digits].parse().ok()?;
    if !(1..=6).contains(&axis) {
        return None;
    }
    let tail = &rest[digits..];
    let offset = if tail.is_empty() {
        0.0
    } else {
        if !tail.starts_with(['+', '-']) {
            return None;
        }
        let v = tail.parse::<f64>().ok()?;
        if !v.is_finite() {
            return None;
        }
        v
    };
    Some(JointSource::Axis {
        axis,
        negate,
        offset,
    })
}

impl fmt::Display for JointSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            JointSource::Axis {
                axis,
                negate,
                offset,
            } => {
                let sign = if negate { "-" } else { "" };
                write!(f, "{sign}A{axis}")?;
                if offset != 0.0 {
                    let o = crate::transpile::front::literal::num(offset);
                    if offset > 0.0 {
                        write!(f, "+{o}")?;
                    } else {
                        write!(f, "{o}")?;
                    }
                }
                Ok(())
            }
            JointSource::Fixed(v) => f.write_str(&crate::transpile::front::literal::num(v)),
        }
    }
}

impl fmt::Display for JointMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.0.iter().map(ToString::to_string).collect();
        f.write_str(&parts.join(","))
    }
}

/// A relative axis move (`PTP_REL {A6 90}`) through `map`: per offset its target joint
/// (0-based), whether it turns the other way, and the KRL value; `robot` names the target arm
/// in the findings. External axes and an axis carried by no single joint are TR001.
pub fn relative_joints<'e>(
    map: &JointMap,
    d: &'e crate::transpile::ir::Delta,
    robot: &str,
) -> crate::transpile::front::R<Vec<(usize, bool, &'e crate::transpile::ir::Expr)>> {
    use crate::transpile::front::fail;
    let mut out = Vec::new();
    for (c, e) in &d.fields {
        let crate::transpile::ir::Component::Axis(i) = c else {
            return fail(
                d.span,
                format!("a relative axis move with external axes has no {robot} equivalent"),
                "move the external axis on its own",
            );
        };
        let Some((joint, source)) = map.joint_of(*i as u8 + 1) else {
            return fail(
                e.span,
                format!(
                    "the joint map {map} gives axis A{} no single {robot} joint",
                    i + 1
                ),
                "give a joint map in which the axis drives one joint",
            );
        };
        let negate = matches!(source, JointSource::Axis { negate: true, .. });
        out.push((joint, negate, e));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_read_and_apply() {
        let m = JointMap::parse("A1, -A2+90, a3-90, -A4, A5, A6", 6, "Kawasaki", "").unwrap();
        assert_eq!(m.to_string(), "A1,-A2+90,A3-90,-A4,A5,A6");
        assert_eq!(
            m.apply(&[10.0, -90.0, 90.0, 5.0, 45.0, 0.0]),
            vec![10.0, 180.0, 0.0, -5.0, 45.0, 0.0]
        );
        assert!(m.invertible());
        let r = JointMap::parse("A1,A2,0,A3,A4,A5,A6", 7, "Rizon", "").unwrap();
        assert_eq!(r.0[2], JointSource::Fixed(0.0));
        assert_eq!(r.joint_of(3).map(|(i, _)| i), Some(3));
        let partial = JointMap::parse("A1,A2,0,A3,A4,A5,-30.5", 7, "Rizon", "").unwrap();
        assert!(!partial.invertible());
        assert!(
            JointMap::parse("A1,A2", 7, "Rizon", "x")
                .unwrap_err()
                .contains("7 entries")
        );
        for bad in [
            "A1,A2,0,A3,A4,A5,A7",
            "A1,A2,x,A3,A4,A5,A6",
            "A1,A2,0,A3,A4,A5,A6*2",
        ] {
            assert!(JointMap::parse(bad, 7, "Rizon", "").is_err(), "{bad}");
        }
    }
}
