//! UBX-NAV-PVT (class 0x01, id 0x07; u-blox F9 HPG 1.32 interface
//! description §3.15.13): the receiver's own navigation solution, kept as
//! the fixes every reader of this module gives ([`PosSolution`]).

use nalgebra::Vector3;

use super::bytes::Le;
use crate::gnss::{checked_gps_time_from_utc, plausible, SECONDS_PER_WEEK};
use crate::logs::PosSolution;

/// NAV-PVT payload length (protocol 14 and later).
const PAYLOAD_BYTES: usize = 92;

/// One NAV-PVT solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavPvt {
    /// Solution time, GPS s since 1980-01-06 (GPS time of week from
    /// `iTOW`, the week from the UTC date and the leap seconds).
    pub gps_time_s: f64,
    /// `fixType`: 0 none, 1 dead reckoning, 2 2D, 3 3D, 4 GNSS + dead
    /// reckoning, 5 time only.
    pub fix_type: u8,
    /// `gnssFixOK`: the fix is within the receiver's accuracy masks.
    pub fix_ok: bool,
    /// Differential corrections applied (`diffSoln`).
    pub differential: bool,
    /// Carrier-phase solution: 0 none, 1 float, 2 fixed (`carrSoln`).
    pub carrier_solution: u8,
    /// Satellites used.
    pub n_satellites: u8,
    /// Latitude, longitude rad, height above the ellipsoid m.
    pub lla: Vector3<f64>,
    /// Height above mean sea level, m.
    pub height_msl_m: f64,
    /// NED velocity, m/s.
    pub velocity_ned_m_s: Vector3<f64>,
    /// Horizontal position accuracy estimate, m.
    pub horizontal_accuracy_m: f64,
    /// Vertical position accuracy estimate, m.
    pub vertical_accuracy_m: f64,
    /// Speed accuracy estimate, m/s.
    pub speed_accuracy_m_s: f64,
}

impl NavPvt {
    /// RTKLIB's solution quality of this fix: 1 fixed and 2 float carrier
    /// phase, 4 differential code, 5 single point, 7 dead reckoning alone.
    pub fn quality(&self) -> u8 {
        match (self.carrier_solution, self.differential, self.fix_type) {
            (2, _, _) => 1,
            (1, _, _) => 2,
            (_, _, 1) => 7,
            (_, true, _) => 4,
            _ => 5,
        }
    }

    /// A position fix: fix type 2D, 3D or GNSS + dead reckoning with
    /// `gnssFixOK` (dead reckoning alone and time-only solutions are not
    /// measurements).
    pub fn is_fix(&self) -> bool {
        self.fix_ok && matches!(self.fix_type, 2..=4)
    }
}

/// Decodes a NAV-PVT payload, or says why it cannot (length, no valid UTC
/// date and time to place the time of week, values out of range).
pub(super) fn decode_nav_pvt(payload: &[u8]) -> Result<NavPvt, String> {
    if payload.len() != PAYLOAD_BYTES {
        return Err(format!(
            "NAV-PVT payload of {} bytes, expected {PAYLOAD_BYTES}",
            payload.len()
        ));
    }
    let p = Le(payload);
    let itow_s = f64::from(p.u32(0)) * 1e-3;
    if itow_s >= SECONDS_PER_WEEK {
        return Err(format!("NAV-PVT iTOW {itow_s} s is beyond the week"));
    }
    // validDate and validTime: without both the week is unknown.
    if p.u8(11) & 3 != 3 {
        return Err("NAV-PVT without a valid UTC date and time (week unknown)".into());
    }
    let utc_s = f64::from(p.u8(10)) + f64::from(p.i32(16)) * 1e-9;
    let utc_gps_s = checked_gps_time_from_utc(
        i64::from(p.u16(4)),
        i64::from(p.u8(6)),
        i64::from(p.u8(7)),
        i64::from(p.u8(8)),
        i64::from(p.u8(9)),
        utc_s.max(0.0),
    )
    .map_err(|e| format!("NAV-PVT UTC date: {e}"))?;
    // The week whose iTOW lies nearest the UTC-derived time (they differ
    // by the UTC rounding only; a wrong leap-second table moves it by
    // seconds, not weeks).
    let week = ((utc_gps_s - itow_s) / SECONDS_PER_WEEK).round();
    let lat = f64::from(p.i32(28)) * 1e-7;
    let lon = f64::from(p.i32(24)) * 1e-7;
    if lat.abs() > 90.0 || lon.abs() > 180.0 {
        return Err(format!(
            "NAV-PVT latitude {lat}° or longitude {lon}° out of range"
        ));
    }
    let mm = |at: usize| f64::from(p.i32(at)) * 1e-3;
    let flags = p.u8(21);
    Ok(NavPvt {
        gps_time_s: week * SECONDS_PER_WEEK + itow_s,
        fix_type: p.u8(20),
        fix_ok: flags & 1 == 1,
        differential: flags & 2 == 2,
        carrier_solution: flags >> 6,
        n_satellites: p.u8(23),
        lla: Vector3::new(lat.to_radians(), lon.to_radians(), mm(32)),
        height_msl_m: mm(36),
        velocity_ned_m_s: Vector3::new(mm(48), mm(52), mm(56)),
        horizontal_accuracy_m: f64::from(p.u32(40)) * 1e-3,
        vertical_accuracy_m: f64::from(p.u32(44)) * 1e-3,
        speed_accuracy_m_s: f64::from(p.u32(68)) * 1e-3,
    })
}

