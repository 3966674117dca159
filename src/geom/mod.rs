//! Orientations and frames: the one home of the Euler-angle conventions, the rotation matrix,
//! the unit quaternion and the KUKA `:` composition. A leaf: it depends on no krlkit module.
//!
//! KUKA `A, B, C` is intrinsic Z-Y'-X'' (R = Rz(A)·Ry(B)·Rx(C), B in [-90°, 90°]); Kawasaki
//! `O, A, T` is intrinsic Z-Y'-Z'' (R = Rz(O)·Ry(A)·Rz(T), A in [0°, 180°]). Angles are degrees,
//! positions mm. At a gimbal-lock pose only a sum or difference of two angles is defined; the
//! free angle is fixed (see [`matrix_to_abc`], [`matrix_to_oat`]) so output is deterministic.
//! Equal orientations must therefore be compared as matrices or quaternions
//! ([`rotation_angle`]), never as angle triples.

#[cfg(test)]
mod tests;

/// A 3×3 rotation matrix, row-major; the tool's X, Y, Z axes are its columns.
pub type Matrix = [[f64; 3]; 3];

/// Below this, the cosine of KUKA's B (or the sine of Kawasaki's A) counts as zero: gimbal
/// lock. 1e-9 is far below a REAL's precision on the controller and far above float noise.
pub const GIMBAL_EPS: f64 = 1e-9;

fn rz(t: f64) -> Matrix {
    let (s, c) = t.to_radians().sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

fn ry(t: f64) -> Matrix {
    let (s, c) = t.to_radians().sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

fn rx(t: f64) -> Matrix {
    let (s, c) = t.to_radians().sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

/// The matrix product `a · b`.
pub fn mul(a: &Matrix, b: &Matrix) -> Matrix {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

/// The transpose, which is the inverse of a rotation.
pub fn transpose(r: &Matrix) -> Matrix {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| r[j][i]))
}

/// `r · v`.
pub fn apply(r: &Matrix, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (0..3).map(|k| r[i][k] * v[k]).sum())
}

/// Largest absolute element difference.
pub fn max_diff(a: &Matrix, b: &Matrix) -> f64 {
    let mut d: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            d = d.max((a[i][j] - b[i][j]).abs());
        }
    }
    d
}

/// KUKA A, B, C (degrees) → rotation matrix.
pub fn abc_to_matrix(a: f64, b: f64, c: f64) -> Matrix {
    mul(&mul(&rz(a), &ry(b)), &rx(c))
}

/// Kawasaki O, A, T (degrees) → rotation matrix.
pub fn oat_to_matrix(o: f64, a: f64, t: f64) -> Matrix {
    mul(&mul(&rz(o), &ry(a)), &rz(t))
}

/// Rotation matrix → KUKA A, B, C (degrees): A and C from `atan2`, so in [-180, 180]; B in
/// [-90, 90].
///
/// At B = ±90 (gimbal lock) only A ∓ C is defined: the whole rotation about Z goes into A and
/// C is 0. KUKA does not document what its controller reports there; this is our choice, and
/// it is the one the interpreter always made (ARCHITECTURE.md, invariants).
pub fn matrix_to_abc(r: &Matrix) -> (f64, f64, f64) {
    let cb = r[0][0].hypot(r[1][0]);
    let b = (-r[2][0]).atan2(cb).to_degrees();
    if cb < GIMBAL_EPS {
        ((-r[0][1]).atan2(r[1][1]).to_degrees(), b, 0.0)
    } else {
        let a = r[1][0].atan2(r[0][0]).to_degrees();
        let c = r[2][1].atan2(r[2][2]).to_degrees();
        (a, b, c)
    }
}

/// Rotation matrix → Kawasaki O, A, T (degrees), A in [0, 180].
///
/// At A = 0 only O + T is defined: T is set to 0. At A = 180 only O − T is defined: T is set
/// to 180.
pub fn matrix_to_oat(r: &Matrix) -> (f64, f64, f64) {
    let sa = r[0][2].hypot(r[1][2]);
    let a = sa.atan2(r[2][2]).to_degrees();
    if sa >= GIMBAL_EPS {
        let o = r[1][2].atan2(r[0][2]).to_degrees();
        let t = r[2][1].atan2(-r[2][0]).to_degrees();
        (norm(o), a, norm(t))
    } else if r[2][2] > 0.0 {
        (norm(r[1][0].atan2(r[0][0]).to_degrees()), 0.0, 0.0)
    } else {
        let phi = (-r[1][0]).atan2(-r[0][0]).to_degrees();
        (norm(phi + 180.0), 180.0, 180.0)
    }
}

