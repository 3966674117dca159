//! Round trips and reference vectors of the orientation conventions.

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

fn pose() -> impl Strategy<Value = [f64; 6]> {
    let lock = prop::sample::select(vec![None, Some(90.0), Some(-90.0)]);
    let nudge = prop::sample::select(vec![0.0, 1e-12, -1e-12]);
    (
        -2000.0f64..2000.0,
        -2000.0f64..2000.0,
        -2000.0f64..2000.0,
        angle(),
        (-90.0f64..=90.0, lock, nudge).prop_map(|(b, l, n)| l.map_or(b, |l: f64| l + n)),
        angle(),
    )
        .prop_map(|(x, y, z, a, b, c)| [x, y, z, a, b, c])
}

fn frames_close(p: &Frame, q: &Frame) -> bool {
    max_diff(&p.rot, &q.rot) < 1e-9 && (0..3).all(|i| (p.pos[i] - q.pos[i]).abs() < 1e-6)
}

#[test]
fn gimbal_lock_puts_the_rotation_into_a() {
    let (a, b, c) = matrix_to_abc(&abc_to_matrix(10.0, 90.0, 20.0));
    assert!(close((a, b, c), (-10.0, 90.0, 0.0)), "{a} {b} {c}");
    let (a, b, c) = matrix_to_abc(&abc_to_matrix(10.0, -90.0, 20.0));
    assert!(close((a, b, c), (30.0, -90.0, 0.0)), "{a} {b} {c}");
}

#[test]
fn rotation_angle_measures_the_turn_between_orientations() {
    let a = abc_to_matrix(0.0, 0.0, 0.0);
    assert!((rotation_angle(&a, &abc_to_matrix(30.0, 0.0, 0.0)) - 30.0).abs() < 1e-9);
    assert!((rotation_angle(&a, &abc_to_matrix(0.0, 0.0, 180.0)) - 180.0).abs() < 1e-9);
    // One orientation, two angle triples: no distance.
    let p = abc_to_matrix(10.0, 90.0, 20.0);
    let q = abc_to_matrix(-10.0, 90.0, 0.0);
    assert!(rotation_angle(&p, &q) < 1e-6);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4_000))]

    #[test]
    fn abc_round_trips_through_the_matrix(f in pose()) {
        let m = abc_to_matrix(f[3], f[4], f[5]);
        let (a, b, c) = matrix_to_abc(&m);
        prop_assert!((-90.0..=90.0).contains(&b));
        let err = max_diff(&m, &abc_to_matrix(a, b, c));
        prop_assert!(err < 1e-9, "{f:?} -> ({a}, {b}, {c}): {err}");
    }

    #[test]
    fn quaternion_round_trips_and_is_normalised(f in pose()) {
        let m = abc_to_matrix(f[3], f[4], f[5]);
        let q = matrix_to_quaternion(&m);
        prop_assert!(q[0] >= 0.0);
        prop_assert!((q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        prop_assert!(max_diff(&m, &quaternion_to_matrix(q)) < 1e-9);
    }

    #[test]
    fn inverse_undoes_compose(f in pose(), g in pose()) {
        let (p, q) = (Frame::from_xyzabc(f), Frame::from_xyzabc(g));
        let back = p.inverse().compose(&p.compose(&q));
        prop_assert!(frames_close(&back, &q), "{back:?} vs {q:?}");
        let printed = Frame::from_xyzabc(p.to_xyzabc());
        prop_assert!(frames_close(&printed, &p));
    }
}
