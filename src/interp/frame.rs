//! The geometric operator `:`, INV_POS, relative and circular targets on KRL pose values; the
//! frame arithmetic itself is `crate::geom`'s.

use super::value::{CART_FIELDS, Value};
use crate::geom::{Frame, apply, round as clean};

fn get(v: &Value) -> Option<[f64; 6]> {
    let mut out = [0.0; 6];
    for (i, n) in CART_FIELDS.iter().enumerate() {
        out[i] = v.field(n).and_then(|x| x.as_f64()).unwrap_or(0.0);
    }
    matches!(v, Value::Struc { .. } | Value::Partial(_)).then_some(out)
}

fn frame_of(v: &Value) -> Option<Frame> {
    get(v).map(Frame::from_xyzabc)
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
    let r = frame_of(a)?.compose(&frame_of(b)?);
    Some(with_frame(b, r.to_xyzabc()))
}

/// The target of a Cartesian `LIN_REL`/`PTP_REL` from `cur` by `rel` (fields it lacks are 0).
/// In the base (`in_tool` false, KRL's default) the offset's X,Y,Z add to the position and its
/// rotation turns about the base axes; with `#TOOL` both are taken in the tool's own axes.
/// The angles are recomputed only when the offset rotates, so a pure translation keeps them
/// as they were written.
pub fn relative(cur: &Value, rel: &Value, in_tool: bool) -> Option<Value> {
    let c = get(cur)?;
    let r = get(rel)?;
    let m = Frame::from_xyzabc(c);
    if r[3..].iter().all(|x| *x == 0.0) {
        let d = if in_tool {
            apply(&m.rot, [r[0], r[1], r[2]])
        } else {
            [r[0], r[1], r[2]]
        };
        let mut out = c;
        for i in 0..3 {
            out[i] = clean(out[i] + d[i]);
        }
        return Some(with_frame(cur, out));
    }
    let composed = if in_tool {
        m.compose(&Frame::from_xyzabc(r))
    } else {
        let turn = Frame::from_xyzabc([0.0, 0.0, 0.0, r[3], r[4], r[5]]);
        let mut turned = turn.compose(&m);
        turned.pos = [0, 1, 2].map(|i| c[i] + r[i]);
        turned
    };
    Some(with_frame(cur, composed.to_xyzabc()))
}

type V3 = [f64; 3];

