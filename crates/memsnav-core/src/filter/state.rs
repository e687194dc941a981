//! Named indices of the error state (method §5) and its typed wrapper.
//!
//! | indices | state | unit |
//! |---|---|---|
//! | 0-2 | attitude error ψ (Ĉ = (I + [ψ×]) C), ECEF axes | rad |
//! | 3-5 | velocity error δv^e | m/s |
//! | 6-8 | position error δr^e | m |
//! | 9-11 | accelerometer bias b_a, body axes | m/s² |
//! | 12-14 | gyro bias b_g, body axes | rad/s |
//! | 15 | receiver clock offset δc (c·δt) | m |
//! | 16 | receiver clock drift δċ | m/s |
//! | 17-19 | accelerometer scale-factor error s_a (optional) | 1 |
//! | 20-22 | gyro scale-factor error s_g (optional) | 1 |
//! | next 7 | installation (optional): lever arm (3, body axes, m), IMU time offset (s), GNSS velocity latency (s), mounting boresight pitch and yaw (rad) | see [`Installation`] |
//! | next 3 | inter-system biases (optional): Galileo, BeiDou and GLONASS pseudoranges minus GPS's, beyond the common receiver clock | m |
//! | last 12 or 40 | pseudorange bias of the satellite in each slot (optional, [`RangeBiasSlots`]) | m |
//!
//! The optional states are a compile-time extension selected by the size
//! `N` alone ([`Layout::of`]): [`BASE_STATES`] (17), [`WITH_SCALE_FACTORS`]
//! (23), [`WITH_RANGE_BIASES`] (29: the base plus [`RANGE_BIAS_SLOTS`]
//! per-satellite pseudorange biases) and [`WITH_ALL`] (35: both), each
//! also with the [`INSTALLATION_STATES`] (24, 30, 36, 42), and each of
//! those with the [`INTER_SYSTEM_BIAS_STATES`] (+3); and each without
//! range biases also with [`EVERY_SATELLITE_SLOTS`] (+40). Every
//! combination has its own size ([`Layout::size`]). A run picks its blocks at run time
//! ([`StateBlocks`]) and reaches the filter of that size through
//! [`StateBlocks::dispatch`], the one place a size is chosen.
//! Misalignments and nonlinearity are not states; the filters absorb them
//! as noise shaped by the sensed motion ([`super::input_noise`]).

use nalgebra::{SVector, Vector3};

/// Attitude error ψ, rad.
pub const ATTITUDE: usize = 0;
/// Velocity error δv^e, m/s.
pub const VELOCITY: usize = 3;
/// Position error δr^e, m.
pub const POSITION: usize = 6;
/// Accelerometer bias, m/s².
pub const ACCEL_BIAS: usize = 9;
/// Gyro bias, rad/s.
pub const GYRO_BIAS: usize = 12;
/// Receiver clock offset, m.
pub const CLOCK_OFFSET: usize = 15;
/// Receiver clock drift, m/s.
pub const CLOCK_DRIFT: usize = 16;
/// Accelerometer scale-factor error (only when `N` = [`WITH_SCALE_FACTORS`]).
pub const ACCEL_SCALE_FACTOR: usize = 17;
/// Gyro scale-factor error (only when `N` = [`WITH_SCALE_FACTORS`]).
pub const GYRO_SCALE_FACTOR: usize = 20;
/// Size of the base state.
pub const BASE_STATES: usize = 17;
/// Size of the state with accelerometer and gyro scale factors.
pub const WITH_SCALE_FACTORS: usize = 23;
/// Satellites whose pseudorange bias a filter with shared range-bias slots
/// carries at once ([`RangeBiasSlots::Shared`]): a receiver sees 8-12 GPS
/// satellites above a 10° mask.
pub const RANGE_BIAS_SLOTS: usize = 12;
/// Range-bias slots of a filter with a slot for every satellite
/// ([`RangeBiasSlots::EverySatellite`]): GPS, Galileo, BeiDou and GLONASS
/// together put 30-40 satellites above a 10° mask.
pub const EVERY_SATELLITE_SLOTS: usize = 40;
/// The most range-bias slots any layout has (the size of the per-slot
/// arrays).
pub const MAX_RANGE_BIAS_SLOTS: usize = EVERY_SATELLITE_SLOTS;
/// Size of the base state plus the per-satellite range biases.
pub const WITH_RANGE_BIASES: usize = BASE_STATES + RANGE_BIAS_SLOTS;
/// Size of the state with scale factors and range biases.
pub const WITH_ALL: usize = WITH_SCALE_FACTORS + RANGE_BIAS_SLOTS;
/// States of the installation block: how the IMU sits in the vehicle and
/// relative to the antenna, estimated instead of assumed.
pub const INSTALLATION_STATES: usize = 7;

