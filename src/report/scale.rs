//! Numbers for people: "nice" steps for ticks and scale bars, and short number text.

/// The nice number (1, 2 or 5 × 10^k) nearest below or at `x` (> 0).
pub fn nice_floor(x: f64) -> f64 {
    if !x.is_finite() || x <= 0.0 {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let m = x / p;
    let base = if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    base * p
}

/// The nice number (1, 2 or 5 × 10^k) nearest above or at `x` (> 0).
pub fn nice_ceil(x: f64) -> f64 {
    if !x.is_finite() || x <= 0.0 {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let m = x / p;
    let base = [1.0, 2.0, 5.0]
        .into_iter()
        .find(|b| m <= b * (1.0 + 1e-9))
        .unwrap_or(10.0);
    base * p
}

/// Tick values: multiples of a nice step covering `lo..=hi`, at most about `n + 1` of them.
pub fn ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let span = (hi - lo).abs();
    if !span.is_finite() || span <= 0.0 {
        return vec![lo];
    }
    let step = nice_ceil(span / n.max(1) as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| clean(i as f64 * step)).collect()
}

fn clean(x: f64) -> f64 {
    let r = (x * 1e9).round() / 1e9;
    if r == 0.0 { 0.0 } else { r }
}

/// A number with at most `decimals` decimals and no trailing zeros (`-0` is `0`).
pub fn num(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".into() } else { s }
}

/// An SVG coordinate (0.1 px is finer than any screen needs).
pub fn px(x: f64) -> String {
    num(x, 1)
}

/// Simulated time: `850 ms`, `12.5 s`.
pub fn duration(ms: f64) -> String {
    if ms.abs() < 1000.0 {
        format!("{} ms", num(ms, 3))
    } else {
        format!("{} s", num(ms / 1000.0, 3))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps_and_ticks() {
        assert_eq!(nice_floor(7.3), 5.0);
        assert_eq!(nice_floor(0.031), 0.02);
        assert_eq!(nice_floor(130.0), 100.0);
        assert_eq!(nice_ceil(7.3), 10.0);
        assert_eq!(nice_ceil(1.2), 2.0);
        assert_eq!(nice_ceil(3.0), 5.0);
        assert_eq!(nice_ceil(0.5), 0.5);
        assert_eq!(ticks(-120.0, 260.0, 4), vec![-100.0, 0.0, 100.0, 200.0]);
        assert_eq!(
            ticks(-110.0, 110.0, 6),
            vec![-100.0, -50.0, 0.0, 50.0, 100.0]
        );
        assert_eq!(ticks(5.0, 5.0, 4), vec![5.0]);
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(12.0, 3), "12");
        assert_eq!(num(-0.0001, 3), "0");
        assert_eq!(num(2.50, 3), "2.5");
        assert_eq!(duration(850.0), "850 ms");
        assert_eq!(duration(12_500.0), "12.5 s");
    }
}
