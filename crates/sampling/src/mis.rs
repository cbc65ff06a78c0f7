//! Multiple importance sampling weights (Veach 1997, ch. 9).

/// Power heuristic with β = 2: `a² / (a² + b²)` for the strategy with pdf `pdf_a` against one
/// with pdf `pdf_b`, both evaluated at the same sample.
///
/// Safe at the edges: 0 when `pdf_a` is 0 (or NaN), 1 when only `pdf_a` is infinite (a delta
/// strategy always wins), ½ when both are infinite; huge finite pdfs do not overflow.
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let (a, b) = (pdf_a.abs(), pdf_b.abs());
    if a.is_nan() || a == 0.0 {
        return 0.0;
    }
    if b.is_nan() {
        return 1.0;
    }
    if a.is_infinite() {
        return if b.is_infinite() { 0.5 } else { 1.0 };
    }
    // Divide by the larger pdf so neither square overflows.
    if a >= b {
        let r = b / a;
        1.0 / (1.0 + r * r)
    } else {
        let r = a / b;
        let r2 = r * r;
        r2 / (1.0 + r2)
    }
}

/// Balance heuristic: `a / (a + b)`, with the same edge cases as [`power_heuristic`].
pub fn balance_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let (a, b) = (pdf_a.abs(), pdf_b.abs());
    if a.is_nan() || a == 0.0 {
        return 0.0;
    }
    if b.is_nan() {
        return 1.0;
    }
    if a.is_infinite() {
        return if b.is_infinite() { 0.5 } else { 1.0 };
    }
    if a >= b {
        1.0 / (1.0 + b / a)
    } else {
        let r = a / b;
        r / (1.0 + r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_sum_to_one_and_survive_extremes() {
        let values = [
            0.0,
            1e-30,
            1e-3,
            0.5,
            1.0,
            3.0,
            1e19,
            1e30,
            f32::MAX,
            f32::INFINITY,
        ];
        for &a in &values {
            for &b in &values {
                for w in [power_heuristic, balance_heuristic] {
                    let (wa, wb) = (w(a, b), w(b, a));
                    assert!(wa.is_finite() && (0.0..=1.0).contains(&wa), "{a} {b}: {wa}");
                    if a > 0.0 || b > 0.0 {
                        assert!((wa + wb - 1.0).abs() < 1e-6, "{a} {b}: {wa} + {wb}");
                    }
                }
            }
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(f32::INFINITY, 5.0), 1.0);
        assert_eq!(power_heuristic(5.0, f32::INFINITY), 0.0);
        assert!((power_heuristic(1.0, 2.0) - 0.2).abs() < 1e-7);
        assert!((power_heuristic(1e30, 2e30) - 0.2).abs() < 1e-6);
        assert!((balance_heuristic(1.0, 3.0) - 0.25).abs() < 1e-7);
    }
}
