//! Single-epoch least-squares position/velocity/clock fix from
//! pseudoranges and pseudorange rates (Groves §9.4.1), for the loosely
//! coupled filter.

use nalgebra::{Matrix3, Matrix4, SMatrix, SVector, Vector3, Vector4};

use super::range::predicted_range;
use super::system::{GnssSystem, FIX_BIAS_SYSTEMS};
use super::{GnssEpoch, SatelliteMeasurement};
use crate::geodesy::domain::MAX_DISTANCE_M;
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::{Error, Result};

/// Dilutions of precision (unweighted geometry, Groves eqs. 9.42-9.44).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dops {
    /// Geometric DOP.
    pub gdop: f64,
    /// Position DOP.
    pub pdop: f64,
    /// Horizontal DOP.
    pub hdop: f64,
    /// Vertical DOP.
    pub vdop: f64,
    /// Time DOP.
    pub tdop: f64,
}

/// A least-squares fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fix {
    /// Reception time of the epoch on the trajectory's time axis, s.
    pub time_s: f64,
    /// Receiver position, ECEF, m.
    pub position_ecef: Vector3<f64>,
    /// NaN when fewer than 4 satellites carry a usable pseudorange rate.
    pub velocity_ecef: Vector3<f64>,
    /// Receiver clock offset, m: of the reference system's pseudoranges
    /// (GPS when the epoch has GPS satellites, else the first of Galileo,
    /// BeiDou, GLONASS it has).
    pub clock_offset_m: f64,
    /// Inter-system biases of Galileo, BeiDou and GLONASS relative to the
    /// reference ([`FIX_BIAS_SYSTEMS`] order), m (each system's
    /// pseudoranges − the reference's at one position); 0 for the
    /// reference, NaN for a system not in the epoch.
    pub inter_system_bias_m: [f64; FIX_BIAS_SYSTEMS.len()],
    /// Receiver clock drift, m/s (NaN without usable rates).
    pub clock_drift_m_s: f64,
    /// Covariance of (x, y, z, clock offset), m², from the measurement stds.
    pub position_clock_covariance: Matrix4<f64>,
    /// Covariance of (vx, vy, vz, clock drift), (m/s)².
    pub velocity_drift_covariance: Matrix4<f64>,
    /// Dilutions of precision of the satellites used.
    pub dops: Dops,
    /// Satellites used in the position.
    pub n_satellites: usize,
    /// Gauss-Newton iterations used for the position.
    pub iterations: usize,
    /// Satellites the residual test left out, in the order it left them
    /// out (`super::residual_test`); empty when every satellite fits.
    pub excluded: ExcludedSatellites,
    /// Post-fit test statistic Σ (vᵢ/σᵢ)² of the satellites used; NaN when
    /// there is no redundancy or the weights are unit (σ = 0 everywhere).
    pub residual_chi_square: f64,
    /// Its degrees of freedom: satellites used − unknowns.
    pub residual_dof: usize,
    /// The threshold χ²(1 − P_fa, dof) it was held to; NaN when the test
    /// did not run (no redundancy, unit weights, or the test turned off).
    pub residual_threshold: f64,
}

/// Satellite numbers left out of a fix, at most [`ExcludedSatellites::CAPACITY`]
/// (a fixed array keeps [`Fix`] `Copy`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ExcludedSatellites {
    ids: [u16; ExcludedSatellites::CAPACITY],
    len: usize,
}

impl ExcludedSatellites {
    /// Most satellites one fix leaves out.
    pub const CAPACITY: usize = 8;

    /// The satellite numbers, in exclusion order.
    pub fn as_slice(&self) -> &[u16] {
        &self.ids[..self.len]
    }

    /// Adds `sat_id`; false (and nothing added) when full.
    pub fn push(&mut self, sat_id: u16) -> bool {
        if self.len == Self::CAPACITY {
            return false;
        }
        self.ids[self.len] = sat_id;
        self.len += 1;
        true
    }

