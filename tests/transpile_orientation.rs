//! KUKA A,B,C (Z-Y'-X'') → Kawasaki O,A,T (Z-Y'-Z''): the converted angles describe the same
//! rotation within 1e-9 for 10,000 seeded random poses, a quarter of them at the degenerate
//! orientations (B = ±90 on the KUKA side; tool pointing down or up, i.e. Kawasaki A = 180 or
//! 0), a quarter just beside them. The values the transpiler prints (rounded to 1e-6 degrees)
//! are checked through `krlkit transpile` itself.

use krlkit::geom::{abc_to_matrix, abc_to_oat, max_diff, oat_to_matrix};
use krlkit::transpile::{self, Options, Source, Target};

/// A small deterministic generator (64-bit LCG), so the poses are the same on every run.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn angle(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }

    fn pick(&mut self, values: &[f64]) -> f64 {
        values[((self.next() * values.len() as f64) as usize).min(values.len() - 1)]
    }
}

/// The 10,000 poses: random, degenerate, near-degenerate, and on the axes.
fn poses() -> Vec<(f64, f64, f64)> {
    let mut g = Lcg(0x6b72_6c6b_6974);
    let mut v = Vec::new();
    for i in 0..10_000 {
        let pose = match i % 4 {
            0 => (
                g.angle(-180.0, 180.0),
                g.angle(-90.0, 90.0),
                g.angle(-180.0, 180.0),
            ),
            // KUKA gimbal lock.
            1 if i % 8 == 1 => (
                g.angle(-180.0, 180.0),
                g.pick(&[90.0, -90.0]),
                g.angle(-180.0, 180.0),
            ),
            // Tool down / up: Kawasaki A = 180 or 0 (O, T only defined as a sum/difference).
            1 => (g.angle(-180.0, 180.0), 0.0, g.pick(&[180.0, -180.0, 0.0])),
            // Beside the degenerate poses, by 1e-6 down to 1e-12 degrees.
            2 => {
                let eps = g.pick(&[1e-6, 1e-9, 1e-12]) * g.pick(&[1.0, -1.0]);
                let b = (g.pick(&[90.0, -90.0, 0.0]) + eps).clamp(-90.0, 90.0);
                (g.angle(-180.0, 180.0), b, g.pick(&[180.0, 0.0]) + eps)
            }
            _ => (
                g.pick(&[-180.0, -90.0, 0.0, 90.0, 180.0]),
                g.pick(&[-90.0, 0.0, 90.0]),
                g.pick(&[-180.0, -90.0, 0.0, 90.0, 180.0]),
            ),
        };
        v.push(pose);
    }
    v
}

#[test]
fn ten_thousand_poses_keep_their_rotation() {
    let poses = poses();
    assert_eq!(poses.len(), 10_000);
    let degenerate = poses
        .iter()
        .filter(|p| p.1.abs() == 90.0 || (p.1 == 0.0 && p.2.abs() % 180.0 == 0.0))
        .count();
    assert!(degenerate >= 2_500, "{degenerate} degenerate poses");
    let mut worst: f64 = 0.0;
    for &(a, b, c) in &poses {
        let (o, aa, t) = abc_to_oat(a, b, c);
        assert!(
            (0.0..=180.0).contains(&aa),
            "A out of range for ({a},{b},{c}): {aa}"
        );
        let err = max_diff(&abc_to_matrix(a, b, c), &oat_to_matrix(o, aa, t));
        assert!(err < 1e-9, "({a}, {b}, {c}) -> ({o}, {aa}, {t}): {err}");
        worst = worst.max(err);
    }
    eprintln!("worst matrix difference over 10,000 poses: {worst:e}");
}

#[test]
fn printed_poses_keep_their_rotation() {
    // Through the transpiler: literal poses in a program, values read back from the AS text.
    let poses = [
        (0.0, 0.0, 0.0),
        (0.0, 0.0, 180.0),
        (30.0, 0.0, 180.0),
        (90.0, 90.0, 0.0),
        (10.0, -90.0, 20.0),
        (-45.5, 12.25, -170.0),
        (179.9, 89.99, -0.01),
    ];
    let mut src = String::from("DEF p()\n");
    for (a, b, c) in poses {
        src.push_str(&format!("  LIN {{X 1, Y 2, Z 3, A {a}, B {b}, C {c}}}\n"));
    }
    src.push_str("END\n");
    let t = transpile::transpile(
        Target::Kawasaki,
        Source {
            path: "p.src".into(),
            text: src,
        },
        None,
        &Options::default(),
    );
    let got: Vec<Vec<f64>> = t
        .text
        .lines()
        .filter_map(|l| {
            l.trim()
                .strip_prefix("LMOVE TRANS(")?
                .strip_suffix(')')
                .map(str::to_owned)
        })
        .map(|args| {
            args.split(',')
                .map(|v| v.parse().expect("number"))
                .collect()
        })
        .collect();
    assert_eq!(got.len(), poses.len(), "{}", t.text);
    for ((a, b, c), v) in poses.iter().zip(&got) {
        assert_eq!(&v[..3], &[1.0, 2.0, 3.0]);
        let err = max_diff(&abc_to_matrix(*a, *b, *c), &oat_to_matrix(v[3], v[4], v[5]));
        assert!(err < 1e-7, "({a}, {b}, {c}) printed as {v:?}: {err}");
    }
    assert_eq!(&got[1][3..], &[0.0, 180.0, 180.0], "tool down");
    assert_eq!(
        &got[4][3..],
        &[-150.0, 90.0, 180.0],
        "KUKA gimbal lock (reference §1.9)"
    );
}
