//! Atmospheric delays of a single-frequency GPS L1 pseudorange: the
//! broadcast Klobuchar ionosphere (IS-GPS-200, §20.3.3.5.2.5) and the
//! Saastamoinen troposphere with a standard atmosphere (Saastamoinen 1972;
//! the form used by RTKLIB's `tropmodel`, Takasu 2013), and the Klobuchar
//! coefficients of a navigation file header.

use std::f64::consts::PI;
use std::path::Path;

use crate::{Error, Result};

/// Speed of light, m/s (IS-GPS-200).
const C_M_S: f64 = 299_792_458.0;

/// The eight broadcast ionosphere coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Klobuchar {
    /// α₀..α₃: s, s/semicircle, s/semicircle², s/semicircle³.
    pub alpha: [f64; 4],
    /// β₀..β₃: s, s/semicircle, s/semicircle², s/semicircle³.
    pub beta: [f64; 4],
}

impl Klobuchar {
    /// RTKLIB's default coefficients (`ion_default` in rtkcmn.c, broadcast
    /// on 2004-01-01), for navigation files whose header carries none.
    pub const RTKLIB_DEFAULT: Klobuchar = Klobuchar {
        alpha: [0.1118e-07, -0.7451e-08, -0.5961e-07, 0.1192e-06],
        beta: [0.1167e+06, -0.2294e+06, -0.1311e+06, 0.1049e+07],
    };

    /// L1 ionospheric delay, m, of a signal received at `gps_time_s` by a
    /// receiver at geodetic `latitude_rad`, `longitude_rad` from a satellite
    /// at `azimuth_rad` (from north, clockwise) and `elevation_rad`
    /// (IS-GPS-200 figure 20-4, step by step; angles there in semicircles).
    pub fn delay_m(
        &self,
        gps_time_s: f64,
        latitude_rad: f64,
        longitude_rad: f64,
        azimuth_rad: f64,
        elevation_rad: f64,
    ) -> f64 {
        let e = elevation_rad / PI;
        let phi_u = latitude_rad / PI;
        let lambda_u = longitude_rad / PI;
        // Earth-centred angle to the ionospheric pierce point, semicircles.
        let psi = 0.0137 / (e + 0.11) - 0.022;
        let phi_i = (phi_u + psi * azimuth_rad.cos()).clamp(-0.416, 0.416);
        let lambda_i = lambda_u + psi * azimuth_rad.sin() / (phi_i * PI).cos();
        // Geomagnetic latitude of the pierce point, semicircles.
        let phi_m = phi_i + 0.064 * ((lambda_i - 1.617) * PI).cos();
        let t = (43_200.0 * lambda_i + gps_time_s).rem_euclid(86_400.0);
        // Obliquity factor.
        let f = 1.0 + 16.0 * (0.53 - e).powi(3);
        let poly = |c: &[f64; 4]| c[0] + phi_m * (c[1] + phi_m * (c[2] + phi_m * c[3]));
        let amplitude = poly(&self.alpha).max(0.0);
        let period = poly(&self.beta).max(72_000.0);
        let x = 2.0 * PI * (t - 50_400.0) / period;
        let delay_s = if x.abs() < 1.57 {
            f * (5e-9 + amplitude * (1.0 - x * x / 2.0 + x.powi(4) / 24.0))
        } else {
            f * 5e-9
        };
        C_M_S * delay_s
    }
}

/// Tropospheric delay, m, from the Saastamoinen model with a standard
/// atmosphere at the receiver's ellipsoidal `height_m` (pressure 1013.25 hPa
/// and 15 °C at sea level, lapse rate 6.5 K/km, relative humidity
/// `relative_humidity` in [0, 1]); the zenith delays are mapped by
/// 1/cos(zenith angle) as in Saastamoinen's formula (RTKLIB `tropmodel`).
/// Heights outside −100 m..10 km and elevations below 0 give 0 (the model
/// does not apply there).
pub fn saastamoinen_delay_m(
    latitude_rad: f64,
    height_m: f64,
    elevation_rad: f64,
    relative_humidity: f64,
) -> f64 {
    if !(-100.0..=1.0e4).contains(&height_m) || elevation_rad <= 0.0 {
        return 0.0;
    }
    let h = height_m.max(0.0);
    let pressure_hpa = 1013.25 * (1.0 - 2.2557e-5 * h).powf(5.2568);
    let temperature_k = 15.0 - 6.5e-3 * h + 273.16;
    let vapour_hpa = 6.108
        * relative_humidity
        * ((17.15 * temperature_k - 4684.0) / (temperature_k - 38.45)).exp();
    let zenith = PI / 2.0 - elevation_rad;
    let hydrostatic = 0.0022768 * pressure_hpa
        / (1.0 - 0.00266 * (2.0 * latitude_rad).cos() - 0.00028 * h / 1e3)
        / zenith.cos();
    let wet = 0.002277 * (1255.0 / temperature_k + 0.05) * vapour_hpa / zenith.cos();
    hydrostatic + wet
}