    /// How many satellites are held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether none is held.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// Checks the stds; returns true when every σ is zero (noise-free data:
/// unit weights and a zero covariance), else the weights are 1/σ².
fn unit_weights(stds: impl Iterator<Item = f64> + Clone, what: &str, time_s: f64) -> Result<bool> {
    let all_zero = stds.clone().all(|s| s == 0.0);
    if let Some(bad) = stds.clone().find(|s| !(s.is_finite() && *s >= 0.0)) {
        return Err(Error::invalid(
            "epoch",
            format!("{what} must be finite and non-negative at t = {time_s} s, got {bad}"),
        ));
    }
    if !all_zero && stds.clone().any(|s| s == 0.0) {
        return Err(Error::invalid(
            "epoch",
            format!("{what} mixes zero and non-zero values at t = {time_s} s"),
        ));
    }
    Ok(all_zero)
}

/// Gauss-Newton fix (Groves eqs. 9.35-9.41) using [`predicted_range`] (so
/// the Sagnac correction is applied exactly as in the filters).
///
/// `prior`: a starting position (e.g. the INS position); `None` starts from
/// the Earth's centre, from which GPS geometry converges in a few steps.
/// Errors: fewer than 4 satellites → `InvalidArgument` naming `epoch`;
/// a geometry singular where the iteration starts → `Unobservable`;
/// pseudoranges that do not fit one position (the iteration is driven to
/// a degenerate geometry, or does not converge in 20 iterations) →
/// `Divergence`, naming the satellite whose pseudorange is the outlier when
/// leaving it out gives a fix that fits (5 or more satellites): an outlier
/// is not reported as singular geometry.
///
/// No residual test: [`super::solve_fix`] runs this, then tests the
/// residuals and leaves out the satellites that fail.
pub fn solve_fix_all_satellites(epoch: &GnssEpoch, prior: Option<Vector3<f64>>) -> Result<Fix> {
    match solve_fix_once(epoch, prior) {
        Err(Failure::Inconsistent { farthest_m }) => Err(inconsistent(epoch, prior, farthest_m)),
        Err(Failure::Error(e)) => Err(e),
        Ok(fix) => Ok(fix),
    }
}

/// Why [`solve_fix_once`] failed: an error to report as it is, or
/// pseudoranges that drove the iteration astray (`farthest_m`: the largest
/// distance from the Earth's centre the iteration reached).
enum Failure {
    Error(Error),
    Inconsistent { farthest_m: f64 },
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Error(e)
    }
}

/// The error of an epoch whose pseudoranges do not fit one position: the
/// outlier satellite when leaving exactly one out gives a fix whose
/// residuals are within 10 σ (and 1 km), else the inconsistency.
fn inconsistent(epoch: &GnssEpoch, prior: Option<Vector3<f64>>, farthest_m: f64) -> Error {
    let t = epoch.time_s;
    let m = &epoch.measurements;
    let mut fitting = Vec::new();
    if m.len() >= 5 {
        for j in 0..m.len() {
            let rest = GnssEpoch {
                time_s: t,
                measurements: m
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != j)
                    .map(|(_, s)| *s)
                    .collect(),
            };
            if let Ok(fix) = solve_fix_once(&rest, prior) {
                let zero = Vector3::zeros();
                let fits = rest.measurements.iter().all(|s| {
                    let p = predicted_range(
                        &s.position_ecef,
                        &s.velocity_ecef,
                        &fix.position_ecef,
                        &zero,
                    );
                    let r = (s.pseudorange_m
                        - p.range_m
                        - clock_and_bias(fix.clock_offset_m, &fix.inter_system_bias_m, s))
                    .abs();
                    let std = if s.pseudorange_std_m > 0.0 {
                        s.pseudorange_std_m
                    } else {
                        100.0
                    };
                    r <= (10.0 * std).min(1000.0)
                });
                if fits {
                    let p = predicted_range(
                        &m[j].position_ecef,
                        &m[j].velocity_ecef,
                        &fix.position_ecef,
                        &zero,
                    );
                    let r = m[j].pseudorange_m
                        - p.range_m
                        - clock_and_bias(fix.clock_offset_m, &fix.inter_system_bias_m, &m[j]);
                    fitting.push((m[j].sat_id, r));
                }
            }
        }
    }
    let reason = match fitting.as_slice() {
        [(id, r)] => format!(
            "least-squares fix: the pseudorange of satellite {id} is an outlier ({r:.4e} m off the fix of the other {} satellites, which fit it); the geometry is fine: leave the satellite out or fix its pseudorange",
            m.len() - 1
        ),
        _ => format!(
            "least-squares fix: the pseudoranges of the {} satellites do not fit one position (the least-squares fix was driven {farthest_m:.3e} m from the Earth's centre, or did not converge in 20 iterations): an outlier or wrong satellite positions, not the geometry",
            m.len()
        ),
    };
    Error::Divergence { time_s: t, reason }
}

/// Unknowns of a fix at most: position, clock, three biases.
const UNKNOWNS: usize = 4 + FIX_BIAS_SYSTEMS.len();
type Normal = SMatrix<f64, UNKNOWNS, UNKNOWNS>;
type Row = SVector<f64, UNKNOWNS>;

