//! The ECEF error-state system model and its discretised, structured
//! covariance propagation (Groves, *Principles of GNSS, Inertial, and
//! Multisensor Integrated Navigation Systems*, 2nd ed., §14.2.3,
//! eq. 14.48-14.50 for F; eq. 14.80-14.82 for Q).
//!
//! With the conventions of [`super::state`] (errors = estimate − truth,
//! f̃ = f + b_a + w_a, ω̃ = ω + b_g + w_g) the continuous model is
//!
//! ```text
//! ψ̇  = −Ω_ie ψ − Ĉ δb_g − Ĉ diag(ω̂) δs_g + Ĉ w_g
//! δv̇ = −[(Ĉ f̂)×] ψ − 2 Ω_ie δv + Γ δr − Ĉ δb_a − Ĉ diag(f̂) δs_a + Ĉ w_a
//! δṙ = δv
//! δḃ = −δb / τ + w_b        (τ = ∞: random walk)
//! δċ = δd,  δḋ = w_d       (receiver clock, two-state model)
//! δḃ_ρ = −δb_ρ / τ_ρ + w_ρ  (per-satellite pseudorange bias, optional)
//! δl̇ = 0, δṫ_o = 0, δL̇ = 0, δμ̇ = 0  (installation constants, optional)
//! ```
//!
//! Γ = ∂g/∂r is the gravity gradient: the point-mass term
//! −μ/r³ (I − 3 r̂ r̂ᵀ) plus the centrifugal term diag(ω_ie², ω_ie², 0).
//! (Groves eq. 14.49 keeps only the radial part −2g/r r̂ r̂ᵀ; the full
//! point-mass form costs the same.) Signs differ from Groves where his
//! bias states are corrections rather than errors.
//!
//! Discretisation: Φ = I + F Δt (Groves eq. 14.72, first order), except the
//! Gauss-Markov bias decay, which uses the exact e^{−Δt/τ} and the exact
//! discrete variance of [`crate::gauss_markov`]. The neglected
//! ½F²Δt² terms scale with (ω_ie Δt)² ≈ 5e-13 and |f| Δt² ≈ 1e-3 m/s at
//! 100 Hz, below the process noise of any IMU grade.
//!
//! Q: Groves eq. 14.82 (the first-order form, noise densities times Δt;
//! Ĉ S Ĉᵀ = S I for the sensors' isotropic white noise) plus, on the
//! attitude and velocity blocks, Ĉ diag(q) Ĉᵀ Δt of the unmodelled errors'
//! noise shaped by this step's inputs ([`super::input_noise`]), and the
//! exact two-state clock block (S_φ Δt + S_f Δt³/3, S_f Δt²/2, S_f Δt).
//!
//! P ← Φ P Φᵀ + Q is computed as (P Φᵀ)ᵀ Φᵀ + Q (P is symmetric): Φᵀ is
//! listed as sparse columns (its non-zeros only, 58 for 17 states, using
//! the structure of the Earth-rate and specific-force blocks), and each
//! product is one sparse-times-dense kernel over whole contiguous columns
//! (58 column axpys of length N instead of N² dot products), the first
//! storing its result transposed, compiled also for AVX2/FMA and chosen at
//! run time. The `exp` of the bias decays and variances is computed once
//! per (Δt, noise) and reused; the filter keeps the kernel's working
//! storage, so nothing is zeroed or allocated per epoch.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::input_noise::{self, InputErrorNoise};
use super::state::{
    Layout, RangeBiasSlots, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, CLOCK_DRIFT, CLOCK_OFFSET,
    GYRO_BIAS, GYRO_SCALE_FACTOR, INSTALLATION_STATES, INTER_SYSTEM_BIAS_STATES, POSITION,
    VELOCITY,
};
use crate::attitude::skew;
use crate::gauss_markov::discretise;
use crate::geodesy::wgs84::{EARTH_RATE_RAD_S, GM_M3_S2};

/// The navigation solution the system matrix is linearised about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SystemInputs {
    /// Estimated body-to-ECEF attitude Ĉ_b^e.
    pub c_b_e: Matrix3<f64>,
    /// Corrected specific force f̂_ib^b, m/s².
    pub specific_force_b: Vector3<f64>,
    /// Corrected angular rate ω̂_ib^b, rad/s.
    pub angular_rate_b: Vector3<f64>,
    /// Estimated position r̂^e, m.
    pub position_ecef: Vector3<f64>,
}

/// Power spectral densities of the filter's process noise (one value per
/// triad, the same on each axis), Groves §14.2.4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcessNoise {
    /// Accelerometer white noise S_ra, m²/s³ (= (velocity random walk)²;
    /// σ² / f_s for a white noise of σ per sample at f_s).
    pub accel_white_psd: f64,
    /// Gyro white noise S_rg, rad²/s (= (angle random walk)²).
    pub gyro_white_psd: f64,
    /// Driving noise of the accelerometer bias S_bad, (m/s²)²/s
    /// (2σ²/τ for a Gauss-Markov bias, the squared random-walk coefficient otherwise).
    pub accel_bias_psd: f64,
    /// Correlation time of the accelerometer bias, s; `f64::INFINITY` for a random walk.
    pub accel_bias_correlation_time_s: f64,
    /// Driving noise of the gyro bias S_bgd, (rad/s)²/s.
    pub gyro_bias_psd: f64,
    /// Correlation time of the gyro bias, s; `f64::INFINITY` for a random walk.
    pub gyro_bias_correlation_time_s: f64,
    /// Receiver clock phase noise S_cφ, m²/s.
    pub clock_phase_psd: f64,
    /// Receiver clock frequency noise S_cf, m²/s³.
    pub clock_frequency_psd: f64,
    /// Driving noise of the accelerometer scale-factor states, 1/s (23-state filters).
    pub accel_scale_factor_psd: f64,
    /// Driving noise of the gyro scale-factor states, 1/s (23-state filters).
    pub gyro_scale_factor_psd: f64,
    /// Driving noise of each satellite's pseudorange-bias state, m²/s
    /// (2σ²/τ of a Gauss-Markov bias; filters with range-bias states).
    pub range_bias_psd: f64,
    /// Correlation time of the pseudorange biases, s.
    pub range_bias_correlation_time_s: f64,
    /// Random-walk PSD of each inter-system bias, m²/s (filters with the
    /// inter-system-bias states).
    pub inter_system_bias_psd: f64,
    /// The sensor errors the state lacks, as noise shaped by the inputs
    /// ([`super::input_noise`]); added to the white noise per body axis.
    pub input_errors: InputErrorNoise,
}