fn sub(p: V3, q: V3) -> V3 {
    [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
}

fn cross(u: V3, v: V3) -> V3 {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

fn dot(u: V3, v: V3) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

/// The circle through `s`, `a`, `e`: centre and unit normal, oriented so that turning about it
/// goes from `s` through `a` to `e`. `None` when the points are on one line.
fn circle(s: V3, a: V3, e: V3) -> Option<(V3, V3)> {
    let (u, v) = (sub(a, s), sub(e, s));
    let n = cross(u, v);
    let nn = dot(n, n);
    if nn < 1e-12 {
        return None;
    }
    // Circumcentre of the triangle s, a, e.
    let (w1, w2) = (cross(n, u), cross(v, n));
    let (uu, vv) = (dot(u, u), dot(v, v));
    let centre = [0, 1, 2].map(|i| s[i] + (vv * w1[i] + uu * w2[i]) / (2.0 * nn));
    let l = nn.sqrt();
    Some((centre, [n[0] / l, n[1] / l, n[2] / l]))
}

/// `p` turned by `angle` degrees about the axis through `centre` along unit `k` (Rodrigues).
fn turn(p: V3, centre: V3, k: V3, angle: f64) -> V3 {
    let r = sub(p, centre);
    let (sin, cos) = angle.to_radians().sin_cos();
    let kxr = cross(k, r);
    let kr = dot(k, r);
    [0, 1, 2].map(|i| centre[i] + r[i] * cos + kxr[i] * sin + k[i] * kr * (1.0 - cos))
}

/// Points along the arc from `s` through `a` to `e` (`n` segments, both ends included), or
/// `None` when the three points are on one line.
pub(crate) fn arc_points(s: V3, a: V3, e: V3, n: usize) -> Option<Vec<V3>> {
    let (centre, k) = circle(s, a, e)?;
    let (rs, re) = (sub(s, centre), sub(e, centre));
    let mut sweep = dot(k, cross(rs, re)).atan2(dot(rs, re)).to_degrees();
    if sweep <= 0.0 {
        sweep += 360.0;
    }
    let n = n.max(1);
    Some(
        (0..=n)
            .map(|i| turn(s, centre, k, sweep * i as f64 / n as f64))
            .collect(),
    )
}

/// Where `CIRC aux, end, CA angle` stops: `start` turned by `angle` degrees about the centre of
/// the circle through `start`, `aux` and `end`, in the direction start → aux → end (aux fields
/// it lacks are the start's); X, Y, Z from the arc, everything else from `end`. `None` when the
/// three points are on one line.
pub fn circ_end(start: &Value, aux: &Value, end: &Value, angle: f64) -> Option<Value> {
    let s = get(start)?;
    let e = get(end)?;
    let a = [0, 1, 2].map(|i| {
        aux.field(CART_FIELDS[i])
            .and_then(|x| x.as_f64())
            .unwrap_or(s[i])
    });
    let s3 = [s[0], s[1], s[2]];
    let (centre, k) = circle(s3, a, [e[0], e[1], e[2]])?;
    let p = turn(s3, centre, k, angle);
    let mut out = e;
    for i in 0..3 {
        out[i] = clean(p[i]);
    }
    Some(with_frame(end, out))
}

/// INV_POS: the inverse frame.
pub fn inverse(a: &Value) -> Option<Value> {
    Some(with_frame(a, frame_of(a)?.inverse().to_xyzabc()))
}

/// `$POS_ACT` after `$BASE`/`$TOOL` changed from `old` to `new` (each `(base, tool)`): the
/// flange stays where it is, so the same physical pose is expressed in the new frames
/// (`INV(new_base) : old_base : pos : INV(old_tool) : new_tool`). Fields other than X..C keep
/// their values.
pub fn rebase(pos: &Value, old: (&Value, &Value), new: (&Value, &Value)) -> Option<Value> {
    let flange = frame_of(old.0)?
        .compose(&frame_of(pos)?)
        .compose(&frame_of(old.1)?.inverse());
    let m = frame_of(new.0)?
        .inverse()
        .compose(&flange)
        .compose(&frame_of(new.1)?);
    Some(with_frame(pos, m.to_xyzabc()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(f: [f64; 6]) -> Value {
        Value::Struc {
            ty: "E6POS".into(),
            fields: CART_FIELDS
                .iter()
                .zip(f)
                .map(|(n, v)| (n.to_string(), Value::Real(v)))
                .chain([("E1".to_string(), Value::Real(7.0))])
                .collect(),
        }
    }

    fn close(a: &Value, b: [f64; 6]) -> bool {
        get(a)
            .unwrap()
            .iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn circ_with_an_angle_follows_the_arc() {
        // Circle through (0,0), (10,10), (20,0) in the XY plane: centre (10,0), radius 10;
        // the arc runs over (10,10), so 90 degrees from the start is (10,10) and 180 the end.
        let start = pose([0.0, 0.0, 5.0, 0.0, 0.0, 0.0]);
        let aux = Value::Partial(vec![
            ("X".into(), Value::Real(10.0)),
            ("Y".into(), Value::Real(10.0)),
        ]);
        let end = pose([20.0, 0.0, 5.0, 30.0, 0.0, 0.0]);
        let q = circ_end(&start, &aux, &end, 90.0).unwrap();
        assert!(close(&q, [10.0, 10.0, 5.0, 30.0, 0.0, 0.0]), "{q:?}");
        let h = circ_end(&start, &aux, &end, 180.0).unwrap();
        assert!(close(&h, [20.0, 0.0, 5.0, 30.0, 0.0, 0.0]), "{h:?}");
        let back = circ_end(&start, &aux, &end, -90.0).unwrap();
        assert!(close(&back, [10.0, -10.0, 5.0, 30.0, 0.0, 0.0]), "{back:?}");
        let line = pose([40.0, 0.0, 5.0, 0.0, 0.0, 0.0]);
        assert!(circ_end(&start, &end, &line, 90.0).is_none());
    }

    #[test]
    fn arc_points_run_from_start_through_aux_to_end() {
        let p = arc_points([0.0, 0.0, 5.0], [10.0, 10.0, 5.0], [20.0, 0.0, 5.0], 4).unwrap();
        let want = [
            [0.0, 0.0],
            [10.0 - 50f64.sqrt(), 50f64.sqrt()],
            [10.0, 10.0],
            [10.0 + 50f64.sqrt(), 50f64.sqrt()],
            [20.0, 0.0],
        ];
        for (q, w) in p.iter().zip(want) {
            assert!(
                (q[0] - w[0]).abs() < 1e-9 && (q[1] - w[1]).abs() < 1e-9,
                "{p:?}"
            );
            assert!((q[2] - 5.0).abs() < 1e-9);
        }
        // The long way round when the auxiliary point says so.
        let long = arc_points([0.0, 0.0, 0.0], [10.0, -10.0, 0.0], [10.0, 10.0, 0.0], 3).unwrap();
        assert!(
            (long[1][1] + 10.0).abs() < 1e-9 && (long[1][0] - 10.0).abs() < 1e-9,
            "{long:?}"
        );
        assert!(arc_points([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], 4).is_none());
    }

    #[test]
    fn rotation_columns_are_the_tool_axes() {
        let rotation = crate::geom::abc_to_matrix;
        // B = 180: the tool's Z points down, X backwards.
        let r = rotation(0.0, 180.0, 0.0);
        let z = [r[0][2], r[1][2], r[2][2]];
        let x = [r[0][0], r[1][0], r[2][0]];
        assert!(
            (z[2] + 1.0).abs() < 1e-12 && (x[0] + 1.0).abs() < 1e-12,
            "{r:?}"
        );
        let r = rotation(90.0, 0.0, 0.0);
        assert!((r[1][0] - 1.0).abs() < 1e-12, "A turns X towards Y: {r:?}");
    }

    #[test]
    fn rebase_keeps_the_flange_where_it_is() {
        let null = pose([0.0; 6]);
        let tool = pose([0.0, 0.0, 100.0, 0.0, 0.0, 0.0]);
        // A TCP pointing down (B = 180): with the 100 mm tool, the flange is 100 mm higher, so
        // the flange pose read without a tool is the TCP pose plus 100 in Z.
        let tcp = pose([500.0, 20.0, 300.0, 0.0, 180.0, 0.0]);
        let flange = rebase(&tcp, (&null, &tool), (&null, &null)).unwrap();
        assert!(
            close(&flange, [500.0, 20.0, 400.0, 180.0, 0.0, 180.0]),
            "{flange:?}"
        );
        let back = rebase(&flange, (&null, &null), (&null, &tool)).unwrap();
        assert!(
            close(&back, [500.0, 20.0, 300.0, 180.0, 0.0, 180.0]),
            "{back:?}"
        );
        assert_eq!(back.field("E1"), Some(&Value::Real(7.0)));
        let base = pose([100.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let in_base = rebase(&flange, (&null, &null), (&base, &null)).unwrap();
        assert!(
            close(&in_base, [400.0, 20.0, 400.0, 180.0, 0.0, 180.0]),
            "{in_base:?}"
        );
    }
}