/// The unknowns of an epoch's fix: position, the reference system's clock
/// and one inter-system bias per other system present (Groves §9.4.2.3).
/// Columns 4, 5 and 6 are the Galileo, BeiDou and GLONASS biases; a
/// system absent, or the reference, has no rows there and its column is
/// held at zero.
struct Unknowns {
    reference: GnssSystem,
    /// Whether each [`FIX_BIAS_SYSTEMS`] bias is estimated.
    estimated: [bool; FIX_BIAS_SYSTEMS.len()],
}

impl Unknowns {
    fn of(m: &[SatelliteMeasurement]) -> Self {
        let present = |system| m.iter().any(|s| s.system == system);
        let reference = GnssSystem::ALL
            .into_iter()
            .find(|&s| present(s))
            .unwrap_or_default();
        let estimated = FIX_BIAS_SYSTEMS.map(|system| system != reference && present(system));
        Self {
            reference,
            estimated,
        }
    }

    fn count(&self) -> usize {
        4 + self.estimated.iter().filter(|&&e| e).count()
    }

    /// The bias column of `system`, when its bias is estimated.
    fn column(&self, system: GnssSystem) -> Option<usize> {
        let k = system.fix_bias_index()?;
        self.estimated[k].then_some(4 + k)
    }

    /// The row of a pseudorange along line of sight `u`.
    fn row(&self, u: &Vector3<f64>, system: GnssSystem) -> Row {
        let mut h = Row::zeros();
        h.fixed_rows_mut::<3>(0).copy_from(&(-u));
        h[3] = 1.0;
        if let Some(j) = self.column(system) {
            h[j] = 1.0;
        }
        h
    }

    /// Holds the columns not estimated at zero (their rows are empty).
    fn hold(&self, normal: &mut Normal) {
        for (k, estimated) in self.estimated.iter().enumerate() {
            if !estimated {
                normal[(4 + k, 4 + k)] = 1.0;
            }
        }
    }
}

/// The pseudorange model's prediction beyond the range: the clock and the
/// satellite's system's bias.
fn clock_and_bias(
    fix_clock_m: f64,
    biases: &[f64; FIX_BIAS_SYSTEMS.len()],
    s: &SatelliteMeasurement,
) -> f64 {
    fix_clock_m
        + s.system.fix_bias_index().map_or(0.0, |k| {
            if biases[k].is_finite() {
                biases[k]
            } else {
                0.0
            }
        })
}

