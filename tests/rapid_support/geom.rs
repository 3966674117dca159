//! Frames for the RAPID interpreter, written from the quaternion definition (q1 = w, q2..q4 =
//! x, y, z) and not with krlkit's `geom`: a convention error in the translator's quaternions must
//! show as a different rotation matrix, not cancel out.

pub type Mat = [[f64; 3]; 3];

/// How far |q| may be from 1 before a controller refuses the orientation (an assumption: the
/// translator prints 7 decimals, so its quaternions are off by ~1e-7).
const UNIT: f64 = 1e-5;

pub fn quat_to_matrix(q: [f64; 4]) -> Result<Mat, String> {
    let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > UNIT {
        return Err(format!(
            "the orientation {q:?} is not normalised (|q| = {norm})"
        ));
    }
    let [w, x, y, z] = q.map(|v| v / norm);
    Ok([
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ])
}

/// Shepperd's method: branch on the largest diagonal term, so rotations near 180° stay exact.
pub fn matrix_to_quat(m: &Mat) -> [f64; 4] {
    let t = m[0][0] + m[1][1] + m[2][2];
    let q = if t >= m[0][0] && t >= m[1][1] && t >= m[2][2] {
        let s = (1.0 + t).sqrt() * 2.0;
        [
            s / 4.0,
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
        ]
    } else if m[0][0] >= m[1][1] && m[0][0] >= m[2][2] {
        let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
        [
            (m[2][1] - m[1][2]) / s,
            s / 4.0,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
        ]
    } else if m[1][1] >= m[2][2] {
        let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
        [
            (m[0][2] - m[2][0]) / s,
            (m[0][1] + m[1][0]) / s,
            s / 4.0,
            (m[1][2] + m[2][1]) / s,
        ]
    } else {
        let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
        [
            (m[1][0] - m[0][1]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            s / 4.0,
        ]
    };
    if q[0] < 0.0 { q.map(|v| -v) } else { q }
}

pub fn mul(a: &Mat, b: &Mat) -> Mat {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

pub fn apply(m: &Mat, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (0..3).map(|k| m[i][k] * v[k]).sum())
}

fn transpose(m: &Mat) -> Mat {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[j][i]))
}

/// A rotation of `deg` degrees about axis 0 (x), 1 (y) or 2 (z).
pub fn rot(axis: usize, deg: f64) -> Mat {
    let (s, c) = deg.to_radians().sin_cos();
    match axis {
        0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

/// `OrientZYX(a, b, c)`: Rz(a)·Ry(b)·Rx(c).
pub fn zyx(a: f64, b: f64, c: f64) -> Mat {
    mul(&mul(&rot(2, a), &rot(1, b)), &rot(0, c))
}

/// `EulerZYX`: the angles (z, y, x) of a rotation in degrees.
pub fn euler_zyx(m: &Mat) -> [f64; 3] {
    let y = (-m[2][0]).atan2((m[0][0] * m[0][0] + m[1][0] * m[1][0]).sqrt());
    let z = m[1][0].atan2(m[0][0]);
    let x = m[2][1].atan2(m[2][2]);
    [z, y, x].map(f64::to_degrees)
}

/// A frame: position (mm) and rotation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub p: [f64; 3],
    pub r: Mat,
}

impl Frame {
    pub const IDENTITY: Frame = Frame {
        p: [0.0; 3],
        r: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// `self` · `other`: `other` expressed in `self`.
    pub fn compose(&self, other: &Frame) -> Frame {
        let d = apply(&self.r, other.p);
        Frame {
            p: [0, 1, 2].map(|i| self.p[i] + d[i]),
            r: mul(&self.r, &other.r),
        }
    }

    pub fn inverse(&self) -> Frame {
        let r = transpose(&self.r);
        let p = apply(&r, self.p).map(|v| -v);
        Frame { p, r }
    }
}