/// Gravity gradient Γ = ∂g^e/∂r^e: point mass plus centrifugal term.
fn gravity_gradient(r: &Vector3<f64>) -> Matrix3<f64> {
    let r2 = r.norm_squared();
    let rn = r2.sqrt();
    let u = r / rn;
    let w2 = EARTH_RATE_RAD_S * EARTH_RATE_RAD_S;
    -GM_M3_S2 / (r2 * rn) * (Matrix3::identity() - 3.0 * u * u.transpose())
        + Matrix3::from_diagonal(&Vector3::new(w2, w2, 0.0))
}

/// The continuous system matrix F (dense), for tests and for users who
/// want it; propagation itself never forms it.
pub fn system_matrix<const N: usize>(
    inputs: &SystemInputs,
    noise: &ProcessNoise,
) -> SMatrix<f64, N, N> {
    let mut f = SMatrix::<f64, N, N>::zeros();
    let omega_ie = skew(&Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S));
    let c = inputs.c_b_e;
    let f_e = c * inputs.specific_force_b;
    let set = |f: &mut SMatrix<f64, N, N>, i: usize, j: usize, b: &Matrix3<f64>| {
        f.fixed_view_mut::<3, 3>(i, j).copy_from(b);
    };
    set(&mut f, ATTITUDE, ATTITUDE, &(-omega_ie));
    set(&mut f, ATTITUDE, GYRO_BIAS, &(-c));
    set(&mut f, VELOCITY, ATTITUDE, &(-skew(&f_e)));
    set(&mut f, VELOCITY, VELOCITY, &(-2.0 * omega_ie));
    set(
        &mut f,
        VELOCITY,
        POSITION,
        &gravity_gradient(&inputs.position_ecef),
    );
    set(&mut f, VELOCITY, ACCEL_BIAS, &(-c));
    set(&mut f, POSITION, VELOCITY, &Matrix3::identity());
    if noise.accel_bias_correlation_time_s.is_finite() {
        set(
            &mut f,
            ACCEL_BIAS,
            ACCEL_BIAS,
            &(-Matrix3::identity() / noise.accel_bias_correlation_time_s),
        );
    }
    if noise.gyro_bias_correlation_time_s.is_finite() {
        set(
            &mut f,
            GYRO_BIAS,
            GYRO_BIAS,
            &(-Matrix3::identity() / noise.gyro_bias_correlation_time_s),
        );
    }
    f[(CLOCK_OFFSET, CLOCK_DRIFT)] = 1.0;
    let layout = Layout::for_size::<N>();
    if let Some(first) = layout.range_bias {
        for k in 0..layout.range_bias_slots {
            f[(first + k, first + k)] = -1.0 / noise.range_bias_correlation_time_s;
        }
    }
    if layout.scale_factors {
        set(
            &mut f,
            ATTITUDE,
            GYRO_SCALE_FACTOR,
            &(-c * Matrix3::from_diagonal(&inputs.angular_rate_b)),
        );
        set(
            &mut f,
            VELOCITY,
            ACCEL_SCALE_FACTOR,
            &(-c * Matrix3::from_diagonal(&inputs.specific_force_b)),
        );
    }
    f
}

/// The parts of one interval's discretisation that depend only on Δt and
/// the noise settings (two `exp` for the bias decays, two for their
/// variances): computed once and reused while Δt and the noise stay the
/// same, as they do at a fixed IMU rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Discretisation {
    dt: f64,
    noise: ProcessNoise,
    ba_decay: f64,
    bg_decay: f64,
    /// Discrete variances of the bias driving noise per interval.
    ba_variance: f64,
    bg_variance: f64,
    /// Decay and discrete variance of the pseudorange-bias states.
    rb_decay: f64,
    rb_variance: f64,
}

impl Discretisation {
    pub(super) fn new(noise: &ProcessNoise, dt: f64) -> Self {
        // The exact Gauss-Markov step of each bias (random walk for τ = ∞).
        let ba = discretise(
            noise.accel_bias_psd,
            noise.accel_bias_correlation_time_s,
            dt,
        );
        let bg = discretise(noise.gyro_bias_psd, noise.gyro_bias_correlation_time_s, dt);
        let rb = discretise(
            noise.range_bias_psd,
            noise.range_bias_correlation_time_s,
            dt,
        );
        Self {
            dt,
            noise: *noise,
            ba_decay: ba.decay,
            bg_decay: bg.decay,
            ba_variance: ba.drive_variance,
            bg_variance: bg.drive_variance,
            rb_decay: rb.decay,
            rb_variance: rb.drive_variance,
        }
    }

    /// Whether this discretisation is the one of (`noise`, `dt`).
    pub(super) fn is_for(&self, noise: &ProcessNoise, dt: f64) -> bool {
        self.dt == dt && self.noise == *noise
    }
}

/// The non-identity blocks of Φ = I + FΔt for one interval, stored
/// transposed (propagation multiplies by Φᵀ from the right, see
/// [`Transition::columns_into`]). The blocks with a known structure
/// are kept as their few parameters: I − Ω_ie Δt through ω_ie Δt, and
/// −[(Ĉ f̂ Δt)×] through Ĉ f̂ Δt.
struct Transition {
    /// ω_ie Δt.
    earth_angle: f64,
    /// Ĉ f̂ Δt, the specific-force velocity increment in ECEF.
    f_dt: Vector3<f64>,
    /// (−Ĉ Δt)ᵀ, the ψ-b_g and v-b_a blocks.
    minus_c_dt_t: Matrix3<f64>,
    /// (−Ĉ diag(ω̂) Δt)ᵀ.
    psi_sg_t: Matrix3<f64>,
    /// (Γ Δt)ᵀ.
    v_r_t: Matrix3<f64>,
    /// (−Ĉ diag(f̂) Δt)ᵀ.
    v_sa_t: Matrix3<f64>,
    dt: f64,
    ba_decay: f64,
    bg_decay: f64,
    rb_decay: f64,
}

