//! The geometric operator `:` and INV_POS on KUKA frames (A about Z, B about Y, C about X, degrees).

use super::value::{CART_FIELDS, Value};

type M = [[f64; 4]; 4];

fn get(v: &Value) -> Option<[f64; 6]> {
    let mut out = [0.0; 6];
    for (i, n) in CART_FIELDS.iter().enumerate() {
        out[i] = v.field(n).and_then(|x| x.as_f64()).unwrap_or(0.0);
    }
    matches!(v, Value::Struc { .. } | Value::Partial(_)).then_some(out)
}

fn matrix(f: [f64; 6]) -> M {
    let (a, b, c) = (f[3].to_radians(), f[4].to_radians(), f[5].to_radians());
    let (sa, ca, sb, cb, sc, cc) = (a.sin(), a.cos(), b.sin(), b.cos(), c.sin(), c.cos());
    [
        [
            ca * cb,
            ca * sb * sc - sa * cc,
            ca * sb * cc + sa * sc,
            f[0],
        ],
        [
            sa * cb,
            sa * sb * sc + ca * cc,
            sa * sb * cc - ca * sc,
            f[1],
        ],
        [-sb, cb * sc, cb * cc, f[2]],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

fn frame(m: &M) -> [f64; 6] {
    let b = (-m[2][0]).atan2((m[0][0] * m[0][0] + m[1][0] * m[1][0]).sqrt());
    let (a, c) = if b.cos().abs() < 1e-9 {
        // Gimbal lock: put the whole rotation into A.
        ((-m[0][1]).atan2(m[1][1]), 0.0)
    } else {
        (m[1][0].atan2(m[0][0]), m[2][1].atan2(m[2][2]))
    };
    [
        m[0][3],
        m[1][3],
        m[2][3],
        a.to_degrees(),
        b.to_degrees(),
        c.to_degrees(),
    ]
}

fn mul(x: &M, y: &M) -> M {
    let mut r = [[0.0; 4]; 4];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..4).map(|k| x[i][k] * y[k][j]).sum();
        }
    }
    r
}

fn with_frame(template: &Value, f: [f64; 6]) -> Value {
    let mut out = template.clone();
    for (i, n) in CART_FIELDS.iter().enumerate() {
        if let Some(slot) = out.field_mut(n) {
            *slot = Value::Real(f[i]);
        }
    }
    out
}

/// `a : b` — the pose `b` expressed through frame `a`; the result has `b`'s type.
pub fn compose(a: &Value, b: &Value) -> Option<Value> {
    let r = frame(&mul(&matrix(get(a)?), &matrix(get(b)?)));
    Some(with_frame(b, r))
}

/// INV_POS: the inverse frame.
#[allow(clippy::needless_range_loop)]
pub fn inverse(a: &Value) -> Option<Value> {
    let m = matrix(get(a)?);
    let mut inv = [[0.0; 4]; 4];
    for i in 0..3 {
        for j in 0..3 {
            inv[i][j] = m[j][i];
        }
    }
    for i in 0..3 {
        inv[i][3] = -(0..3).map(|k| inv[i][k] * m[k][3]).sum::<f64>();
    }
    inv[3][3] = 1.0;
    Some(with_frame(a, frame(&inv)))
}
