//! Chi-square quantiles for innovation gates and consistency bands.

/// Standard normal quantile Φ⁻¹(p), 0 < p < 1 (NaN outside): Acklam's
/// rational approximation, relative error below 1.2e-9 — ample for gates
/// and consistency bands.
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    if !(p > 0.0 && p < 1.0) {
        return f64::NAN;
    }
    let tail = |q: f64| {
        let t = (-2.0 * q.ln()).sqrt();
        (((((C[0] * t + C[1]) * t + C[2]) * t + C[3]) * t + C[4]) * t + C[5])
            / ((((D[0] * t + D[1]) * t + D[2]) * t + D[3]) * t + 1.0)
    };
    if p < 0.02425 {
        tail(p)
    } else if p > 1.0 - 0.02425 {
        -tail(1.0 - p)
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// Quantile of the chi-square distribution with `dof` degrees of freedom:
/// exact for 1 (squared normal quantile) and 2 (−2 ln(1 − p)) degrees of
/// freedom, Wilson-Hilferty (relative error < 1e-3 from 3 dof, better as
/// dof grows) beyond.
pub fn chi_square_quantile(dof: f64, p: f64) -> f64 {
    if dof == 1.0 {
        let z = normal_quantile(0.5 + 0.5 * p);
        z * z
    } else if dof == 2.0 {
        -2.0 * (1.0 - p).ln()
    } else {
        let a = 2.0 / (9.0 * dof);
        let z = normal_quantile(p);
        dof * (1.0 - a + z * a.sqrt()).powi(3)
    }
}

/// The two-sided `probability` band of the mean of `samples` independent
/// chi-square(`dof`) variables divided by `dof` (the mean NEES or NIS per
/// degree of freedom of a consistent filter): the sum is chi-square with
/// samples·dof degrees of freedom (Bar-Shalom et al. 2001, eq. 5.4.2-5).
pub fn mean_per_dof_band(dof: f64, samples: usize, probability: f64) -> (f64, f64) {
    let n = dof * samples as f64;
    let alpha = 0.5 * (1.0 - probability);
    (
        chi_square_quantile(n, alpha) / n,
        chi_square_quantile(n, 1.0 - alpha) / n,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against published table values (Abramowitz & Stegun table 26.8).
    #[test]
    fn quantiles_match_tables() {
        assert!((normal_quantile(0.975) - 1.959_963_985).abs() < 1e-8);
        assert!((normal_quantile(0.001) + 3.090_232_306).abs() < 1e-8);
        assert!((chi_square_quantile(1.0, 0.95) - 3.841_459).abs() < 1e-5);
        assert!((chi_square_quantile(1.0, 0.999) - 10.827_566).abs() < 1e-5);
        assert!((chi_square_quantile(2.0, 0.95) - 5.991_465).abs() < 1e-5);
        assert!((chi_square_quantile(9.0, 0.95) - 16.918_978).abs() < 0.02);
        assert!((chi_square_quantile(100.0, 0.025) - 74.221_927).abs() < 0.02);
        let (lo, hi) = mean_per_dof_band(9.0, 100, 0.95);
        assert!(lo < 1.0 && hi > 1.0 && hi - lo < 0.2);
    }
}
