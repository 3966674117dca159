//! Euler-angle conventions of the robot brands, and exact conversion between them.
//!
//! KUKA `A, B, C` is intrinsic Z-Y'-X'' (R = Rz(A)·Ry(B)·Rx(C), B in [-90°, 90°]); Kawasaki
//! `O, A, T` is intrinsic Z-Y'-Z'' (R = Rz(O)·Ry(A)·Rz(T), A in [0°, 180°]). Positions are mm on
//! both sides. Conversions go through the rotation matrix; at the gimbal-lock poses only a sum or
//! difference of two angles is defined, and we fix the free angle (documented per function) so
//! output is deterministic. Equal orientations must therefore be compared as matrices, never as
//! angle triples.

/// A 3×3 rotation matrix, row-major.
pub type Matrix = [[f64; 3]; 3];

/// Below this, `sin` of the middle angle counts as zero (gimbal lock).
const EPS: f64 = 1e-12;

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

pub fn mul(a: &Matrix, b: &Matrix) -> Matrix {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
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

/// Rotation matrix → Kawasaki O, A, T (degrees), A in [0, 180].
///
/// At A = 0 only O + T is defined: T is set to 0. At A = 180 only O − T is defined: T is set
/// to 180.
pub fn matrix_to_oat(r: &Matrix) -> (f64, f64, f64) {
    let sa = r[0][2].hypot(r[1][2]);
    let a = sa.atan2(r[2][2]).to_degrees();
    if sa > EPS {
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

/// Rotation matrix → KUKA A, B, C (degrees), B in [-90, 90].
///
/// At B = ±90 only A ∓ C is defined: A is set to 0.
pub fn matrix_to_abc(r: &Matrix) -> (f64, f64, f64) {
    let cb = r[0][0].hypot(r[1][0]);
    let b = (-r[2][0]).atan2(cb).to_degrees();
    if cb > EPS {
        let a = r[1][0].atan2(r[0][0]).to_degrees();
        let c = r[2][1].atan2(r[2][2]).to_degrees();
        (norm(a), b, norm(c))
    } else if r[2][0] < 0.0 {
        (0.0, 90.0, norm(r[0][1].atan2(r[1][1]).to_degrees()))
    } else {
        (0.0, -90.0, norm((-r[0][1]).atan2(r[1][1]).to_degrees()))
    }
}

/// KUKA A, B, C → Kawasaki O, A, T (degrees).
pub fn abc_to_oat(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    matrix_to_oat(&abc_to_matrix(a, b, c))
}

/// Kawasaki O, A, T → KUKA A, B, C (degrees).
pub fn oat_to_abc(o: f64, a: f64, t: f64) -> (f64, f64, f64) {
    matrix_to_abc(&oat_to_matrix(o, a, t))
}

/// Maps an angle into (-180, 180], and rounds away float dust so `-0` and `180 - 1e-14` print
/// cleanly.
fn norm(deg: f64) -> f64 {
    let mut d = deg % 360.0;
    if d <= -180.0 {
        d += 360.0;
    } else if d > 180.0 {
        d -= 360.0;
    }
    let r = (d * 1e9).round() / 1e9;
    if r == -180.0 {
        180.0
    } else if r == 0.0 {
        0.0
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: (f64, f64, f64), b: (f64, f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9 && (a.2 - b.2).abs() < 1e-9
    }

    #[test]
    fn reference_vectors() {
        // KUKA -> Kawasaki pairs from the reference (§1.9), with our tie-break rules.
        let cases = [
            ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
            ((0.0, 0.0, 180.0), (0.0, 180.0, 180.0)),
            ((30.0, 0.0, 180.0), (30.0, 180.0, 180.0)),
            ((90.0, 90.0, 0.0), (90.0, 90.0, 0.0)),
            ((10.0, -90.0, 20.0), (-150.0, 90.0, 180.0)),
        ];
        for (abc, oat) in cases {
            let got = abc_to_oat(abc.0, abc.1, abc.2);
            assert!(close(got, oat), "{abc:?} -> {got:?}, want {oat:?}");
            let m1 = abc_to_matrix(abc.0, abc.1, abc.2);
            let m2 = oat_to_matrix(got.0, got.1, got.2);
            assert!(max_diff(&m1, &m2) < 1e-9);
        }
    }

    /// A random angle, with a good share of the values that cause gimbal lock.
    fn angle() -> impl Strategy<Value = f64> {
        prop_oneof![
            3 => -180.0f64..=180.0,
            1 => prop::sample::select(vec![-180.0, -90.0, 0.0, 90.0, 180.0]),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(10_000))]

        #[test]
        fn kuka_to_kawasaki_keeps_the_rotation(a in angle(), b in -90.0f64..=90.0, c in angle(),
                                               lock in prop::sample::select(vec![None, Some(90.0), Some(-90.0)])) {
            let b = lock.unwrap_or(b);
            let (o, aa, t) = abc_to_oat(a, b, c);
            prop_assert!((0.0..=180.0).contains(&aa));
            let err = max_diff(&abc_to_matrix(a, b, c), &oat_to_matrix(o, aa, t));
            prop_assert!(err < 1e-9, "abc ({a}, {b}, {c}) -> oat ({o}, {aa}, {t}): {err}");
        }

        #[test]
        fn kawasaki_to_kuka_keeps_the_rotation(o in angle(), a in 0.0f64..=180.0, t in angle(),
                                               lock in prop::sample::select(vec![None, Some(0.0), Some(180.0)])) {
            let a = lock.unwrap_or(a);
            let (ka, kb, kc) = oat_to_abc(o, a, t);
            prop_assert!((-90.0..=90.0).contains(&kb));
            let err = max_diff(&oat_to_matrix(o, a, t), &abc_to_matrix(ka, kb, kc));
            prop_assert!(err < 1e-9, "oat ({o}, {a}, {t}) -> abc ({ka}, {kb}, {kc}): {err}");
        }
    }
}
