//! The values a GPS, Galileo or BeiDou broadcast ephemeris can carry, in
//! the order of their RINEX 3 navigation records (RINEX 3.05 tables A6,
//! A8, A14): each value's name and the range its bits span in the
//! navigation message. A value outside cannot have been broadcast (an orbit
//! inside the Earth, a week in the next century): the RINEX reader refuses
//! it naming the line, the UBX decoders skip the ephemeris with a count.
//! The other plausibility ranges are in [`super::plausible`].

/// The values of a GPS record in RINEX order (`values[0..3]` = a_f0, a_f1,
/// a_f2 on the epoch line; then seven lines of four, RINEX 3.05 table A6).
pub(crate) const GPS_NAMES: [&str; 29] = [
    "SV clock bias",
    "SV clock drift",
    "SV clock drift rate",
    "IODE",
    "Crs",
    "Delta n",
    "M0",
    "Cuc",
    "e",
    "Cus",
    "sqrt(A)",
    "Toe",
    "Cic",
    "OMEGA0",
    "Cis",
    "i0",
    "Crc",
    "omega",
    "OMEGA DOT",
    "IDOT",
    "codes on L2",
    "GPS week",
    "L2 P flag",
    "SV accuracy",
    "SV health",
    "TGD",
    "IODC",
    "transmission time",
    "fit interval",
];

/// The values of a Galileo record (RINEX 3.05 table A8).
pub(crate) const GALILEO_NAMES: [&str; 28] = [
    "SV clock bias",
    "SV clock drift",
    "SV clock drift rate",
    "IODnav",
    "Crs",
    "Delta n",
    "M0",
    "Cuc",
    "e",
    "Cus",
    "sqrt(A)",
    "Toe",
    "Cic",
    "OMEGA0",
    "Cis",
    "i0",
    "Crc",
    "omega",
    "OMEGA DOT",
    "IDOT",
    "data sources",
    "GAL week",
    "spare",
    "SISA",
    "SV health",
    "BGD E5a/E1",
    "BGD E5b/E1",
    "transmission time",
];

/// The values of a BeiDou record (RINEX 3.05 table A14).
pub(crate) const BEIDOU_NAMES: [&str; 29] = [
    "SV clock bias",
    "SV clock drift",
    "SV clock drift rate",
    "AODE",
    "Crs",
    "Delta n",
    "M0",
    "Cuc",
    "e",
    "Cus",
    "sqrt(A)",
    "Toe",
    "Cic",
    "OMEGA0",
    "Cis",
    "i0",
    "Crc",
    "omega",
    "OMEGA DOT",
    "IDOT",
    "spare",
    "BDT week",
    "spare",
    "SV accuracy",
    "SatH1",
    "TGD1",
    "TGD2",
    "transmission time",
    "AODC",
];

/// The weeks of [`super::plausible::GPS_WEEKS`].
const GPS_WEEK_RANGE: (f64, f64) = (0.0, 6260.0);

/// The last BDT week before 2100 (GPS week 6260 − 1356).
const BDT_LAST_WEEK: f64 = 4904.0;

pub(crate) type Ranges = [Option<(f64, f64)>; 29];

const fn sym(x: f64) -> Option<(f64, f64)> {
    Some((-x, x))
}