impl Transition {
    fn new<const N: usize>(inputs: &SystemInputs, d: &Discretisation) -> Self {
        let dt = d.dt;
        let c_dt = inputs.c_b_e * dt;
        let (psi_sg_t, v_sa_t) = if Layout::for_size::<N>().scale_factors {
            (
                (-c_dt * Matrix3::from_diagonal(&inputs.angular_rate_b)).transpose(),
                (-c_dt * Matrix3::from_diagonal(&inputs.specific_force_b)).transpose(),
            )
        } else {
            (Matrix3::zeros(), Matrix3::zeros())
        };
        Self {
            earth_angle: EARTH_RATE_RAD_S * dt,
            f_dt: c_dt * inputs.specific_force_b,
            minus_c_dt_t: -c_dt.transpose(),
            psi_sg_t,
            // Γ is symmetric: no transpose needed.
            v_r_t: gravity_gradient(&inputs.position_ecef) * dt,
            v_sa_t,
            dt,
            ba_decay: d.ba_decay,
            bg_decay: d.bg_decay,
            rb_decay: d.rb_decay,
        }
    }

    /// Φᵀ as sparse columns, written over `out` (every entry the products
    /// read is rewritten: nothing zeroed per epoch). Column j of M Φᵀ is
    /// Σ_k M_{·k} Φ_jk over the listed (Φ_jk, k), in the order the
    /// products accumulate them; only the non-zeros of Φ are listed:
    ///
    /// - ψ: M_ψ (I − Ω_ie Δt)ᵀ + M_bg (−ĈΔt)ᵀ [+ M_sg (−Ĉ diag(ω̂) Δt)ᵀ];
    ///   with I − Ω_ie Δt = [[1, ωΔt, 0], [−ωΔt, 1, 0], [0, 0, 1]];
    /// - v: M_ψ (−[a×])ᵀ + M_v (I − 2Ω_ie Δt)ᵀ + M_r (ΓΔt)ᵀ + M_ba (−ĈΔt)ᵀ
    ///   [+ M_sa (−Ĉ diag(f̂) Δt)ᵀ], a = Ĉ f̂ Δt, −[a×] = [[0, a_z, −a_y],
    ///   [−a_z, 0, a_x], [a_y, −a_x, 0]];
    /// - r: M_r + Δt M_v; biases (sensor and range): decay; clock offset:
    ///   M_δc + Δt M_δċ; installation: itself (constants).
    fn columns_into<const N: usize>(&self, out: &mut Columns) {
        let mut n = 0;
        let mut set = |j: usize, terms: &[(f64, usize)]| {
            out.start[j] = n as u8;
            for &(a, k) in terms {
                out.coefficient[n] = a;
                out.source[n] = k as u8;
                n += 1;
            }
            out.end[j] = n as u8;
        };
        let (w, w2, a) = (self.earth_angle, 2.0 * self.earth_angle, &self.f_dt);
        let (bc, ba, bg, sa, sg) = (
            &self.minus_c_dt_t,
            ACCEL_BIAS,
            GYRO_BIAS,
            ACCEL_SCALE_FACTOR,
            GYRO_SCALE_FACTOR,
        );
        let g = &self.v_r_t;
        let (ps, ve, po) = (ATTITUDE, VELOCITY, POSITION);
        let layout = Layout::for_size::<N>();
        let scale = layout.scale_factors;
        // ψ columns. Row j of (−ĈΔt) is column j of its transpose `bc`.
        let psi_extra: [(f64, usize); 2] = [(w, ps + 1), (-w, ps)];
        for j in 0..3 {
            let mut terms = [(0.0, 0); 8];
            let mut n = 0;
            let mut push = |t: (f64, usize)| {
                terms[n] = t;
                n += 1;
            };
            push((1.0, ps + j));
            if j < 2 {
                push(psi_extra[j]);
            }
            for k in 0..3 {
                push((bc[(k, j)], bg + k));
            }
            if scale {
                for k in 0..3 {
                    push((self.psi_sg_t[(k, j)], sg + k));
                }
            }
            set(ps + j, &terms[..n]);
        }
        // v columns: Ω (two terms), −[a×] (two terms), Γ, −Ĉ, [−Ĉ diag(f̂)].
        let structured: [[(f64, usize); 4]; 3] = [
            [(1.0, ve), (w2, ve + 1), (a.z, ps + 1), (-a.y, ps + 2)],
            [(1.0, ve + 1), (-w2, ve), (-a.z, ps), (a.x, ps + 2)],
            [(1.0, ve + 2), (a.y, ps), (-a.x, ps + 1), (0.0, ps)],
        ];
        for j in 0..3 {
            let mut terms = [(0.0, 0); 13];
            let k0 = if j == 2 { 3 } else { 4 };
            terms[..k0].copy_from_slice(&structured[j][..k0]);
            let mut n = k0;
            for k in 0..3 {
                terms[n] = (g[(k, j)], po + k);
                terms[n + 1] = (bc[(k, j)], ba + k);
                n += 2;
            }
            if scale {
                for k in 0..3 {
                    terms[n] = (self.v_sa_t[(k, j)], sa + k);
                    n += 1;
                }
            }
            set(ve + j, &terms[..n]);
        }
        for j in 0..3 {
            set(po + j, &[(1.0, po + j), (self.dt, ve + j)]);
            set(ba + j, &[(self.ba_decay, ba + j)]);
            set(bg + j, &[(self.bg_decay, bg + j)]);
            if scale {
                set(sa + j, &[(1.0, sa + j)]);
                set(sg + j, &[(1.0, sg + j)]);
            }
        }
        set(CLOCK_OFFSET, &[(1.0, CLOCK_OFFSET), (self.dt, CLOCK_DRIFT)]);
        set(CLOCK_DRIFT, &[(1.0, CLOCK_DRIFT)]);
        for j in constant_states(layout) {
            set(j, &[(1.0, j)]);
        }
        if let Some(first) = layout.range_bias {
            for j in first..first + layout.range_bias_slots {
                set(j, &[(self.rb_decay, j)]);
            }
        }
    }