/// States of the inter-system-bias block: Galileo's, BeiDou's and
/// GLONASS's pseudorange bias relative to GPS, one per system in the order
/// of [`crate::gnss::INTER_SYSTEM_BIAS_SYSTEMS`] (a multi-GNSS receiver's
/// one clock plus an offset per other system; Groves §9.4.2.3 and
/// §14.3.3). GLONASS's absorbs the mean of the receiver's inter-frequency
/// biases; each slot's departure from it stays in the range-bias states
/// or the pseudorange noise.
///
/// One block for every system beyond GPS, rather than a GLONASS state only
/// in runs that have GLONASS: the layout is read from the size `N` alone,
/// and a block of 2 or 3 would give clashing sizes (6 + 3 = 7 + 2, 12 + 3 =
/// 6 + 7 + 2). A GPS-only run has no block at all; a run that combines
/// systems carries the states of those it lacks at their prior, one state
/// more than before GLONASS was added (measured in CHANGELOG.md).
pub const INTER_SYSTEM_BIAS_STATES: usize = 3;

/// Offsets of the installation states inside their block. Each is an error
/// (estimate − truth) of a constant:
///
/// - lever arm δl: the antenna's position from the IMU, body axes, m;
/// - time offset δt_o: added to the IMU time stamps (the same sense as
///   `[imu] time_offset_s`), s;
/// - velocity latency δL: the fixes' velocity given at t is the antenna's
///   at t − L, s;
/// - mounting boresight δμ = (0, δμ_y, δμ_z): the vehicle axes are
///   (I − [μ×]) times the body axes (a small rotation left after the
///   configured mounting), rad. Pitch and yaw only: the non-holonomic
///   constraint that reveals them cannot see a roll about the forward axis
///   (it leaves the body velocity (v, 0, 0) as it is), so the roll stays
///   the configured one (Shin 2001 §4.3 likewise estimates two angles).
pub struct Installation;

impl Installation {
    /// Lever arm, 3 states.
    pub const LEVER_ARM: usize = 0;
    /// IMU time offset.
    pub const TIME_OFFSET: usize = 3;
    /// GNSS velocity latency.
    pub const VELOCITY_LATENCY: usize = 4;
    /// Mounting boresight pitch then yaw, 2 states.
    pub const MOUNTING: usize = 5;
}

/// The per-satellite pseudorange-bias states a state carries. A satellite
/// seen for the first time takes a free slot, or the slot of the satellite
/// seen longest ago; one that finds none (more satellites at one epoch than
/// slots) is used with its bias variance added to its noise
/// (`coupling::engine::range_bias`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RangeBiasSlots {
    /// No range-bias states.
    #[default]
    None,
    /// [`RANGE_BIAS_SLOTS`] slots, held by the satellites used most
    /// recently: with more satellites than that, the rest count as white
    /// noise of the bias's variance.
    Shared,
    /// [`EVERY_SATELLITE_SLOTS`] slots: a state for every satellite a
    /// multi-system receiver tracks.
    EverySatellite,
}

impl RangeBiasSlots {
    /// How many slots.
    pub const fn count(self) -> usize {
        match self {
            Self::None => 0,
            Self::Shared => RANGE_BIAS_SLOTS,
            Self::EverySatellite => EVERY_SATELLITE_SLOTS,
        }
    }

    const ALL: [Self; 3] = [Self::None, Self::Shared, Self::EverySatellite];
}

/// Which optional blocks a state of size `N` has (the sizes above are the
/// only valid ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Accelerometer and gyro scale-factor states at 17-22.
    pub scale_factors: bool,
    /// Index of the first installation state, when there are any.
    pub installation: Option<usize>,
    /// Index of the first inter-system-bias state, when there are any.
    pub inter_system_bias: Option<usize>,
    /// Index of the first range-bias state, when there are any.
    pub range_bias: Option<usize>,
    /// Number of range-bias slots (0 without range-bias states).
    pub range_bias_slots: usize,
}

impl Layout {
    /// The layout of a state of size `n`; `None` for any other size.
    pub const fn of(n: usize) -> Option<Self> {
        let mut k = 0;
        while k < 24 {
            let (sf, inst, isb) = (k & 1 != 0, k & 2 != 0, k & 4 != 0);
            let rb = RangeBiasSlots::ALL[k >> 3];
            if Self::size(sf, inst, isb, rb) == n {
                let after_sf = if sf { WITH_SCALE_FACTORS } else { BASE_STATES };
                let after_inst = after_sf + if inst { INSTALLATION_STATES } else { 0 };
                let after_isb = after_inst + if isb { INTER_SYSTEM_BIAS_STATES } else { 0 };
                return Some(Self {
                    scale_factors: sf,
                    installation: if inst { Some(after_sf) } else { None },
                    inter_system_bias: if isb { Some(after_inst) } else { None },
                    range_bias: if rb.count() > 0 {
                        Some(after_isb)
                    } else {
                        None
                    },
                    range_bias_slots: rb.count(),
                });
            }
            k += 1;
        }
        None
    }