/// The ranges of the clock (`clock`), the issue of data (`slot_3`) and
/// the orbit values (IS-GPS-200 table 20-III, Galileo ICD table 60, B1I
/// ICD table 5-9: bits × scale; angles in semicircles there are radians
/// in RINEX): the harmonic corrections bound by `crs_m` (Crs, Crc) and
/// `cuc_rad` (Cuc, Cus, Cic, Cis), the rest alike in the three systems.
const fn orbit_ranges(
    clock: [Option<(f64, f64)>; 3],
    slot_3: (f64, f64),
    crs_m: f64,
    cuc_rad: f64,
) -> [Option<(f64, f64)>; 20] {
    const PI: f64 = std::f64::consts::PI;
    [
        clock[0],
        clock[1],
        clock[2],
        Some(slot_3),
        sym(crs_m),                // Crs
        sym(3.725_290_3e-9 * PI),  // Δn: 16 bits × 2⁻⁴³ semicircles/s
        sym(PI),                   // M0: 32 bits × 2⁻³¹ semicircles
        sym(cuc_rad),              // Cuc
        Some((0.0, 0.5)),          // e: 32 bits unsigned × 2⁻³³
        sym(cuc_rad),              // Cus
        Some((2530.0, 8192.0)),    // √A, √m (IS-GPS-200's range; BeiDou GEO 6493)
        Some((0.0, 604_800.0)),    // t_oe, s of the week
        sym(cuc_rad),              // Cic
        sym(PI),                   // Ω0
        sym(cuc_rad),              // Cis
        sym(PI),                   // i0
        sym(crs_m),                // Crc
        sym(PI),                   // ω
        sym(9.536_743_2e-7 * PI),  // Ω̇: 24 bits × 2⁻⁴³ semicircles/s
        sym(9.313_225_8e-10 * PI), // IDOT: 14 bits × 2⁻⁴³ semicircles/s
    ]
}

/// Ranges of `head` then the system's last values (`None`: no limit).
const fn ranges(head: [Option<(f64, f64)>; 20], tail: [Option<(f64, f64)>; 9]) -> Ranges {
    let mut out = [None; 29];
    let mut k = 0;
    while k < 20 {
        out[k] = head[k];
        k += 1;
    }
    while k < 29 {
        out[k] = tail[k - 20];
        k += 1;
    }
    out
}

/// GPS (IS-GPS-200 tables 20-I, 20-III): a value outside cannot have been broadcast.
const GPS_RANGES: Ranges = ranges(
    orbit_ranges(
        [
            sym(9.765_625e-4),    // a_f0: 22 bits × 2⁻³¹ s
            sym(3.725_290_3e-9),  // a_f1: 16 bits × 2⁻⁴³ s/s
            sym(3.552_713_7e-15), // a_f2: 8 bits × 2⁻⁵⁵ s/s²
        ],
        (0.0, 1023.0),  // IODE (8 bits; 10 in RINEX 3 files of IODC)
        1024.0,         // Crs, Crc: 16 bits × 2⁻⁵ m
        6.103_515_7e-5, // Cuc, ...: 16 bits × 2⁻²⁹ rad
    ),
    [
        None,                 // codes on L2
        Some(GPS_WEEK_RANGE), // GPS week (continuous in RINEX)
        None,                 // L2 P flag
        None,                 // SV accuracy
        Some((0.0, 63.0)),    // SV health (6 bits)
        sym(5.960_464_5e-8),  // T_GD: 8 bits × 2⁻³¹ s
        Some((0.0, 1023.0)),  // IODC (10 bits)
        None,                 // transmission time
        Some((0.0, 1000.0)),  // fit interval, h
    ],
);

/// Galileo (OS SIS ICD tables 60, 63, 65).
const GALILEO_RANGES: Ranges = ranges(
    orbit_ranges(
        [
            sym(0.0625),          // a_f0: 31 bits × 2⁻³⁴ s
            sym(1.490_116_2e-8),  // a_f1: 21 bits × 2⁻⁴⁶ s/s
            sym(5.551_115_2e-17), // a_f2: 6 bits × 2⁻⁵⁹ s/s²
        ],
        (0.0, 1023.0),  // IODnav (10 bits)
        1024.0,         // Crs, Crc: 16 bits × 2⁻⁵ m
        6.103_515_7e-5, // Cuc, ...: 16 bits × 2⁻²⁹ rad
    ),
    [
        Some((0.0, 1023.0)),  // data sources (10 bits)
        Some(GPS_WEEK_RANGE), // GAL week (continuous, GPS-aligned)
        None,                 // spare
        None,                 // SISA, m (−1: no prediction)
        Some((0.0, 511.0)),   // SV health (9 bits)
        sym(1.192_092_9e-7),  // BGD E5a/E1: 10 bits × 2⁻³² s
        sym(1.192_092_9e-7),  // BGD E5b/E1
        None,                 // transmission time
        None,                 // (no value)
    ],
);