    /// Φ itself as sparse columns, written over `out` (the mirror of
    /// [`Self::columns_into`]: with these, the sparse products compute M Φ,
    /// column j being Σ_k M_{·k} Φ_kj over the non-zeros of column j of Φ),
    /// for the smoother's backward pass, which needs Φᵀ λ and Φᵀ Λ Φ.
    /// Column j of Φ:
    ///
    /// - ψ_j: (I − Ω_ie Δt)_{·j} on the ψ rows, (−[a×])_{·j} on the v rows;
    /// - v_j: (I − 2Ω_ie Δt)_{·j} on the v rows, Δt on r_j;
    /// - r_j: (ΓΔt)_{·j} on the v rows, 1 on r_j;
    /// - b_a,j (b_g,j): (−ĈΔt)_{·j} on the v (ψ) rows, the decay on itself;
    /// - s_a,j (s_g,j): the scale-factor blocks' column on the v (ψ) rows, 1;
    /// - clock offset: 1; clock drift: Δt on the offset, 1; installation: 1;
    ///   range biases: decay.
    fn phi_columns_into<const N: usize>(&self, out: &mut Columns) {
        let mut n = 0;
        let mut set = |j: usize, terms: &[(f64, usize)]| {
            out.start[j] = n as u8;
            for &(a, k) in terms {
                out.coefficient[n] = a;
                out.source[n] = k as u8;
                n += 1;
            }
            out.end[j] = n as u8;
        };
        let (w, w2, a) = (self.earth_angle, 2.0 * self.earth_angle, &self.f_dt);
        let bc = &self.minus_c_dt_t;
        let (ps, ve, po) = (ATTITUDE, VELOCITY, POSITION);
        let (ba, bg, sa, sg) = (ACCEL_BIAS, GYRO_BIAS, ACCEL_SCALE_FACTOR, GYRO_SCALE_FACTOR);
        let layout = Layout::for_size::<N>();
        // ψ columns: (I − Ω Δt) = [[1, w, 0], [−w, 1, 0], [0, 0, 1]] and
        // −[a×] = [[0, a_z, −a_y], [−a_z, 0, a_x], [a_y, −a_x, 0]].
        let psi: [[(f64, usize); 4]; 3] = [
            [(1.0, ps), (-w, ps + 1), (-a.z, ve + 1), (a.y, ve + 2)],
            [(w, ps), (1.0, ps + 1), (a.z, ve), (-a.x, ve + 2)],
            [(1.0, ps + 2), (-a.y, ve), (a.x, ve + 1), (0.0, ps)],
        ];
        // v columns: (I − 2Ω Δt) and Δt on r_j.
        let vel: [[(f64, usize); 3]; 3] = [
            [(1.0, ve), (-w2, ve + 1), (self.dt, po)],
            [(w2, ve), (1.0, ve + 1), (self.dt, po + 1)],
            [(1.0, ve + 2), (self.dt, po + 2), (0.0, ve)],
        ];
        for j in 0..3 {
            set(ps + j, &psi[j]);
            set(ve + j, &vel[j]);
            let g = &self.v_r_t;
            set(
                po + j,
                &[
                    (g[(0, j)], ve),
                    (g[(1, j)], ve + 1),
                    (g[(2, j)], ve + 2),
                    (1.0, po + j),
                ],
            );
            // Column j of −ĈΔt is row j of its stored transpose.
            let c = |i: usize| bc[(j, i)];
            set(
                ba + j,
                &[
                    (c(0), ve),
                    (c(1), ve + 1),
                    (c(2), ve + 2),
                    (self.ba_decay, ba + j),
                ],
            );
            set(
                bg + j,
                &[
                    (c(0), ps),
                    (c(1), ps + 1),
                    (c(2), ps + 2),
                    (self.bg_decay, bg + j),
                ],
            );
            if layout.scale_factors {
                let (va, pg) = (&self.v_sa_t, &self.psi_sg_t);
                set(
                    sa + j,
                    &[
                        (va[(j, 0)], ve),
                        (va[(j, 1)], ve + 1),
                        (va[(j, 2)], ve + 2),
                        (1.0, sa + j),
                    ],
                );
                set(
                    sg + j,
                    &[
                        (pg[(j, 0)], ps),
                        (pg[(j, 1)], ps + 1),
                        (pg[(j, 2)], ps + 2),
                        (1.0, sg + j),
                    ],
                );
            }
        }
        set(CLOCK_OFFSET, &[(1.0, CLOCK_OFFSET)]);
        set(CLOCK_DRIFT, &[(self.dt, CLOCK_OFFSET), (1.0, CLOCK_DRIFT)]);
        for j in constant_states(layout) {
            set(j, &[(1.0, j)]);
        }
        if let Some(first) = layout.range_bias {
            for j in first..first + layout.range_bias_slots {
                set(j, &[(self.rb_decay, j)]);
            }
        }
    }
}

/// The smoother's backward step over one interval (the adjoint of the
/// propagation): λ ← Φᵀ λ (as the row λᵀ Φ) and R = R′ Φ for the factor
/// R′ of the adjoint Λ′ = R′ᵀ R′ after the step (so that Λ = Φᵀ Λ′ Φ), one
/// sparse product by the columns of Φ.
fn adjoint<const N: usize>(
    lambda: &mut SVector<f64, N>,
    factor: Option<super::smoother::Factor<'_, N>>,
    phi: &Transition,
    columns: &mut Columns,
) {
    phi.phi_columns_into::<N>(columns);
    let (source, mut row) = (lambda.transpose(), lambda.transpose());
    sparse_product::<1, N, false>(columns, &source.data.0, row.as_mut_slice());
    *lambda = row.transpose();
    if let Some((after, factor)) = factor {
        column_product(columns, after, factor);
    }
}

/// The filter's own propagation as the smoother reverses it and carries
/// its smoothed quantities forward over it: a step is the linearisation
/// point and the interval; Φ and Q are rebuilt from them with the run's
/// process noise.
#[derive(Debug, Clone)]
pub struct InsStepModel {
    noise: ProcessNoise,
    discretisation: Option<Discretisation>,
    /// Φ (or Φᵀ) by columns, rewritten at every step.
    columns: Columns,
}

impl InsStepModel {
    /// The model of a filter with process noise `noise`.
    pub fn new(noise: ProcessNoise) -> Self {
        Self {
            noise,
            discretisation: None,
            columns: Columns::new(),
        }
    }

