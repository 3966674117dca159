//! What the Flexiv backend needs to know that the KRL program does not say: the RDK version
//! (its Python API shape), the robot's serial number, the I/O port map, whether a joint map
//! from KUKA's six axes to the Rizon's seven joints exists, which primitive a Cartesian PTP
//! becomes, and the Mech-Mind client's settings from the spec.

use std::fmt;
use std::str::FromStr;

pub use crate::transpile::joints::{JointMap, JointSource};

/// The Flexiv RDK release the script is written for. Supported: 1.6 (the seed's API) up to
/// 1.9; 2.x (joint groups) has a different `ExecutePrimitive`/`primitive_states` shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct RdkVersion {
    pub major: u32,
    pub minor: u32,
}

/// The Python API shapes that differ between the supported releases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Api {
    /// 1.6: `SetDigitalOutputs(port_list, value_list)`, `JPos.q`.
    V16,
    /// 1.7 to 1.9: `SetDigitalOutputs({port: value})`, `JPos.q_m`.
    V17,
}

impl RdkVersion {
    pub const DEFAULT: RdkVersion = RdkVersion { major: 1, minor: 6 };

    pub fn api(self) -> Api {
        if self.minor >= 7 { Api::V17 } else { Api::V16 }
    }
}

impl Default for RdkVersion {
    fn default() -> RdkVersion {
        RdkVersion::DEFAULT
    }
}

impl fmt::Display for RdkVersion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.major, self.minor)
    }
}

impl FromStr for RdkVersion {
    type Err = String;

    /// `1.6`, `1.7.1`, `v1.8` …
    fn from_str(s: &str) -> Result<RdkVersion, String> {
        let t = s.trim().trim_start_matches(['v', 'V']);
        let mut parts = t.split('.');
        let num = |p: Option<&str>| p.and_then(|p| p.parse::<u32>().ok());
        let (Some(major), Some(minor)) = (num(parts.next()), num(parts.next())) else {
            return Err(format!(
                "`{s}` is not an RDK version; write it as MAJOR.MINOR, e.g. 1.6"
            ));
        };
        if parts.any(|p| p.parse::<u32>().is_err()) {
            return Err(format!(
                "`{s}` is not an RDK version; write it as MAJOR.MINOR, e.g. 1.6"
            ));
        }
        let v = RdkVersion { major, minor };
        if major == 2 {
            return Err(format!(
                "RDK {v} is not supported: 2.x drives joint groups (ExecutePrimitive per group, PrimitiveStates objects); use --rdk 1.6 to 1.9"
            ));
        }
        if major != 1 || !(6..=9).contains(&minor) {
            return Err(format!(
                "RDK {v} is not supported: the translation writes the Python API of RDK 1.6 to 1.9 (flexivrdk on PyPI starts at 1.6)"
            ));
        }
        Ok(v)
    }
}

/// What a Cartesian `PTP` becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PtpPrimitive {
    /// `MoveL` with a TR002 (the path is a straight line, not joint-interpolated).
    #[default]
    MoveL,
    /// `MovePTP`, which the user confirms exists on the robot's software (unverified).
    MovePtp,
}

/// The joint map for a Rizon's seven joints, e.g. `A1,A2,0,A3,A4,A5,A6`.
pub fn joint_map(s: &str) -> Result<JointMap, String> {
    JointMap::parse(s, 7, "Rizon", "A1,A2,0,A3,A4,A5,A6")
}

/// Options of the Flexiv backend.
#[derive(Debug, Clone)]
pub struct FlexivOptions {
    pub rdk: RdkVersion,
    /// The robot's serial number; `None`: the script reads it from its argument or
    /// `FLEXIV_ROBOT_SN`.
    pub serial: Option<String>,
    /// `$IN[n]` → digital input port `n + input_offset` (Flexiv ports are 0-based).
    pub input_offset: i64,
    /// `$OUT[n]` → digital output port `n + output_offset`.
    pub output_offset: i64,
    pub ptp: PtpPrimitive,
    pub joint_map: Option<JointMap>,
    /// Mech-Mind client: seconds to wait for a reply (spec `reply_timeout`).
    pub reply_timeout: u32,
    /// Mech-Mind client: most points one reply may carry (spec `batch_size`).
    pub batch_size: u32,
}

impl Default for FlexivOptions {
    fn default() -> FlexivOptions {
        let spec = crate::spec::Spec::default();
        FlexivOptions {
            rdk: RdkVersion::DEFAULT,
            serial: None,
            input_offset: -1,
            output_offset: -1,
            ptp: PtpPrimitive::MoveL,
            joint_map: None,
            reply_timeout: spec.reply_timeout,
            batch_size: spec.batch_size,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions() {
        assert_eq!("1.6".parse::<RdkVersion>().unwrap().api(), Api::V16);
        assert_eq!("1.7.1".parse::<RdkVersion>().unwrap().api(), Api::V17);
        assert_eq!("v1.9".parse::<RdkVersion>().unwrap().to_string(), "1.9");
        assert!(
            "2.0"
                .parse::<RdkVersion>()
                .unwrap_err()
                .contains("joint groups")
        );
        assert!("1.5".parse::<RdkVersion>().is_err());
        assert!("one".parse::<RdkVersion>().is_err());
        assert!("1.6.x".parse::<RdkVersion>().is_err());
    }
}
