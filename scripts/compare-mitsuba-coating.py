#!/usr/bin/env python3
"""Read Mitsuba 3's rough-plastic coating back from its BSDF: the internal reflectance R_int and
the transmittance T(mu) that `roughplastic` precomputes, recovered from its diffuse lobe's eval
at normal incidence with `nonlinear` off and on. strata's `coating::tests::
tables_match_mitsubas_roughplastic` compares its own tables with these numbers. Mitsuba is a
measuring stick only, never a dependency of strata or its tests. Setup (Debian 12):
    apt-get install libllvm19
    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba==3.9.1 numpy
    /tmp/mi/bin/python scripts/compare-mitsuba-coating.py
The diffuse lobe's value is  d / (1 - R) / pi / eta^2 * cos(theta_o) * T(theta_i) T(theta_o)
(linear) and  d / (1 - d R) ...  (nonlinear); their ratio at d = 0.5 gives R, then the values at
theta_i = 0 give T.
"""
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
ETA = 1.49
D = 0.5
for alpha in [0.001, 0.05, 0.3, 1.0]:
    values = {}
    for nonlinear in [False, True]:
        bsdf = mi.load_dict({
            "type": "roughplastic", "distribution": "ggx", "alpha": alpha,
            "int_ior": ETA, "ext_ior": 1.0, "nonlinear": nonlinear,
            "diffuse_reflectance": {"type": "rgb", "value": [D, D, D]},
        })
        ctx = mi.BSDFContext()
        ctx.type_mask = mi.BSDFFlags.DiffuseReflection
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(0, 0, 1)
        values[nonlinear] = [
            bsdf.eval(ctx, si, mi.Vector3f(np.sqrt(1 - mu * mu), 0, mu))[0]
            for mu in (1.0, 0.5, 0.1)
        ]
    ratio = values[False][0] / values[True][0]  # (1 - D R) / (1 - R)
    r = (ratio - 1) / (ratio - D)
    scale = (1 - r) * np.pi * ETA**2 / D
    t1 = np.sqrt(values[False][0] * scale)
    t05 = values[False][1] * scale / 0.5 / t1
    t01 = values[False][2] * scale / 0.1 / t1
    print(f"alpha {alpha}: R_int {r:.6f} T(1) {t1:.6f} T(0.5) {t05:.6f} T(0.1) {t01:.6f}")