fn solve_fix_once(
    epoch: &GnssEpoch,
    prior: Option<Vector3<f64>>,
) -> std::result::Result<Fix, Failure> {
    let m = &epoch.measurements;
    let t = epoch.time_s;
    let unknowns = Unknowns::of(m);
    if m.len() < unknowns.count() {
        return Err(Failure::Error(Error::invalid(
            "epoch",
            format!(
                "a fix needs at least {} satellites (4, and one per system beyond the first for \
                 its inter-system bias), got {} at t = {t} s",
                unknowns.count(),
                m.len()
            ),
        )));
    }
    for s in m {
        let finite = s.position_ecef.iter().all(|x| x.is_finite()) && s.pseudorange_m.is_finite();
        if finite && s.position_ecef.amax() > MAX_DISTANCE_M {
            return Err(Failure::Error(Error::invalid(
                "epoch",
                format!(
                    "satellite {} at t = {t} s has a position component of {:.1e} m",
                    s.sat_id,
                    s.position_ecef.amax()
                ),
            )));
        }
        if !finite {
            return Err(Failure::Error(Error::invalid(
                "epoch",
                format!(
                    "satellite {} at t = {t} s has a NaN or infinite position or pseudorange",
                    s.sat_id
                ),
            )));
        }
    }
    let unit_range = unit_weights(m.iter().map(|s| s.pseudorange_std_m), "pseudorange_std", t)?;
    // Rates are optional: the velocity is solved from the satellites whose
    // rate, rate std and satellite velocity are finite, when there are 4.
    let rated: Vec<&SatelliteMeasurement> = m
        .iter()
        .filter(|s| {
            s.pseudorange_rate_m_s.is_finite()
                && s.pseudorange_rate_std_m_s.is_finite()
                && s.velocity_ecef.iter().all(|x| x.is_finite())
        })
        .collect();
    let unit_rate = unit_weights(
        rated.iter().map(|s| s.pseudorange_rate_std_m_s),
        "pseudorange_rate_std",
        t,
    )?;
    if let Some(p) = prior {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(Failure::Error(Error::invalid(
                "prior",
                "contains NaN or infinite values",
            )));
        }
        // The largest component: the norm of a 1e200 m vector overflows.
        if p.amax() > MAX_DISTANCE_M {
            return Err(Failure::Error(Error::invalid(
                "prior",
                format!(
                    "has a component of {:.1e} m, beyond the ±{:.1e} m of any position",
                    p.amax(),
                    MAX_DISTANCE_M
                ),
            )));
        }
    }
    let singular = || Error::Unobservable {
        axis: "ecef".into(),
        parameter: "position and clock".into(),
        reason: format!("the satellite geometry at t = {t} s is singular"),
    };

    // Position, clock offset and inter-system biases.
    let mut x = prior.unwrap_or_else(Vector3::zeros);
    let mut b = 0.0;
    let mut biases = [0.0; FIX_BIAS_SYSTEMS.len()];
    let zero = Vector3::zeros();
    let mut iterations = 0;
    let mut converged = false;
    let mut normal = Normal::zeros();
    let mut geometry = Normal::zeros();
    let mut farthest_m: f64 = 0.0;
    while iterations < 20 {
        iterations += 1;
        normal = Normal::zeros();
        geometry = Normal::zeros();
        let mut rhs = Row::zeros();
        for s in m {
            let p = predicted_range(&s.position_ecef, &s.velocity_ecef, &x, &zero);
            let h = unknowns.row(&p.line_of_sight_ecef, s.system);
            let w = if unit_range {
                1.0
            } else {
                1.0 / (s.pseudorange_std_m * s.pseudorange_std_m)
            };
            normal += w * h * h.transpose();
            geometry += h * h.transpose();
            rhs += w * h * (s.pseudorange_m - p.range_m - clock_and_bias(b, &biases, s));
        }
        unknowns.hold(&mut normal);
        unknowns.hold(&mut geometry);
        // Singular where the iteration starts: the geometry. Singular (or
        // not finite) only after the pseudoranges moved the estimate: they
        // do not fit one position.
        if iterations == 1 {
            // The SVD does not return on non-finite entries.
            if !geometry.iter().all(|v| v.is_finite()) {
                return Err(singular().into());
            }
            let sv = geometry.singular_values();
            if sv.min().is_nan() || sv.min() <= 1e-12 * sv.max() {
                return Err(singular().into());
            }
        }
        let Some(inverse) = normal.try_inverse() else {
            return Err(if iterations == 1 {
                singular().into()
            } else {
                Failure::Inconsistent { farthest_m }
            });
        };
        let dx = inverse * rhs;
        x += dx.fixed_rows::<3>(0);
        b += dx[3];
        for (k, bias) in biases.iter_mut().enumerate() {
            *bias += dx[4 + k];
        }
        farthest_m = farthest_m.max(x.norm());
        if !(x.iter().all(|v| v.is_finite()) && b.is_finite()) {
            return Err(Failure::Inconsistent { farthest_m });
        }
        if dx.norm() < 1e-4 {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(Failure::Inconsistent { farthest_m });
    }
    let covariance: Matrix4<f64> = if unit_range {
        Matrix4::zeros()
    } else {
        normal
            .try_inverse()
            .ok_or_else(singular)?
            .fixed_view::<4, 4>(0, 0)
            .into_owned()
    };
    let q: Matrix4<f64> = geometry
        .try_inverse()
        .ok_or_else(singular)?
        .fixed_view::<4, 4>(0, 0)
        .into_owned();
    let inter_system_bias_m = FIX_BIAS_SYSTEMS.map(|system| {
        match (system == unknowns.reference, unknowns.column(system)) {
            (true, _) => 0.0,
            (false, Some(j)) => biases[j - 4],
            (false, None) => f64::NAN,
        }
    });

    // Velocity and clock drift: the rate model is linear in (v, ḃ) up to
    // the light-time factor, so a few Gauss-Newton passes converge. Without
    // four usable rates both stay NaN.
    let mut v = Vector3::repeat(f64::NAN);
    let mut d = f64::NAN;
    let mut rate_covariance = Matrix4::repeat(f64::NAN);
    if rated.len() >= 4 {
        v = Vector3::zeros();
        d = 0.0;
        let mut rate_normal = Matrix4::zeros();
        for _ in 0..5 {
            rate_normal = Matrix4::zeros();
            let mut rhs = Vector4::zeros();
            for s in &rated {
                let p = predicted_range(&s.position_ecef, &s.velocity_ecef, &x, &v);
                let u = p.line_of_sight_ecef;
                let h = Vector4::new(-u.x, -u.y, -u.z, 1.0);
                let w = if unit_rate {
                    1.0
                } else {
                    1.0 / (s.pseudorange_rate_std_m_s * s.pseudorange_rate_std_m_s)
                };
                rate_normal += w * h * h.transpose();
                rhs += w * h * (s.pseudorange_rate_m_s - p.range_rate_m_s - d);
            }
            let dv = rate_normal.try_inverse().ok_or_else(singular)? * rhs;
            v += dv.fixed_rows::<3>(0);
            d += dv[3];
            if dv.norm() < 1e-9 {
                break;
            }
        }
        rate_covariance = if unit_rate {
            Matrix4::zeros()
        } else {
            rate_normal.try_inverse().ok_or_else(singular)?
        };
    }

    // DOPs: position block in NED (Groves eq. 9.44).
    let g = ecef_to_geodetic(&x);
    let c = c_n_e(g.latitude_rad, g.longitude_rad);
    let q_pos: Matrix3<f64> = q.fixed_view::<3, 3>(0, 0).into_owned();
    let q_ned = c.transpose() * q_pos * c;
    Ok(Fix {
        time_s: t,
        position_ecef: x,
        velocity_ecef: v,
        clock_offset_m: b,
        inter_system_bias_m,
        clock_drift_m_s: d,
        position_clock_covariance: covariance,
        velocity_drift_covariance: rate_covariance,
        dops: Dops {
            gdop: q.trace().sqrt(),
            pdop: q_pos.trace().sqrt(),
            hdop: (q_ned[(0, 0)] + q_ned[(1, 1)]).sqrt(),
            vdop: q_ned[(2, 2)].sqrt(),
            tdop: q[(3, 3)].sqrt(),
        },
        n_satellites: m.len(),
        iterations,
        excluded: ExcludedSatellites::default(),
        residual_chi_square: f64::NAN,
        residual_dof: m.len() - unknowns.count(),
        residual_threshold: f64::NAN,
    })
}

