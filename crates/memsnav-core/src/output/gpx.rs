//! GPX 1.1 (topografix.com/GPX/1/1): one `trk` of one `trkseg`, each
//! `trkpt` with latitude, longitude, `ele` (the ellipsoidal height, m) and
//! its `time` in UTC (GPS time less the leap seconds,
//! [`crate::gnss::utc_text_from_gps_time`]).

use super::{xml_escape, TrackPoint};
use crate::gnss::utc_text_from_gps_time;

/// The creator attribute that marks a GPX as memsnav's.
pub(super) const SIGNATURE: &str = "creator=\"memsnav\"";

/// The GPX text of a track (at least two points) titled `name`.
pub(super) fn format(points: &[TrackPoint], name: &str) -> String {
    let name = xml_escape(name);
    let mut out = String::with_capacity(512 + points.len() * 120);
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(&format!(
        "<gpx version=\"1.1\" {SIGNATURE} xmlns=\"http://www.topografix.com/GPX/1/1\">\n"
    ));
    out.push_str(&format!(
        "<metadata><name>{name}</name><desc>ele: ellipsoidal height (WGS 84), m</desc>\
         <time>{}</time></metadata>\n",
        utc_text_from_gps_time(points[0].gps_time_s)
    ));
    out.push_str(&format!("<trk><name>{name}</name><trkseg>\n"));
    for p in points {
        out.push_str(&format!(
            "<trkpt lat=\"{:.9}\" lon=\"{:.9}\"><ele>{:.4}</ele><time>{}</time></trkpt>\n",
            p.lat_deg,
            p.lon_deg,
            p.height_m,
            utc_text_from_gps_time(p.gps_time_s)
        ));
    }
    out.push_str("</trkseg></trk>\n</gpx>\n");
    out
}
