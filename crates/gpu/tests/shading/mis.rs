//! MIS weights (`mis.wgsl`) against `stratapt_sampling::mis`, on edge values and random pdfs.

use super::*;
use stratapt_sampling::mis;

const MIS_PROBE: &str = r#"
fn probe(i: u32) {
    let a = probe_f(2u * i);
    let b = probe_f(2u * i + 1u);
    probe_put(2u * i, mis_power_heuristic(a, b));
    probe_put(2u * i + 1u, mis_balance_heuristic(a, b));
}
"#;

#[test]
fn mis_weights_match_cpu() {
    let values = [
        0.0,
        -0.0,
        1e-30,
        1e-3,
        0.5,
        1.0,
        3.0,
        1e19,
        1e30,
        f32::MAX,
        f32::INFINITY,
        f32::NAN,
    ];
    let mut rng = Rng(3);
    let mut pairs: Vec<(f32, f32)> = values
        .iter()
        .flat_map(|&a| values.iter().map(move |&b| (a, b)))
        .collect();
    pairs.extend((0..500).map(|_| (rng.log_range(1e-6, 1e6), rng.log_range(1e-6, 1e6))));
    let input: Vec<f32> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["mis"],
        MIS_PROBE,
        &input,
        2,
        pairs.len(),
    );
    let mut c = Check::new("mis");
    for (i, &(a, b)) in pairs.iter().enumerate() {
        c.f("power_heuristic", i, out[2 * i], mis::power_heuristic(a, b));
        c.f(
            "balance_heuristic",
            i,
            out[2 * i + 1],
            mis::balance_heuristic(a, b),
        );
    }
    c.finish();
}