    /// The layout of size `N`, checked at compile time.
    pub const fn for_size<const N: usize>() -> Self {
        // Evaluated at compile time for each N (an inline const): the
        // layout is a constant of the filter's type, not a search at every
        // propagation step.
        const {
            match Self::of(N) {
                Some(l) => l,
                None => panic!(
                    "the error state has 17 or 23 states, + 7 installation states, + 3 inter-system-bias states, + 12 or 40 range-bias slots"
                ),
            }
        }
    }

    /// The size for these options: the base, then the scale factors, the
    /// installation block, the inter-system biases and the range biases,
    /// in that order (every combination gives a different size).
    pub const fn size(
        scale_factors: bool,
        installation: bool,
        inter_system_biases: bool,
        range_biases: RangeBiasSlots,
    ) -> usize {
        BASE_STATES
            + if scale_factors {
                WITH_SCALE_FACTORS - BASE_STATES
            } else {
                0
            }
            + if installation { INSTALLATION_STATES } else { 0 }
            + if inter_system_biases {
                INTER_SYSTEM_BIAS_STATES
            } else {
                0
            }
            + range_biases.count()
    }
}

/// The optional blocks of a run's error state, chosen at run time from the
/// configuration and the data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StateBlocks {
    /// Accelerometer and gyro scale-factor states.
    pub scale_factors: bool,
    /// The installation block ([`Installation`]).
    pub installation: bool,
    /// Inter-system biases (pseudoranges of systems beyond GPS).
    pub inter_system_biases: bool,
    /// Per-satellite pseudorange biases (tight coupling) or the fixes'
    /// position errors (loose coupling).
    pub range_biases: RangeBiasSlots,
}

/// Work that needs the error state's size as a constant: a filter of `N`
/// states. [`StateBlocks::dispatch`] runs it at the size the blocks give.
pub trait SizedJob {
    /// What the work returns.
    type Output;
    /// The work with `N` error states.
    fn run<const N: usize>(self) -> Self::Output;
}

impl StateBlocks {
    /// The error state's size ([`Layout::size`]).
    pub const fn size(self) -> usize {
        Layout::size(
            self.scale_factors,
            self.installation,
            self.inter_system_biases,
            self.range_biases,
        )
    }

    /// Runs `job` with the state size these blocks give: one monomorphised
    /// filter per combination, chosen here and nowhere else.
    pub fn dispatch<J: SizedJob>(self, job: J) -> J::Output {
        macro_rules! by_blocks {
            ($(($a:literal, $b:literal, $c:literal)),*) => {
                match (
                    self.scale_factors,
                    self.installation,
                    self.inter_system_biases,
                    self.range_biases,
                ) {
                    $(
                        ($a, $b, $c, RangeBiasSlots::None) => {
                            job.run::<{ Layout::size($a, $b, $c, RangeBiasSlots::None) }>()
                        }
                        ($a, $b, $c, RangeBiasSlots::Shared) => {
                            job.run::<{ Layout::size($a, $b, $c, RangeBiasSlots::Shared) }>()
                        }
                        ($a, $b, $c, RangeBiasSlots::EverySatellite) => {
                            job.run::<{ Layout::size($a, $b, $c, RangeBiasSlots::EverySatellite) }>()
                        }
                    )*
                }
            };
        }
        by_blocks!(
            (false, false, false),
            (true, false, false),
            (false, true, false),
            (true, true, false),
            (false, false, true),
            (true, false, true),
            (false, true, true),
            (true, true, true)
        )
    }

    /// The blocks of a state of size `n` (see [`Layout::of`]).
    pub const fn of_size(n: usize) -> Option<Self> {
        match Layout::of(n) {
            Some(l) => Some(Self {
                scale_factors: l.scale_factors,
                installation: l.installation.is_some(),
                inter_system_biases: l.inter_system_bias.is_some(),
                range_biases: match l.range_bias_slots {
                    0 => RangeBiasSlots::None,
                    RANGE_BIAS_SLOTS => RangeBiasSlots::Shared,
                    _ => RangeBiasSlots::EverySatellite,
                },
            }),
            None => None,
        }
    }
}

/// Names of the states, for messages and for the Python solution.
pub struct StateLayout;