/// BeiDou (B1I ICD tables 5-7, 5-9).
const BEIDOU_RANGES: Ranges = ranges(
    orbit_ranges(
        [
            sym(9.765_625e-4),    // a_0: 24 bits × 2⁻³³ s
            sym(1.862_645_2e-9),  // a_1: 22 bits × 2⁻⁵⁰ s/s
            sym(1.387_778_8e-17), // a_2: 11 bits × 2⁻⁶⁶ s/s²
        ],
        (0.0, 31.0),    // AODE (5 bits)
        2048.0,         // Crs, Crc: 18 bits × 2⁻⁶ m
        1.220_703_2e-4, // Cuc, ...: 18 bits × 2⁻³¹ rad
    ),
    [
        None,                       // spare
        Some((0.0, BDT_LAST_WEEK)), // BDT week (13 bits; BDT began at GPS week 1356)
        None,                       // spare
        None,                       // SV accuracy, m
        Some((0.0, 1.0)),           // SatH1
        sym(5.12e-8),               // TGD1: 10 bits × 0.1 ns
        sym(5.12e-8),               // TGD2
        None,                       // transmission time
        Some((0.0, 31.0)),          // AODC (5 bits)
    ],
);

/// The names and ranges of the record values of system `letter` (G, E, C).
pub(crate) fn record_table(letter: char) -> Option<(&'static [&'static str], &'static Ranges)> {
    match letter {
        'G' => Some((&GPS_NAMES, &GPS_RANGES)),
        'E' => Some((&GALILEO_NAMES, &GALILEO_RANGES)),
        'C' => Some((&BEIDOU_NAMES, &BEIDOU_RANGES)),
        _ => None,
    }
}

/// `Ok` when value `index` of a record of satellite `sat` (whose letter
/// picks the table) lies in its range, else the sentence the readers give.
pub(crate) fn check_value(sat: &str, index: usize, value: f64) -> Result<(), String> {
    let letter = sat.chars().next().unwrap_or(' ');
    let Some((names, ranges)) = record_table(letter) else {
        return Err(format!("{sat}: not a GPS, Galileo or BeiDou satellite"));
    };
    match ranges.get(index).copied().flatten() {
        Some((low, high)) if !(low..=high).contains(&value) => Err(format!(
            "{} = {value:e} for {sat} is out of range ({low:e} to {high:e}): not a value the navigation message can carry",
            names[index]
        )),
        _ => Ok(()),
    }
}

/// The first value of a whole record of satellite `sat` out of its range:
/// its index and the sentence.
pub(crate) fn check_record(sat: &str, values: &[f64]) -> Result<(), (usize, String)> {
    values
        .iter()
        .enumerate()
        .try_for_each(|(index, &v)| check_value(sat, index, v).map_err(|e| (index, e)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbits_inside_the_earth_are_named() {
        let e = check_value("G32", 10, 33.6).unwrap_err();
        assert!(
            e.starts_with("sqrt(A) = 3.36e1 for G32 is out of range"),
            "{e}"
        );
        assert!(check_value("E11", 10, 64.6).is_err());
        assert!(check_value("C21", 10, 1186.6).is_err());
        assert!(check_value("C21", 10, 5282.6).is_ok());
        let mut values = [0.0; 29];
        values[10] = 5153.6;
        values[21] = 2400.0;
        assert_eq!(check_record("G01", &values), Ok(()));
        values[21] = 9999.0;
        assert_eq!(check_record("G01", &values).unwrap_err().0, 21);
    }
}
