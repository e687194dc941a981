//! The truth at the point being scored. A reference (an RTK solution,
//! another system's INS) gives its position at its own point and in its
//! own datum; memsnav's solution is scored at the GNSS antenna. The truth
//! is moved there by the lever arm l from its point to the antenna in its
//! own body axes (forward, right, down), which needs its attitude C_b^n,
//! and by a constant datum offset o in NED (the GNSS's datum less the
//! truth's):
//!
//! ```text
//! r_scored = r_truth + C_n^e (C_b^n l + o)
//! ```
//!
//! the lever-arm transformation of Groves eq. 2.124 (r_a = r_b + C_b^e
//! l_ba^b) with C_b^e = C_n^e C_b^n (C_n^e: eq. 2.150 transposed, at the
//! truth's latitude and longitude), the datum offset added along the same
//! local axes (docs/how-to/your-own-files.md, "The truth").

use nalgebra::{Matrix3, Vector3};

use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
use crate::{validate, Error, Result};

/// The truth's positions moved to the scored point: `geodetic` the
/// truth's [latitude rad, longitude rad, ellipsoidal height m] at its own
/// point, `c_b_n` its attitude (body to NED) at each epoch (needed for a
/// non-zero `lever_arm_b_m`), `lever_arm_b_m` the scored point from the
/// truth's point in the truth's body axes, m, `offset_ned_m` the datum
/// offset added in the local NED, m. ECEF, m.
pub fn truth_at_point(
    geodetic: &[Vector3<f64>],
    c_b_n: Option<&[Matrix3<f64>]>,
    lever_arm_b_m: &Vector3<f64>,
    offset_ned_m: &Vector3<f64>,
) -> Result<Vec<Vector3<f64>>> {
    validate::finite_vectors("geodetic", geodetic)?;
    validate::finite_vectors("lever_arm", &[*lever_arm_b_m])?;
    validate::finite_vectors("offset_ned", &[*offset_ned_m])?;
    let lever_arm = *lever_arm_b_m != Vector3::zeros();
    if let Some(c) = c_b_n {
        validate::same_length("attitude", c.len(), "geodetic", geodetic.len())?;
        if let Some(k) = c.iter().position(|m| !m.iter().all(|x| x.is_finite())) {
            return Err(Error::invalid(
                "attitude",
                format!("epoch {k} is not finite"),
            ));
        }
    } else if lever_arm {
        return Err(Error::invalid(
            "lever_arm",
            "the truth gives no attitude: a lever arm in its body axes needs it (a fixes CSV's qw, qx, qy, qz or roll_deg, pitch_deg, yaw_deg columns)",
        ));
    }
    Ok(geodetic
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let body = match c_b_n {
                Some(c) if lever_arm => c[k] * lever_arm_b_m,
                _ => Vector3::zeros(),
            };
            geodetic_to_ecef(Geodetic::new(g.x, g.y, g.z)) + c_n_e(g.x, g.y) * (body + offset_ned_m)
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::euler_to_dcm;
    use crate::geodesy::ecef_to_geodetic;
    use std::f64::consts::FRAC_PI_2;

    /// NED of `r` from `origin` at the origin's latitude and longitude.
    fn ned(r: &Vector3<f64>, origin: &Vector3<f64>) -> Vector3<f64> {
        let g = ecef_to_geodetic(origin);
        c_n_e(g.latitude_rad, g.longitude_rad).transpose() * (r - origin)
    }

    /// Cases where the offset is obvious: a level car heading north puts a
    /// point 2.2 m behind it 2.2 m south; heading east, 2.2 m west; a
    /// point 1 m to its right and 0.5 m below, heading east, 1 m south and
    /// 0.5 m down; the datum offset adds along N, E, D as given.
    #[test]
    fn straight_drives_move_the_truth_where_expected() {
        let g = Vector3::new(39.76_f64.to_radians(), (-84.11_f64).to_radians(), 220.0);
        let origin = geodetic_to_ecef(Geodetic::new(g.x, g.y, g.z));
        let cases = [
            (
                0.0,
                Vector3::new(-2.2, 0.0, 0.0),
                Vector3::new(-2.2, 0.0, 0.0),
            ),
            (
                FRAC_PI_2,
                Vector3::new(-2.2, 0.0, 0.0),
                Vector3::new(0.0, -2.2, 0.0),
            ),
            (
                FRAC_PI_2,
                Vector3::new(0.0, 1.0, 0.5),
                Vector3::new(-1.0, 0.0, 0.5),
            ),
        ];
        for (yaw, lever, want) in cases {
            let c = [euler_to_dcm(0.0, 0.0, yaw)];
            let r = truth_at_point(&[g], Some(&c), &lever, &Vector3::zeros()).unwrap();
            assert!((ned(&r[0], &origin) - want).norm() < 1e-9, "yaw {yaw}");
        }
        let offset = Vector3::new(0.1, -1.0, 1.0);
        let r = truth_at_point(&[g], None, &Vector3::zeros(), &offset).unwrap();
        assert!((ned(&r[0], &origin) - offset).norm() < 1e-9);
        let e = truth_at_point(&[g], None, &Vector3::x(), &Vector3::zeros()).unwrap_err();
        assert!(e
            .to_string()
            .starts_with("lever_arm: the truth gives no attitude"));
    }

    /// A rotation where the answer is not obvious, against an independent
    /// construction: the body axes of roll 20°, pitch −10°, yaw 130° built
    /// by turning the NED axes one elementary rotation at a time (yaw about
    /// down, then pitch about the new right axis, then roll about the new
    /// forward axis: the z-y-x sequence), the lever arm summed along them, and
    /// the NED result taken to ECEF through the east-north-up basis
    /// written out from latitude and longitude.
    #[test]
    fn a_tilted_heading_against_rotated_axes() {
        let (roll, pitch, yaw) = (
            20_f64.to_radians(),
            (-10_f64).to_radians(),
            130_f64.to_radians(),
        );
        let rotate = |v: Vector3<f64>, axis: Vector3<f64>, angle: f64| {
            // Rodrigues' formula for a unit axis.
            v * angle.cos()
                + axis.cross(&v) * angle.sin()
                + axis * axis.dot(&v) * (1.0 - angle.cos())
        };
        let (mut x, mut y, mut z) = (Vector3::x(), Vector3::y(), Vector3::z());
        x = rotate(x, Vector3::z(), yaw);
        y = rotate(y, Vector3::z(), yaw);
        let (x1, z1) = (rotate(x, y, pitch), rotate(z, y, pitch));
        x = x1;
        z = z1;
        let (y2, z2) = (rotate(y, x, roll), rotate(z, x, roll));
        y = y2;
        z = z2;
        let lever = Vector3::new(-2.2, 0.4, -0.9);
        let want_ned = x * lever.x + y * lever.y + z * lever.z;
        let (lat, lon) = (39.76_f64.to_radians(), (-84.11_f64).to_radians());
        let east = Vector3::new(-lon.sin(), lon.cos(), 0.0);
        let north = Vector3::new(-lat.sin() * lon.cos(), -lat.sin() * lon.sin(), lat.cos());
        let up = Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin());
        let g = Vector3::new(lat, lon, 220.0);
        let origin = geodetic_to_ecef(Geodetic::new(lat, lon, 220.0));
        let offset = Vector3::new(0.3, -0.8, 1.5);
        let total = want_ned + offset;
        let want = origin + north * total.x + east * total.y - up * total.z;
        let c = [euler_to_dcm(roll, pitch, yaw)];
        let r = truth_at_point(&[g], Some(&c), &lever, &offset).unwrap();
        assert!((r[0] - want).norm() < 1e-9, "{} vs {}", r[0], want);
    }
}