/// Largest |α_n| the navigation message can carry (8 signed bits × 2⁻³⁰,
/// 2⁻²⁷, 2⁻²⁴, 2⁻²⁴ s/semicircleⁿ; IS-GPS-200 table 20-X), s.
const ALPHA_LIMITS: [f64; 4] = [
    128.0 * 9.313_225_746_154_785e-10,
    128.0 * 7.450_580_596_923_828e-9,
    128.0 * 5.960_464_477_539_063e-8,
    128.0 * 5.960_464_477_539_063e-8,
];
/// Largest |β_n| (8 signed bits × 2¹¹, 2¹⁴, 2¹⁶, 2¹⁶ s/semicircleⁿ), s.
const BETA_LIMITS: [f64; 4] = [
    128.0 * 2048.0,
    128.0 * 16384.0,
    128.0 * 65536.0,
    128.0 * 65536.0,
];

/// The first coefficient of `values` that is NaN or beyond its limit:
/// (index, value, limit). The one range check of a Klobuchar coefficient,
/// read from a file or given as an argument.
fn out_of_range(values: &[f64; 4], limits: &[f64; 4]) -> Option<(usize, f64, f64)> {
    values
        .iter()
        .zip(limits)
        .enumerate()
        .find(|(_, (x, limit))| x.is_nan() || x.abs() > **limit)
        .map(|(j, (&x, &limit))| (j, x, limit))
}