/// `Ok` when a solution's values can come from a receiver: its heights
/// within [`plausible::HEIGHT_M`] and each velocity component within
/// ±[`plausible::MAX_SPEED_M_S`]; else the first value outside, named by
/// its NAV-PVT field.
pub(super) fn check_plausible(s: &NavPvt) -> Result<(), String> {
    let speed = -plausible::MAX_SPEED_M_S..=plausible::MAX_SPEED_M_S;
    let v = s.velocity_ned_m_s;
    plausible::check(s.lla.z, plausible::HEIGHT_M, "NAV-PVT height", "m")?;
    plausible::check(s.height_msl_m, plausible::HEIGHT_M, "NAV-PVT hMSL", "m")?;
    for (value, name) in [
        (v.x, "NAV-PVT velN"),
        (v.y, "NAV-PVT velE"),
        (v.z, "NAV-PVT velD"),
    ] {
        plausible::check(value, speed.clone(), name, "m/s")?;
    }
    Ok(())
}

/// The fixes among `solutions` (see [`NavPvt::is_fix`]) as a
/// [`PosSolution`], in time order with repeated epochs dropped. u-blox's
/// hAcc is a horizontal (two-axis) accuracy: north and east get hAcc/√2
/// each, down vAcc; every velocity axis gets sAcc (the speed accuracy).
pub(super) fn fixes(solutions: &[NavPvt]) -> PosSolution {
    let mut out = PosSolution::with_capacity(solutions.len());
    for s in solutions.iter().filter(|s| s.is_fix()) {
        if out.gps_time_s.last().is_some_and(|&t| s.gps_time_s <= t) {
            out.warnings.push(format!(
                "NAV-PVT at GPS {} s does not follow the previous fix; skipped",
                s.gps_time_s
            ));
            continue;
        }
        let h = s.horizontal_accuracy_m / std::f64::consts::SQRT_2;
        out.gps_time_s.push(s.gps_time_s);
        out.lla.push(s.lla);
        out.quality.push(s.quality());
        out.n_satellites.push(u16::from(s.n_satellites));
        out.std_ned_m
            .push(Vector3::new(h, h, s.vertical_accuracy_m));
        out.velocity_ned_m_s.push(s.velocity_ned_m_s);
        out.velocity_std_ned_m_s
            .push(Vector3::repeat(s.speed_accuracy_m_s));
    }
    out
}

