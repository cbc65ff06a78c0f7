// needs: nothing
// Multiple importance sampling weights (Veach 1997, ch. 9): mirrors `crates/sampling/src/mis.rs`.
//
// Interface (other modules may call):
//   fn mis_power_heuristic(pdf_a: f32, pdf_b: f32) -> f32     a² / (a² + b²), β = 2
//   fn mis_balance_heuristic(pdf_a: f32, pdf_b: f32) -> f32   a / (a + b)
// Edge cases as on the CPU: 0 when pdf_a is 0 or NaN, 1 when only pdf_a is infinite (a delta
// strategy wins), ½ when both are infinite; huge finite pdfs do not overflow.

fn mis_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

fn mis_is_inf(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) == 0x7f800000u;
}

fn mis_power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = abs(pdf_a);
    let b = abs(pdf_b);
    if (mis_is_nan(a) || a == 0.0) {
        return 0.0;
    }
    if (mis_is_nan(b)) {
        return 1.0;
    }
    if (mis_is_inf(a)) {
        return select(1.0, 0.5, mis_is_inf(b));
    }
    // Divide by the larger pdf so neither square overflows.
    if (a >= b) {
        let r = b / a;
        return 1.0 / (1.0 + r * r);
    }
    let r = a / b;
    let r2 = r * r;
    return r2 / (1.0 + r2);
}

fn mis_balance_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = abs(pdf_a);
    let b = abs(pdf_b);
    if (mis_is_nan(a) || a == 0.0) {
        return 0.0;
    }
    if (mis_is_nan(b)) {
        return 1.0;
    }
    if (mis_is_inf(a)) {
        return select(1.0, 0.5, mis_is_inf(b));
    }
    if (a >= b) {
        return 1.0 / (1.0 + b / a);
    }
    let r = a / b;
    return r / (1.0 + r);
}