impl Klobuchar {
    /// Checks that every coefficient is one the navigation message can
    /// carry (an error naming `argument`, e.g. `klobuchar`).
    pub fn validate(&self, argument: &str) -> Result<()> {
        for (label, values, limits) in [
            ("alpha", &self.alpha, &ALPHA_LIMITS),
            ("beta", &self.beta, &BETA_LIMITS),
        ] {
            if let Some((j, x, limit)) = out_of_range(values, limits) {
                return Err(Error::invalid(
                    argument,
                    format!(
                        "{label}[{j}] = {x:e} is out of range (±{limit:e}): not a value the GPS \
                         navigation message can carry"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The Klobuchar coefficients in a RINEX navigation header: `ION ALPHA` /
/// `ION BETA` (RINEX 2) or `IONOSPHERIC CORR` `GPSA` / `GPSB` (RINEX 3);
/// `None` when the header has neither.
pub fn read_klobuchar(path: impl AsRef<Path>) -> Result<Option<Klobuchar>> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let text = std::fs::read(path).map_err(|e| Error::Io {
        path: file.clone(),
        reason: e.to_string(),
    })?;
    parse_klobuchar(&String::from_utf8_lossy(&text), &file)
}

/// [`read_klobuchar`] on the text of a navigation file; `file` names it in errors.
pub fn parse_klobuchar(text: &str, file: &str) -> Result<Option<Klobuchar>> {
    let file = file.to_string();
    let (mut alpha, mut beta) = (None, None);
    for (k, line) in text.lines().enumerate() {
        let label = line.get(60..).unwrap_or("").trim_end();
        if label == "END OF HEADER" {
            break;
        }
        let (target, start, limits) = match label {
            "ION ALPHA" => (&mut alpha, 2, ALPHA_LIMITS),
            "ION BETA" => (&mut beta, 2, BETA_LIMITS),
            "IONOSPHERIC CORR" if line.starts_with("GPSA") => (&mut alpha, 5, ALPHA_LIMITS),
            "IONOSPHERIC CORR" if line.starts_with("GPSB") => (&mut beta, 5, BETA_LIMITS),
            _ => continue,
        };
        let mut v = [0.0_f64; 4];
        for (j, x) in v.iter_mut().enumerate() {
            let f = line.get(start + 12 * j..start + 12 * (j + 1)).unwrap_or("");
            *x = f
                .trim()
                .replace(['D', 'd'], "E")
                .parse()
                .map_err(|_| Error::Parse {
                    file: file.clone(),
                    line: k + 1,
                    reason: format!(
                        "expected Klobuchar coefficient {} of {label} in columns {}-{}, got {:?}",
                        j + 1,
                        start + 12 * j + 1,
                        start + 12 * (j + 1),
                        f.trim()
                    ),
                })?;
        }
        if let Some((j, x, limit)) = out_of_range(&v, &limits) {
            return Err(Error::Parse {
                file: file.clone(),
                line: k + 1,
                reason: format!(
                    "Klobuchar coefficient {} of {label} = {x:e} is out of range (±{limit:e}): not a value the GPS navigation message can carry",
                    j + 1
                ),
            });
        }
        *target = Some(v);
    }
    Ok(match (alpha, beta) {
        (Some(alpha), Some(beta)) => Some(Klobuchar { alpha, beta }),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coefficients given as an argument (a configuration's
    /// `klobuchar_alpha`) were not checked; NaN changed every delay.
    #[test]
    fn coefficients_given_are_checked_as_read_ones_are() {
        assert!(Klobuchar::RTKLIB_DEFAULT.validate("klobuchar").is_ok());
        let mut k = Klobuchar::RTKLIB_DEFAULT;
        k.alpha[0] = f64::NAN;
        let err = k.validate("klobuchar").unwrap_err().to_string();
        assert!(
            err.starts_with("klobuchar: alpha[0] = NaN is out of range"),
            "{err}"
        );
        let mut k = Klobuchar::RTKLIB_DEFAULT;
        k.beta[3] = 1e10;
        let err = k.validate("klobuchar").unwrap_err().to_string();
        assert!(
            err.starts_with("klobuchar: beta[3] = 1e10 is out of range"),
            "{err}"
        );
    }

    #[test]
    fn klobuchar_night_floor_and_afternoon_peak() {
        let k = Klobuchar::RTKLIB_DEFAULT;
        // At the zenith, psi = 0.0137/0.61 - 0.022 and the pierce point is
        // the receiver; F = 1 + 16 (0.53 - 0.5)^3.
        let f = 1.0 + 16.0 * 0.03_f64.powi(3);
        // Local midnight at longitude 0: t = 0 → x far outside ±1.57: 5 ns · F.
        let night = k.delay_m(0.0, 0.0, 0.0, 0.0, PI / 2.0);
        assert!((night - C_M_S * 5e-9 * f).abs() < 1e-9, "{night}");
        // At 14:00 local time x = 0: 5 ns + amplitude, amplitude = Σ α_n φ_m^n
        // with the geomagnetic latitude of the pierce point, due north of the
        // receiver by psi semicircles (azimuth 0, λ_i = 0).
        let psi = 0.0137 / 0.61 - 0.022;
        let phi_m = psi + 0.064 * (-1.617 * PI).cos();
        let amp: f64 = (0..4).map(|n| k.alpha[n] * phi_m.powi(n as i32)).sum();
        let peak = k.delay_m(50_400.0, 0.0, 0.0, 0.0, PI / 2.0);
        assert!((peak - C_M_S * f * (5e-9 + amp)).abs() < 1e-9, "{peak}");
        // Lower elevations are longer paths.
        assert!(k.delay_m(50_400.0, 0.0, 0.0, 0.0, 0.2) > 2.0 * peak);
    }

    #[test]
    fn saastamoinen_zenith_at_sea_level_and_slant() {
        // Dry zenith delay at 1013.25 hPa, latitude 45° (cos 2φ = 0):
        // 0.0022768 × 1013.25 = 2.3070 m (Saastamoinen 1972).
        let dry = saastamoinen_delay_m(PI / 4.0, 0.0, PI / 2.0, 0.0);
        assert!((dry - 0.0022768 * 1013.25).abs() < 1e-9, "{dry}");
        // The wet part at 70 % humidity and 15 °C is about 0.1 m.
        let wet = saastamoinen_delay_m(PI / 4.0, 0.0, PI / 2.0, 0.7) - dry;
        assert!((0.05..0.2).contains(&wet), "{wet}");
        // At 30° elevation the path is 1/sin(30°) = 2 times longer.
        let slant = saastamoinen_delay_m(PI / 4.0, 0.0, PI / 6.0, 0.0);
        assert!((slant - 2.0 * dry).abs() < 1e-9);
        // At 1.6 km (Boulder) the pressure is about 835 hPa: 82 % of sea level.
        let boulder = saastamoinen_delay_m(PI / 4.0, 1600.0, PI / 2.0, 0.0);
        assert!((boulder / dry - 0.824).abs() < 0.01, "{}", boulder / dry);
        assert_eq!(saastamoinen_delay_m(0.7, 20_000.0, 1.0, 0.5), 0.0);
    }

    #[test]
    fn header_coefficients_rinex2_and_3() {
        let dir = std::env::temp_dir().join(format!("memsnav-iono-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p2 = dir.join("a.nav");
        std::fs::write(
            &p2,
            "     2.10           N: GPS NAV DATA                         RINEX VERSION / TYPE\n    \
  0.1118D-07 -0.7451D-08 -0.5961D-07  0.1192D-06          ION ALPHA           \n    \
  0.1167D+06 -0.2294D+06 -0.1311D+06  0.1049D+07          ION BETA            \n\
                                                            END OF HEADER       \n",
        )
        .unwrap();
        assert_eq!(
            read_klobuchar(&p2).unwrap(),
            Some(Klobuchar::RTKLIB_DEFAULT)
        );
        let p3 = dir.join("b.nav");
        std::fs::write(
            &p3,
            "     3.04           N: GNSS NAV DATA    M: Mixed            RINEX VERSION / TYPE\n\
GPSA   1.1180D-08 -7.4510D-09 -5.9610D-08  1.1920D-07       IONOSPHERIC CORR    \n\
GPSB   1.1670D+05 -2.2940D+05 -1.3110D+05  1.0490D+06       IONOSPHERIC CORR    \n\
                                                            END OF HEADER       \n",
        )
        .unwrap();
        let k = read_klobuchar(&p3).unwrap().unwrap();
        for j in 0..4 {
            assert!((k.alpha[j] / Klobuchar::RTKLIB_DEFAULT.alpha[j] - 1.0).abs() < 1e-12);
            assert!((k.beta[j] / Klobuchar::RTKLIB_DEFAULT.beta[j] - 1.0).abs() < 1e-12);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