/// A satellite's post-fit residual at a fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PostFitResidual {
    /// The satellite number ([`crate::gnss::satellite_number`]).
    pub sat_id: u16,
    /// Measured − predicted pseudorange, m.
    pub residual_m: f64,
    /// The residual over its own σ: vᵢ / (σᵢ √rᵢ), rᵢ = 1 − wᵢ hᵢᵀ (HᵀWH)⁻¹ hᵢ
    /// its redundancy number (Baarda's w-test statistic, standard normal
    /// when the model holds; Teunissen 2003, §4.5): NaN when rᵢ ≈ 0 (a
    /// satellite the fix cannot do without, e.g. the only one of its
    /// system).
    pub normalized: f64,
}

/// The post-fit residuals of `epoch`'s pseudoranges at `fix` (made from
/// the same satellites), and Σ (vᵢ/σᵢ)². `None` with unit weights (every
/// σ zero: no scale to test against).
pub fn post_fit_residuals(epoch: &GnssEpoch, fix: &Fix) -> Option<(Vec<PostFitResidual>, f64)> {
    let m = &epoch.measurements;
    if m.iter()
        .any(|s| s.pseudorange_std_m.is_nan() || s.pseudorange_std_m <= 0.0)
    {
        return None;
    }
    let unknowns = Unknowns::of(m);
    let zero = Vector3::zeros();
    let mut normal = Normal::zeros();
    let mut rows = Vec::with_capacity(m.len());
    for s in m {
        let p = predicted_range(
            &s.position_ecef,
            &s.velocity_ecef,
            &fix.position_ecef,
            &zero,
        );
        let h = unknowns.row(&p.line_of_sight_ecef, s.system);
        let w = 1.0 / (s.pseudorange_std_m * s.pseudorange_std_m);
        normal += w * h * h.transpose();
        let v = s.pseudorange_m
            - p.range_m
            - clock_and_bias(fix.clock_offset_m, &fix.inter_system_bias_m, s);
        rows.push((h, w, v));
    }
    unknowns.hold(&mut normal);
    let inverse = normal.try_inverse()?;
    let mut chi_square = 0.0;
    let residuals = m
        .iter()
        .zip(rows)
        .map(|(s, (h, w, v))| {
            chi_square += w * v * v;
            let redundancy = 1.0 - w * (h.transpose() * inverse * h)[(0, 0)];
            PostFitResidual {
                sat_id: s.sat_id,
                residual_m: v,
                normalized: if redundancy > 1e-9 {
                    v * w.sqrt() / redundancy.sqrt()
                } else {
                    f64::NAN
                },
            }
        })
        .collect();
    Some((residuals, chi_square))
}