impl StateLayout {
    const NAMES: [&'static str; WITH_SCALE_FACTORS] = [
        "attitude_x",
        "attitude_y",
        "attitude_z",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "position_x",
        "position_y",
        "position_z",
        "accel_bias_x",
        "accel_bias_y",
        "accel_bias_z",
        "gyro_bias_x",
        "gyro_bias_y",
        "gyro_bias_z",
        "clock_offset",
        "clock_drift",
        "accel_scale_factor_x",
        "accel_scale_factor_y",
        "accel_scale_factor_z",
        "gyro_scale_factor_x",
        "gyro_scale_factor_y",
        "gyro_scale_factor_z",
    ];

    const INSTALLATION_NAMES: [&'static str; INSTALLATION_STATES] = [
        "lever_arm_x",
        "lever_arm_y",
        "lever_arm_z",
        "time_offset",
        "velocity_latency",
        "mounting_pitch",
        "mounting_yaw",
    ];

    const INTER_SYSTEM_BIAS_NAMES: [&'static str; INTER_SYSTEM_BIAS_STATES] = [
        "inter_system_bias_galileo",
        "inter_system_bias_beidou",
        "inter_system_bias_glonass",
    ];

    /// The names of the states of a filter of size `n` (see [`Layout::of`]).
    pub fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| Self::name_in(n, i)).collect()
    }

    /// The name of state `i` of a filter of size `n`: range biases are
    /// `range_bias_<slot>`.
    pub fn name_in(n: usize, i: usize) -> String {
        let Some(layout) = Layout::of(n) else {
            return "unknown".into();
        };
        let after = |first: Option<usize>| first.filter(|&f| i >= f).map(|f| i - f);
        if let Some(k) = after(layout.range_bias).filter(|&k| k < layout.range_bias_slots) {
            return format!("range_bias_{k}");
        }
        let name = if let Some(k) = after(layout.inter_system_bias) {
            Self::INTER_SYSTEM_BIAS_NAMES.get(k)
        } else if let Some(k) = after(layout.installation) {
            Self::INSTALLATION_NAMES.get(k)
        } else {
            Self::NAMES.get(i)
        };
        name.copied().unwrap_or("unknown").into()
    }
}

/// The error-state vector with named accessors (estimate minus truth).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorState<const N: usize>(pub SVector<f64, N>);

impl<const N: usize> ErrorState<N> {
    /// All zero (the state after each closed-loop feedback).
    pub fn zero() -> Self {
        Self(SVector::zeros())
    }
    fn block(&self, i: usize) -> Vector3<f64> {
        self.0.fixed_rows::<3>(i).into_owned()
    }
    /// ψ, rad.
    pub fn attitude(&self) -> Vector3<f64> {
        self.block(ATTITUDE)
    }
    /// δv^e, m/s.
    pub fn velocity(&self) -> Vector3<f64> {
        self.block(VELOCITY)
    }
    /// δr^e, m.
    pub fn position(&self) -> Vector3<f64> {
        self.block(POSITION)
    }
    /// Accelerometer bias error, m/s².
    pub fn accel_bias(&self) -> Vector3<f64> {
        self.block(ACCEL_BIAS)
    }
    /// Gyro bias error, rad/s.
    pub fn gyro_bias(&self) -> Vector3<f64> {
        self.block(GYRO_BIAS)
    }
    /// Clock offset error, m.
    pub fn clock_offset(&self) -> f64 {
        self.0[CLOCK_OFFSET]
    }
    /// Clock drift error, m/s.
    pub fn clock_drift(&self) -> f64 {
        self.0[CLOCK_DRIFT]
    }
    /// The installation errors (the block of [`Installation`]), when the
    /// state has them.
    pub fn installation(&self) -> Option<SVector<f64, INSTALLATION_STATES>> {
        Layout::for_size::<N>()
            .installation
            .map(|first| self.0.fixed_rows::<INSTALLATION_STATES>(first).into_owned())
    }
    /// The inter-system-bias errors (Galileo, BeiDou, GLONASS), m, when the state
    /// has them.
    pub fn inter_system_biases(&self) -> Option<[f64; INTER_SYSTEM_BIAS_STATES]> {
        Layout::for_size::<N>()
            .inter_system_bias
            .map(|first| std::array::from_fn(|k| self.0[first + k]))
    }
    /// Scale-factor errors (accelerometer, gyro), when the state has them.
    pub fn scale_factors(&self) -> Option<(Vector3<f64>, Vector3<f64>)> {
        Layout::for_size::<N>().scale_factors.then(|| {
            (
                self.block(ACCEL_SCALE_FACTOR),
                self.block(GYRO_SCALE_FACTOR),
            )
        })
    }
}