    fn transition<const N: usize>(
        &mut self,
        step: &(SystemInputs, f64),
    ) -> (Transition, Discretisation) {
        let d = match self.discretisation {
            Some(d) if d.is_for(&self.noise, step.1) => d,
            _ => {
                let d = Discretisation::new(&self.noise, step.1);
                self.discretisation = Some(d);
                d
            }
        };
        (Transition::new::<N>(&step.0, &d), d)
    }
}

impl<const N: usize> super::smoother::StepModel<N> for InsStepModel {
    type Step = (SystemInputs, f64);

    fn carry(
        &mut self,
        step: &Self::Step,
        root: Option<super::smoother::Root<'_, N>>,
        y: &mut SVector<f64, N>,
        lambda_after: &SVector<f64, N>,
    ) {
        let (phi, d) = self.transition::<N>(step);
        phi.columns_into::<N>(&mut self.columns);
        // Z′ = Z Φᵀ + R′ Q and y ← Φ y + Q λ′ ((Φ y)ᵀ = yᵀ Φᵀ): the
        // products with Φ first, then Q's terms, formed once for both.
        let mut root = root.map(|(z, factor, next)| {
            column_product(&self.columns, z, next);
            (factor.as_slice(), next.as_mut_slice())
        });
        let (source, mut row) = (y.transpose(), y.transpose());
        sparse_product::<1, N, false>(&self.columns, &source.data.0, row.as_mut_slice());
        *y = row.transpose();
        // Columns of the column-major matrices are contiguous: the plain
        // loop vectorises where nalgebra's strided `axpy` does not (same
        // sums, same rounding).
        for_each_process_noise::<N>(&d, &step.0, |i, j, q| {
            if let Some((source, target)) = root.as_mut() {
                let from = &source[i * N..(i + 1) * N];
                for (t, f) in target[j * N..(j + 1) * N].iter_mut().zip(from) {
                    *t += q * f;
                }
            }
            y[i] += q * lambda_after[j];
        });
    }

    fn adjoint(
        &mut self,
        step: &Self::Step,
        lambda: &mut SVector<f64, N>,
        factor: Option<super::smoother::Factor<'_, N>>,
    ) {
        let (phi, _) = self.transition::<N>(step);
        adjoint(lambda, factor, &phi, &mut self.columns);
    }
}

/// Working storage of [`propagate_with`], kept by a filter between epochs
/// so that nothing is zeroed or allocated per epoch.
#[derive(Debug, Clone)]
pub(super) struct Scratch<const N: usize> {
    columns: Columns,
    b_t: SMatrix<f64, N, N>,
}

impl<const N: usize> Scratch<N> {
    pub(super) fn new() -> Self {
        Self {
            columns: Columns::new(),
            b_t: SMatrix::zeros(),
        }
    }
}

/// [`propagate`] with the caller's working storage.
pub(super) fn propagate_with<const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    inputs: &SystemInputs,
    d: &Discretisation,
    scratch: &mut Scratch<N>,
) {
    let phi = Transition::new::<N>(inputs, d);
    phi.columns_into::<N>(&mut scratch.columns);
    if x.iter().any(|v| *v != 0.0) {
        // (Φ x)ᵀ = xᵀ Φᵀ.
        let (source, mut row) = (x.transpose(), x.transpose());
        sparse_product::<1, N, false>(&scratch.columns, &source.data.0, row.as_mut_slice());
        *x = row.transpose();
    }
    covariance_product(&scratch.columns, p, &mut scratch.b_t);
    add_process_noise(p, d, inputs);
}

/// The states whose Φ is 1 and couples to nothing: the installation
/// constants and the inter-system biases (random walks: their noise is in
/// Q alone).
fn constant_states(layout: Layout) -> impl Iterator<Item = usize> {
    [
        (layout.installation, INSTALLATION_STATES),
        (layout.inter_system_bias, INTER_SYSTEM_BIAS_STATES),
    ]
    .into_iter()
    .filter_map(|(first, len)| first.map(|f| f..f + len))
    .flatten()
}

/// Most states of a filter (every optional block).
const MAX_STATES: usize = Layout::size(true, true, true, RangeBiasSlots::EverySatellite);
/// Most non-zeros of Φ (the 73-state filter has 132: the 45-state one's
/// 104, the 42-state one's 101 and one per inter-system bias, with 28 more
/// range-bias slots, one term each).
const MAX_TERMS: usize = 132;

/// A sparse matrix by columns: column j holds the terms
/// `start[j]..end[j]`, each a coefficient and the row it multiplies (here:
/// Φᵀ, so column j lists row j of Φ).
#[derive(Debug, Clone)]
struct Columns {
    coefficient: [f64; MAX_TERMS],
    source: [u8; MAX_TERMS],
    start: [u8; MAX_STATES],
    end: [u8; MAX_STATES],
}

impl Columns {
    fn new() -> Self {
        Self {
            coefficient: [0.0; MAX_TERMS],
            source: [0; MAX_TERMS],
            start: [0; MAX_STATES],
            end: [0; MAX_STATES],
        }
    }
}

/// Column j of `dst` (R × N, by columns) ← Σ coefficient · column `source`
/// of `src`, over the terms of column j of `columns`: M Φᵀ. Each output
/// column is accumulated in registers and stored once. `TRANSPOSED`:
/// stored as row j instead (R = N), the transpose folded into the stores.
/// The terms are walked as slices and the source columns read from the
/// fixed-size array of columns (one index check per term, not three).
#[inline(always)]
fn sparse_product_with<const R: usize, const N: usize, const TRANSPOSED: bool, const FMA: bool>(
    columns: &Columns,
    src: &[[f64; R]; N],
    dst: &mut [f64],
) {
    for j in 0..N {
        let (start, end) = (columns.start[j] as usize, columns.end[j] as usize);
        let terms = columns.coefficient[start..end]
            .iter()
            .zip(&columns.source[start..end]);
        let mut acc = [0.0; R];
        for (&a, &k) in terms {
            let c = &src[k as usize];
            for i in 0..R {
                acc[i] = if FMA {
                    a.mul_add(c[i], acc[i])
                } else {
                    acc[i] + a * c[i]
                };
            }
        }
        if TRANSPOSED {
            for (i, v) in acc.iter().enumerate() {
                dst[j + i * N] = *v;
            }
        } else {
            dst[j * R..(j + 1) * R].copy_from_slice(&acc);
        }
    }
}