/// A NAV-PVT payload (the inverse of [`decode_nav_pvt`] for the fields it
/// reads), for tests.
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
pub(super) fn encode_nav_pvt(
    itow_ms: u32,
    utc: (u16, u8, u8, u8, u8, u8),
    fix_type: u8,
    flags: u8,
    n_satellites: u8,
    lat_lon_deg: (f64, f64),
    height_msl_mm: (i32, i32),
    accuracy_mm: (u32, u32, u32),
) -> Vec<u8> {
    let mut p = vec![0u8; PAYLOAD_BYTES];
    p[0..4].copy_from_slice(&itow_ms.to_le_bytes());
    p[4..6].copy_from_slice(&utc.0.to_le_bytes());
    p[6..11].copy_from_slice(&[utc.1, utc.2, utc.3, utc.4, utc.5]);
    p[11] = 0x07;
    p[20] = fix_type;
    p[21] = flags;
    p[23] = n_satellites;
    let deg = |x: f64| ((x * 1e7).round() as i32).to_le_bytes();
    p[24..28].copy_from_slice(&deg(lat_lon_deg.1));
    p[28..32].copy_from_slice(&deg(lat_lon_deg.0));
    p[32..36].copy_from_slice(&height_msl_mm.0.to_le_bytes());
    p[36..40].copy_from_slice(&height_msl_mm.1.to_le_bytes());
    p[40..44].copy_from_slice(&accuracy_mm.0.to_le_bytes());
    p[44..48].copy_from_slice(&accuracy_mm.1.to_le_bytes());
    p[48..52].copy_from_slice(&250i32.to_le_bytes());
    p[68..72].copy_from_slice(&accuracy_mm.2.to_le_bytes());
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_position_and_quality() {
        // 2025-08-28 17:30:00 UTC = GPS week 2381, TOW 4 d 17 h 30 min + 18 s.
        let itow_ms = ((4 * 86_400 + 17 * 3_600 + 30 * 60 + 18) * 1000) as u32;
        let p = encode_nav_pvt(
            itow_ms,
            (2025, 8, 28, 17, 30, 0),
            3,
            0x81, // gnssFixOK, carrSoln = 2 (fixed)
            20,
            (40.0, -105.25),
            (1_580_048, 1_601_435),
            (14, 20, 30),
        );
        let s = decode_nav_pvt(&p).unwrap();
        assert_eq!(
            s.gps_time_s,
            2381.0 * SECONDS_PER_WEEK + f64::from(itow_ms) * 1e-3
        );
        assert_eq!((s.quality(), s.n_satellites), (1, 20));
        assert!((s.lla.x.to_degrees() - 40.0).abs() < 1e-12);
        assert_eq!((s.lla.z, s.height_msl_m), (1580.048, 1601.435));
        assert_eq!(s.velocity_ned_m_s.x, 0.25);
        let f = fixes(&[s, s]);
        assert_eq!(f.gps_time_s.len(), 1);
        assert_eq!(f.warnings.len(), 1);
        assert!((f.std_ned_m[0].x - 0.014 / 2f64.sqrt()).abs() < 1e-15);
        // Float carrier, differential code, plain single point, no fix.
        let q = |flags, fix_type| {
            let mut p = p.clone();
            (p[21], p[20]) = (flags, fix_type);
            decode_nav_pvt(&p).unwrap()
        };
        assert_eq!(q(0x41, 3).quality(), 2);
        assert_eq!(q(0x03, 3).quality(), 4);
        assert_eq!(q(0x01, 3).quality(), 5);
        assert!(!q(0x00, 3).is_fix() && !q(0x01, 5).is_fix());
        let mut bad = p.clone();
        bad[11] = 0;
        assert!(decode_nav_pvt(&bad).unwrap_err().contains("valid UTC"));
        assert!(decode_nav_pvt(&p[1..]).unwrap_err().contains("91 bytes"));
    }

    #[test]
    fn heights_and_speeds_no_receiver_reports_are_named() {
        let p = encode_nav_pvt(
            0,
            (2025, 8, 28, 0, 0, 0),
            3,
            1,
            9,
            (40.0, 5.0),
            (300, 250),
            (1, 1, 1),
        );
        assert_eq!(check_plausible(&decode_nav_pvt(&p).unwrap()), Ok(()));
        let mut deep = p.clone();
        deep[32..36].copy_from_slice(&(-1_043_477_000i32).to_le_bytes());
        let e = check_plausible(&decode_nav_pvt(&deep).unwrap()).unwrap_err();
        assert!(
            e.starts_with("NAV-PVT height = -1.043477e6 m is out of range"),
            "{e}"
        );
        let mut fast = p.clone();
        fast[52..56].copy_from_slice(&i32::MIN.to_le_bytes());
        let e = check_plausible(&decode_nav_pvt(&fast).unwrap()).unwrap_err();
        assert!(e.starts_with("NAV-PVT velE = -2.147483648e6 m/s"), "{e}");
    }
}
