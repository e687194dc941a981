//! GLONASS in single-point positioning, on a GNSS simulator's RINEX files
//! (Orolia Skydel, from INSTINCT's test data: static receiver at a known
//! position, no ionosphere, no troposphere; excerpts and licence in
//! `tests/data/rinex-public`), against the truth and against RTKLIB's
//! single-point solution of the same files.

mod figures;

use std::path::{Path, PathBuf};

use figures::Figures;
use memsnav_core::geodesy::{geodetic_to_ecef, Geodetic};
use memsnav_core::gnss::{
    broadcast_epochs, read_broadcast_nav, read_rinex_obs, solve_fix, BroadcastNav, Fix, GnssSystem,
    ObservableOptions,
};
use nalgebra::Vector3;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/rinex-public")
        .join(name)
}

/// The simulated receiver (the data's README).
fn truth() -> Vector3<f64> {
    Vector3::new(-481819.31349724, 5507219.95375401, 3170373.73538364)
}

/// RTKLIB's positions (demo5 b34d, single mode, 0° mask, no atmosphere)
/// of an excerpt of its `.pos` file.
fn rtklib(name: &str) -> Vec<Vector3<f64>> {
    std::fs::read_to_string(data(name))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('%'))
        .map(|l| {
            let f: Vec<f64> = l
                .split_whitespace()
                .skip(2)
                .take(3)
                .map(|x| x.parse().unwrap())
                .collect();
            geodetic_to_ecef(Geodetic::new(f[0].to_radians(), f[1].to_radians(), f[2]))
        })
        .collect()
}

fn fixes(systems: &[GnssSystem]) -> Vec<Fix> {
    let obs = read_rinex_obs(data("skydel_20230080000_excerpt_MO.rnx")).unwrap();
    let nav = BroadcastNav {
        gps: read_broadcast_nav(data("skydel_20230080000_excerpt_GN.rnx"))
            .unwrap()
            .gps,
        glonass: read_broadcast_nav(data("skydel_20230080000_excerpt_RN.rnx"))
            .unwrap()
            .glonass,
        ..BroadcastNav::default()
    };
    let mut options = ObservableOptions::new(truth());
    options.ionosphere = None;
    options.troposphere = false;
    options.elevation_mask_rad = 0.0;
    options.systems = systems.to_vec();
    broadcast_epochs(&obs, &nav, &options)
        .unwrap()
        .iter()
        .map(|e| solve_fix(e, None).unwrap())
        .collect()
}

#[test]
fn glonass_alone_finds_the_simulated_receiver() {
    let fixes = fixes(&[GnssSystem::Glonass]);
    let reference = rtklib("skydel_rtklib_excerpt_R.pos");
    assert_eq!(fixes.len(), 5);
    let mut spans = Spans::default();
    for (fix, rtk) in fixes.iter().zip(&reference) {
        let error = (fix.position_ecef - truth()).norm();
        let rtk_error = (rtk - truth()).norm();
        spans.add(error, rtk_error, (fix.position_ecef - rtk).norm());
        // The same error model as RTKLIB's single mode (the default
        // weighting): the same fix to centimetres.
        assert!(fix.n_satellites >= 7);
        assert!(error < 3.5, "{error} m (RTKLIB {rtk_error} m)");
        assert!((fix.position_ecef - rtk).norm() < 0.05);
        assert!(fix
            .inter_system_bias_m
            .iter()
            .all(|b| b.is_nan() || *b == 0.0));
    }
    spans.record("glonass_alone_fixes", None);
}

/// The least and largest error of memsnav's and RTKLIB's fixes against the
/// truth, and the largest distance between the two, m: what
/// docs/how-to/convert-ublox.md shows to the centimetre.
#[derive(Default)]
struct Spans {
    memsnav: Vec<f64>,
    rtklib: Vec<f64>,
    apart: Vec<f64>,
}

impl Spans {
    fn add(&mut self, memsnav: f64, rtklib: f64, apart: f64) {
        self.memsnav.push(memsnav);
        self.rtklib.push(rtklib);
        self.apart.push(apart);
    }

    fn record(&self, name: &'static str, glonass_bias_m: Option<f64>) {
        let least = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let most = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let mut figures = Figures::new(name);
        figures
            .add("memsnav_least_m", least(&self.memsnav), 0.005)
            .add("memsnav_most_m", most(&self.memsnav), 0.005)
            .add("rtklib_least_m", least(&self.rtklib), 0.005)
            .add("rtklib_most_m", most(&self.rtklib), 0.005)
            .add("largest_apart_m", most(&self.apart), 0.005);
        if let Some(bias) = glonass_bias_m {
            figures.add("largest_glonass_bias_m", bias, 0.005);
        }
        figures.check_or_write();
    }
}

#[test]
fn gps_and_glonass_with_an_inter_system_bias() {
    let fixes = fixes(&[GnssSystem::Gps, GnssSystem::Glonass]);
    let reference = rtklib("skydel_rtklib_excerpt_GR.pos");
    let mut spans = Spans::default();
    let mut largest_bias = 0.0f64;
    for (fix, rtk) in fixes.iter().zip(&reference) {
        let error = (fix.position_ecef - truth()).norm();
        let rtk_error = (rtk - truth()).norm();
        spans.add(error, rtk_error, (fix.position_ecef - rtk).norm());
        // The simulator has no inter-system bias: the estimate's is near zero.
        assert!(error < 1.0, "{error} m (RTKLIB {rtk_error} m)");
        assert!((fix.position_ecef - rtk).norm() < 0.05);
        let glonass_bias = fix.inter_system_bias_m[GnssSystem::Glonass.fix_bias_index().unwrap()];
        assert!(glonass_bias.abs() < 0.5, "{glonass_bias}");
        largest_bias = largest_bias.max(glonass_bias.abs());
        assert!(fix.inter_system_bias_m[..2].iter().all(|b| b.is_nan()));
    }
    spans.record("gps_glonass_fixes", Some(largest_bias));
}