/// KUKA A, B, C → Kawasaki O, A, T (degrees), printed clean ([`norm`]).
pub fn abc_to_oat(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    matrix_to_oat(&abc_to_matrix(a, b, c))
}

/// Kawasaki O, A, T → KUKA A, B, C (degrees), printed clean ([`norm`]).
pub fn oat_to_abc(o: f64, a: f64, t: f64) -> (f64, f64, f64) {
    let (a, b, c) = matrix_to_abc(&oat_to_matrix(o, a, t));
    (norm(a), round(b), norm(c))
}

/// Rounded to 1e-9 (far below a REAL's precision on the controller), so computed values do
/// not carry float noise (-165.00000000000003, "-0.0000") into output.
pub fn round(x: f64) -> f64 {
    let r = (x * 1e9).round() / 1e9;
    if r == 0.0 { 0.0 } else { r }
}

/// An angle mapped into (-180, 180] and [`round`]ed, so `-0` and `180 - 1e-14` print cleanly.
pub fn norm(deg: f64) -> f64 {
    let mut d = deg % 360.0;
    if d <= -180.0 {
        d += 360.0;
    } else if d > 180.0 {
        d -= 360.0;
    }
    let r = round(d);
    if r == -180.0 { 180.0 } else { r }
}

/// A unit quaternion `[w, x, y, z]` with `w >= 0` (ABB RAPID's `q1..q4` order).
pub type Quaternion = [f64; 4];

/// Rotation matrix → normalised quaternion, `w >= 0` (of the two equal quaternions, the one a
/// reader expects).
pub fn matrix_to_quaternion(r: &Matrix) -> Quaternion {
    let tr = r[0][0] + r[1][1] + r[2][2];
    // Shepperd: divide by the largest of the four candidates, never by a small number.
    let q = if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        [
            0.25 * s,
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
        ]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
        [
            (r[2][1] - r[1][2]) / s,
            0.25 * s,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
        ]
    } else if r[1][1] > r[2][2] {
        let s = (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt() * 2.0;
        [
            (r[0][2] - r[2][0]) / s,
            (r[0][1] + r[1][0]) / s,
            0.25 * s,
            (r[1][2] + r[2][1]) / s,
        ]
    } else {
        let s = (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt() * 2.0;
        [
            (r[1][0] - r[0][1]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            0.25 * s,
        ]
    };
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
    q.map(|x| sign * x / n)
}

/// Unit quaternion `[w, x, y, z]` → rotation matrix (normalised first).
pub fn quaternion_to_matrix(q: Quaternion) -> Matrix {
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [w, x, y, z] = q.map(|v| v / n);
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// The angle (degrees, in [0, 180]) of the rotation that turns orientation `a` into `b`: the
/// one measure of how far apart two orientations are, whatever their angle triples.
pub fn rotation_angle(a: &Matrix, b: &Matrix) -> f64 {
    let q = matrix_to_quaternion(&mul(&transpose(a), b));
    let v = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    (2.0 * v.atan2(q[0].abs())).to_degrees()
}

/// A frame: position (mm) and orientation. KUKA's `:` is [`Frame::compose`], INV_POS is
/// [`Frame::inverse`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub pos: [f64; 3],
    pub rot: Matrix,
}

impl Frame {
    /// From KUKA X, Y, Z, A, B, C.
    pub fn from_xyzabc(f: [f64; 6]) -> Frame {
        Frame {
            pos: [f[0], f[1], f[2]],
            rot: abc_to_matrix(f[3], f[4], f[5]),
        }
    }

    /// To KUKA X, Y, Z, A, B, C, each [`round`]ed; A and C stay in [-180, 180] as `atan2`
    /// gives them (a KRL REAL may hold -180).
    pub fn to_xyzabc(&self) -> [f64; 6] {
        let (a, b, c) = matrix_to_abc(&self.rot);
        [self.pos[0], self.pos[1], self.pos[2], a, b, c].map(round)
    }

    /// `self : other` — `other` expressed through `self`.
    pub fn compose(&self, other: &Frame) -> Frame {
        let p = apply(&self.rot, other.pos);
        Frame {
            pos: [0, 1, 2].map(|i| self.pos[i] + p[i]),
            rot: mul(&self.rot, &other.rot),
        }
    }

    /// The inverse frame (INV_POS): `f.inverse().compose(&f)` is the identity.
    pub fn inverse(&self) -> Frame {
        let rot = transpose(&self.rot);
        let p = apply(&rot, self.pos);
        Frame {
            pos: p.map(|x| -x),
            rot,
        }
    }
}
