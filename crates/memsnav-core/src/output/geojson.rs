//! GeoJSON (RFC 7946): a `FeatureCollection` (with the foreign member
//! `"generator": "memsnav"`, §6.1) of one `Feature` whose geometry is a
//! `LineString` of [longitude, latitude, ellipsoidal height] (§3.1.1), and
//! whose properties are its `name`, each position's time as UTC text
//! (`coordTimes`, the name map tools read) and as GPS time (`gps_time_s`).

use super::TrackPoint;
use crate::gnss::utc_text_from_gps_time;

/// The start every GeoJSON of memsnav's has.
pub(super) const SIGNATURE: &str = "{\"type\": \"FeatureCollection\", \"generator\": \"memsnav\"";

/// `text` as a JSON string (RFC 8259 §7).
fn json_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if u32::from(c) < 0x20 => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The GeoJSON text of a track (at least two points) titled `name`.
pub(super) fn format(points: &[TrackPoint], name: &str) -> String {
    let join =
        |f: &dyn Fn(&TrackPoint) -> String| points.iter().map(f).collect::<Vec<_>>().join(", ");
    let times = join(&|p| format!("\"{}\"", utc_text_from_gps_time(p.gps_time_s)));
    let gps = join(&|p| format!("{:.4}", p.gps_time_s));
    let coordinates = points
        .iter()
        .map(|p| format!("[{:.9}, {:.9}, {:.4}]", p.lon_deg, p.lat_deg, p.height_m))
        .collect::<Vec<_>>()
        .join(",\n");
    format!(
        "{SIGNATURE}, \"features\": [\n{{\"type\": \"Feature\", \"properties\": {{\"name\": {}, \
         \"height\": \"ellipsoidal (WGS 84), m\", \"coordTimes\": [{times}], \"gps_time_s\": [{gps}]}}, \
         \"geometry\": {{\"type\": \"LineString\", \"coordinates\": [\n{coordinates}]}}}}]}}\n",
        json_string(name)
    )
}