/// [`sparse_product_with`] without fused multiply-adds, for any target.
fn sparse_product<const R: usize, const N: usize, const TRANSPOSED: bool>(
    columns: &Columns,
    src: &[[f64; R]; N],
    dst: &mut [f64],
) {
    sparse_product_with::<R, N, TRANSPOSED, false>(columns, src, dst);
}

/// P ← Φ P Φᵀ. With B = P Φᵀ, Φ P Φᵀ = Φ B = (Bᵀ Φᵀ)ᵀ, and Bᵀ Φᵀ is
/// symmetric, so P ← Bᵀ Φᵀ: two sparse products by columns, the first
/// storing its columns as the rows of Bᵀ (the transpose folded into the
/// stores). The dominant cost of the filter, so it is also compiled for
/// AVX2 with FMA and that version chosen at run time (the wheel targets
/// baseline x86-64); a fused multiply-add rounds once instead of twice, so
/// the two versions agree to rounding, not bitwise.
#[multiversion::multiversion(targets("x86_64+avx2+fma"))]
fn covariance_product<const N: usize>(
    columns: &Columns,
    p: &mut SMatrix<f64, N, N>,
    b_t: &mut SMatrix<f64, N, N>,
) {
    const FMA: bool = multiversion::target::selected_target!().supports_feature_str("fma");
    sparse_product_with::<N, N, true, FMA>(columns, &p.data.0, b_t.as_mut_slice());
    sparse_product_with::<N, N, false, FMA>(columns, &b_t.data.0, p.as_mut_slice());
}

/// M ← M S for a sparse S given by its columns (Φᵀ or Φ): one product of
/// [`covariance_product`], for the smoother's factor and root (compiled for
/// AVX2 with FMA as well, chosen at run time).
#[multiversion::multiversion(targets("x86_64+avx2+fma"))]
fn column_product<const N: usize>(
    columns: &Columns,
    m: &SMatrix<f64, N, N>,
    product: &mut SMatrix<f64, N, N>,
) {
    const FMA: bool = multiversion::target::selected_target!().supports_feature_str("fma");
    sparse_product_with::<N, N, false, FMA>(columns, &m.data.0, product.as_mut_slice());
}

/// P ← P + Q for one interval.
fn add_process_noise<const N: usize>(
    p: &mut SMatrix<f64, N, N>,
    d: &Discretisation,
    inputs: &SystemInputs,
) {
    for_each_process_noise::<N>(d, inputs, |i, j, q| p[(i, j)] += q);
}

