//! The UBX reader on the walk's raw u-blox log (shared data), against the
//! RINEX navigation file converted from the same log, the receiver's own
//! solution and the least-squares fix.

mod shared_data;

use memsnav_core::gnss::{read_rinex_nav, GpsEphemeris};
use memsnav_core::logs::read_ubx;
use shared_data::shared_data;

const WALK_UBX: &str = "real-imu-gnss/walk_0827/gnss_1730.ubx";
const WALK_NAV: &str = "real-imu-gnss/walk_0827/gnss_1730.nav";

#[test]
fn walk_log_scratch() {
    let log = read_ubx(shared_data(WALK_UBX)).unwrap();
    println!("{:?}", log.messages);
    println!("{:?}", log.skipped);
    println!("{:?}", log.warnings);
    println!(
        "rawx {} pvt {} fixes {}",
        log.rawx.len(),
        log.nav_pvt.len(),
        log.fixes.gps_time_s.len()
    );
    println!("{:?}", log.observations.observation_types);
    for e in &log.gps_ephemerides {
        println!("{:?}", e);
    }
    let nav: Vec<GpsEphemeris> = read_rinex_nav(shared_data(WALK_NAV)).unwrap();
    for n in &nav {
        println!("{:?}", n);
    }
}