/// Calls `f(i, j, Q_ij)` for every non-zero of Q over one interval (Groves
/// eq. 14.82 plus the exact clock block), both triangles; the attitude and
/// velocity blocks add the input-shaped noise of the errors the state
/// lacks at this step's `inputs`, Ĉ diag(q) Ĉᵀ Δt ([`input_noise`]).
fn for_each_process_noise<const N: usize>(
    d: &Discretisation,
    inputs: &SystemInputs,
    mut f: impl FnMut(usize, usize, f64),
) {
    let (noise, dt) = (&d.noise, d.dt);
    let layout = Layout::for_size::<N>();
    if noise.input_errors.is_active() {
        let (qa, qg) = noise
            .input_errors
            .body_psd(&inputs.specific_force_b, &inputs.angular_rate_b);
        let (qa, qg) = (
            input_noise::to_ecef(&inputs.c_b_e, &qa),
            input_noise::to_ecef(&inputs.c_b_e, &qg),
        );
        for i in 0..3 {
            for j in 0..3 {
                f(ATTITUDE + i, ATTITUDE + j, qg[(i, j)] * dt);
                f(VELOCITY + i, VELOCITY + j, qa[(i, j)] * dt);
            }
        }
    }
    for k in 0..3 {
        f(ATTITUDE + k, ATTITUDE + k, noise.gyro_white_psd * dt);
        f(VELOCITY + k, VELOCITY + k, noise.accel_white_psd * dt);
        f(ACCEL_BIAS + k, ACCEL_BIAS + k, d.ba_variance);
        f(GYRO_BIAS + k, GYRO_BIAS + k, d.bg_variance);
        if layout.scale_factors {
            let (a, g) = (ACCEL_SCALE_FACTOR + k, GYRO_SCALE_FACTOR + k);
            f(a, a, noise.accel_scale_factor_psd * dt);
            f(g, g, noise.gyro_scale_factor_psd * dt);
        }
    }
    let sf = noise.clock_frequency_psd;
    f(
        CLOCK_OFFSET,
        CLOCK_OFFSET,
        noise.clock_phase_psd * dt + sf * dt * dt * dt / 3.0,
    );
    f(CLOCK_OFFSET, CLOCK_DRIFT, 0.5 * sf * dt * dt);
    f(CLOCK_DRIFT, CLOCK_OFFSET, 0.5 * sf * dt * dt);
    f(CLOCK_DRIFT, CLOCK_DRIFT, sf * dt);
    if let Some(first) = layout.inter_system_bias {
        for j in first..first + INTER_SYSTEM_BIAS_STATES {
            f(j, j, noise.inter_system_bias_psd * dt);
        }
    }
    if let Some(first) = layout.range_bias {
        for j in first..first + layout.range_bias_slots {
            f(j, j, d.rb_variance);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::euler_to_dcm;
    use crate::geodesy::{geodetic_to_ecef, gravity_ecef, Geodetic};

    /// x ← Φ x, P ← Φ P Φᵀ + Q over one interval, with fresh storage.
    fn propagate<const N: usize>(
        x: &mut SVector<f64, N>,
        p: &mut SMatrix<f64, N, N>,
        inputs: &SystemInputs,
        d: &Discretisation,
    ) {
        propagate_with(x, p, inputs, d, &mut Scratch::new());
    }

    fn inputs() -> SystemInputs {
        SystemInputs {
            c_b_e: euler_to_dcm(0.3, -0.2, 1.1),
            specific_force_b: Vector3::new(1.2, -0.4, -9.7),
            angular_rate_b: Vector3::new(0.05, -0.02, 0.3),
            position_ecef: geodetic_to_ecef(Geodetic::new(0.76, 0.025, 150.0)),
        }
    }

    fn noise(tau: f64) -> ProcessNoise {
        ProcessNoise {
            accel_white_psd: 1e-4,
            gyro_white_psd: 1e-8,
            accel_bias_psd: 1e-7,
            accel_bias_correlation_time_s: tau,
            gyro_bias_psd: 1e-11,
            gyro_bias_correlation_time_s: 2.0 * tau,
            clock_phase_psd: 0.01,
            clock_frequency_psd: 0.04,
            accel_scale_factor_psd: 1e-9,
            gyro_scale_factor_psd: 2e-9,
            range_bias_psd: 0.05,
            range_bias_correlation_time_s: 0.5 * tau,
            inter_system_bias_psd: 0.03,
            input_errors: InputErrorNoise {
                errors: super::super::input_noise::UnmodelledErrors {
                    accel_scale_factor: 1e-3,
                    accel_misalignment: 2e-3,
                    accel_nonlinearity_per_m_s2: 1e-4,
                    gyro_scale_factor: 3e-3,
                    gyro_misalignment: 4e-3,
                    gyro_g_sensitivity_rad_s_per_m_s2: 1e-4,
                },
                correlation_time_s: 10.0,
                reference_specific_force_b: Vector3::new(0.0, 0.1, -9.8),
            },
        }
    }

    fn random_spd<const N: usize>() -> SMatrix<f64, N, N> {
        let a = SMatrix::<f64, N, N>::from_fn(|i, j| ((i * 7 + j * 13) % 11) as f64 / 11.0 - 0.4);
        a * a.transpose() + SMatrix::identity()
    }

    /// Φ = I + FΔt with the Gauss-Markov decays e^{−Δt/τ} on the diagonal
    /// of the bias and range-bias states: the dense reference.
    fn dense_transition<const N: usize>(
        inp: &SystemInputs,
        nz: &ProcessNoise,
        dt: f64,
    ) -> SMatrix<f64, N, N> {
        let mut phi = SMatrix::<f64, N, N>::identity() + system_matrix::<N>(inp, nz) * dt;
        let decay = |tau: f64| crate::gauss_markov::discretise(0.0, tau, dt).decay;
        for k in 0..3 {
            phi[(ACCEL_BIAS + k, ACCEL_BIAS + k)] = decay(nz.accel_bias_correlation_time_s);
            phi[(GYRO_BIAS + k, GYRO_BIAS + k)] = decay(nz.gyro_bias_correlation_time_s);
        }
        if let Some(first) = Layout::for_size::<N>().range_bias {
            for j in first..N {
                phi[(j, j)] = decay(nz.range_bias_correlation_time_s);
            }
        }
        phi
    }

    /// Q over one interval as a dense matrix.
    fn dense_noise<const N: usize>(
        nz: &ProcessNoise,
        inp: &SystemInputs,
        dt: f64,
    ) -> SMatrix<f64, N, N> {
        let mut q = SMatrix::zeros();
        add_process_noise(&mut q, &Discretisation::new(nz, dt), inp);
        q
    }

    /// The structured Φ P Φᵀ + Q equals the dense product with the dense Φ
    /// and Q.
    fn structured_equals_dense<const N: usize>(tau: f64) {
        let (inp, nz, dt) = (inputs(), noise(tau), 0.01);
        let (phi, q) = (
            dense_transition::<N>(&inp, &nz, dt),
            dense_noise::<N>(&nz, &inp, dt),
        );
        let p0 = random_spd::<N>();
        let dense = phi * p0 * phi.transpose() + q;
        let mut p = p0;
        let mut x = SVector::<f64, N>::from_fn(|i, _| i as f64 * 0.1);
        let x_dense = phi * x;
        propagate(&mut x, &mut p, &inp, &Discretisation::new(&nz, dt));
        assert!((p - dense).abs().max() < 1e-12 * dense.abs().max(), "P");
        assert!((x - x_dense).abs().max() < 1e-13, "x");
        assert!((p - p.transpose()).abs().max() < 1e-13);
    }

    /// The adjoint step equals Φᵀ λ and R′ Φ with the dense Φ (so that the
    /// adjoint Λ′ = R′ᵀ R′ becomes Φᵀ Λ′ Φ).
    fn adjoint_equals_dense<const N: usize>(tau: f64) {
        let (inp, nz, dt) = (inputs(), noise(tau), 0.01);
        let phi = dense_transition::<N>(&inp, &nz, dt);
        let after = random_spd::<N>();
        let mut lambda = SVector::<f64, N>::from_fn(|i, _| (i as f64 * 0.37).sin());
        let mut factor = SMatrix::<f64, N, N>::zeros();
        let (l_dense, r_dense) = (phi.transpose() * lambda, after * phi);
        let d = Discretisation::new(&nz, dt);
        let mut alone = lambda;
        let phi = Transition::new::<N>(&inp, &d);
        adjoint(
            &mut lambda,
            Some((&after, &mut factor)),
            &phi,
            &mut Columns::new(),
        );
        assert!((lambda - l_dense).abs().max() < 1e-13 * l_dense.abs().max().max(1.0));
        assert!((factor - r_dense).abs().max() < 1e-12 * r_dense.abs().max());
        // Without the factor, λ is the same bit for bit.
        adjoint(&mut alone, None, &phi, &mut Columns::new());
        assert_eq!(alone, lambda);
    }

    #[test]
    fn adjoint_step_matches_dense() {
        adjoint_equals_dense::<17>(300.0);
        adjoint_equals_dense::<23>(f64::INFINITY);
        adjoint_equals_dense::<29>(300.0);
        adjoint_equals_dense::<35>(300.0);
        adjoint_equals_dense::<24>(300.0);
        adjoint_equals_dense::<42>(300.0);
        adjoint_equals_dense::<20>(300.0);
        adjoint_equals_dense::<45>(300.0);
    }

    /// The smoother's forward step: Z′ = Z Φᵀ + R′ Q and y′ = Φ y + Q λ′,
    /// against the dense Φ and Q.
    fn carry_equals_dense<const N: usize>(tau: f64) {
        use super::super::smoother::StepModel;
        let (inp, nz, dt) = (inputs(), noise(tau), 0.01);
        let (phi, q) = (
            dense_transition::<N>(&inp, &nz, dt),
            dense_noise::<N>(&nz, &inp, dt),
        );
        let after = random_spd::<N>() * 0.3;
        let z0 = SMatrix::<f64, N, N>::from_fn(|i, j| ((i * 3 + j * 5) % 7) as f64 - 3.0);
        let y0 = SVector::<f64, N>::from_fn(|i, _| (i as f64 * 0.7).cos());
        let lambda = SVector::<f64, N>::from_fn(|i, _| (i as f64 * 0.37).sin());
        let z_dense = z0 * phi.transpose() + after * q;
        let y_dense = phi * y0 + q * lambda;
        let (mut z, mut y) = (SMatrix::<f64, N, N>::zeros(), y0);
        InsStepModel::new(nz).carry(&(inp, dt), Some((&z0, &after, &mut z)), &mut y, &lambda);
        assert!((z - z_dense).abs().max() < 1e-12 * z_dense.abs().max(), "Z");
        assert!((y - y_dense).abs().max() < 1e-12 * y_dense.abs().max(), "y");
        // Without the root, y is the same bit for bit.
        let mut alone = y0;
        InsStepModel::new(nz).carry(&(inp, dt), None, &mut alone, &lambda);
        assert_eq!(alone, y);
    }

    #[test]
    fn carry_step_matches_dense() {
        carry_equals_dense::<17>(300.0);
        carry_equals_dense::<23>(f64::INFINITY);
        carry_equals_dense::<29>(300.0);
        carry_equals_dense::<35>(300.0);
        carry_equals_dense::<30>(300.0);
        carry_equals_dense::<42>(300.0);
        carry_equals_dense::<45>(300.0);
    }

    #[test]
    fn structured_propagation_matches_dense() {
        structured_equals_dense::<17>(300.0);
        structured_equals_dense::<17>(f64::INFINITY);
        structured_equals_dense::<23>(300.0);
        structured_equals_dense::<29>(300.0);
        structured_equals_dense::<35>(300.0);
        structured_equals_dense::<24>(300.0);
        structured_equals_dense::<30>(f64::INFINITY);
        structured_equals_dense::<36>(300.0);
        structured_equals_dense::<42>(300.0);
        // With the inter-system biases: base, + range biases, + installation, all.
        structured_equals_dense::<20>(300.0);
        structured_equals_dense::<32>(300.0);
        structured_equals_dense::<27>(f64::INFINITY);
        structured_equals_dense::<45>(300.0);
    }

    /// A filter's kept working storage gives what fresh storage gives,
    /// epoch after epoch (nothing stale survives between epochs).
    #[test]
    fn kept_scratch_equals_fresh_scratch() {
        fn check<const N: usize>() {
            let nz = noise(300.0);
            let d = Discretisation::new(&nz, 0.01);
            let mut scratch = Scratch::<N>::new();
            let (mut p_kept, mut p_fresh) = (random_spd::<N>(), random_spd::<N>());
            for k in 0..5 {
                let mut inp = inputs();
                inp.specific_force_b.x += k as f64;
                inp.c_b_e = crate::attitude::euler_to_dcm(0.1 * k as f64, -0.2, 1.1);
                let (mut x1, mut x2) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
                propagate_with(&mut x1, &mut p_kept, &inp, &d, &mut scratch);
                propagate(&mut x2, &mut p_fresh, &inp, &d);
                assert_eq!(p_kept, p_fresh, "epoch {k}");
            }
        }
        check::<17>();
        check::<35>();
    }

    /// Γ against a central difference of the J2 gravity model the INS uses
    /// (J2 adds ~1e-3 relative, far below what the filter needs).
    #[test]
    fn gravity_gradient_matches_numerical_derivative() {
        let r = inputs().position_ecef;
        let g = gravity_gradient(&r);
        for j in 0..3 {
            let mut d = Vector3::zeros();
            d[j] = 1.0;
            let col = (gravity_ecef(&(r + d)) - gravity_ecef(&(r - d))) / 2.0;
            assert!((g.column(j) - col).norm() < 1e-2 * g.norm(), "column {j}");
        }
    }

    /// F against a numerical linearisation of the ECEF velocity equation
    /// v̇ = Ĉ f̂ + g(r) − 2Ω v with Ĉ = (I + [ψ×])C, f̂ = f − δb_a − diag(f)δs_a.
    #[test]
    fn velocity_rows_match_the_perturbed_dynamics() {
        let inp = inputs();
        let f = system_matrix::<23>(&inp, &noise(100.0));
        let omega = skew(&Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S));
        let v = Vector3::new(10.0, -3.0, 1.0);
        let vdot = |x: &SVector<f64, 23>| {
            let psi = x.fixed_rows::<3>(ATTITUDE).into_owned();
            let c = crate::attitude::rotation_vector_to_dcm(&psi) * inp.c_b_e;
            let ba = x.fixed_rows::<3>(ACCEL_BIAS).into_owned();
            let sa = x.fixed_rows::<3>(ACCEL_SCALE_FACTOR).into_owned();
            let fb = inp.specific_force_b - ba - inp.specific_force_b.component_mul(&sa);
            let r = inp.position_ecef + x.fixed_rows::<3>(POSITION);
            let vv = v + x.fixed_rows::<3>(VELOCITY);
            c * fb + gravity_ecef(&r) - 2.0 * omega * vv
        };
        let x0 = SVector::<f64, 23>::zeros();
        for j in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 17, 18, 19] {
            let h = if (6..9).contains(&j) { 1.0 } else { 1e-6 };
            let mut xp = x0;
            xp[j] = h;
            let mut xm = x0;
            xm[j] = -h;
            let col = (vdot(&xp) - vdot(&xm)) / (2.0 * h);
            let tol = if (6..9).contains(&j) {
                1e-7
            } else {
                1e-7 * col.norm().max(1.0)
            };
            assert!(
                (f.fixed_view::<3, 1>(VELOCITY, j) - col).norm() < tol,
                "column {j}: {} vs {}",
                f.fixed_view::<3, 1>(VELOCITY, j),
                col
            );
        }
    }
}
