//! KML 2.2 (OGC 07-147r2): a `Document` with the track as a `LineString`
//! placemark (longitude, latitude, height; drawn on the ground, the KML
//! default, since KML heights are above sea level and ours ellipsoidal),
//! and the start and end as points.

use super::{xml_escape, TrackPoint};
use crate::gnss::utc_text_from_gps_time;

/// The comment that marks a KML as memsnav's.
pub(super) const SIGNATURE: &str = "<!-- written by memsnav";

fn coordinates(p: &TrackPoint) -> String {
    format!("{:.9},{:.9},{:.4}", p.lon_deg, p.lat_deg, p.height_m)
}

fn point(label: &str, p: &TrackPoint) -> String {
    format!(
        "<Placemark><name>{label}</name><TimeStamp><when>{}</when></TimeStamp>\
         <Point><coordinates>{}</coordinates></Point></Placemark>\n",
        utc_text_from_gps_time(p.gps_time_s),
        coordinates(p)
    )
}

/// The KML text of a track (at least two points) titled `name`.
pub(super) fn format(points: &[TrackPoint], name: &str) -> String {
    let name = xml_escape(name);
    let (first, last) = (&points[0], &points[points.len() - 1]);
    let mut out = String::with_capacity(512 + points.len() * 42);
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(&format!(
        "{SIGNATURE}: heights ellipsoidal (WGS 84), times UTC -->\n"
    ));
    out.push_str("<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n<Document>\n");
    out.push_str(&format!("<name>{name}</name>\n"));
    out.push_str(
        "<Style id=\"track\"><LineStyle><color>ffff0000</color><width>3</width></LineStyle></Style>\n",
    );
    out.push_str(&format!(
        "<Placemark><name>{name}</name><TimeSpan><begin>{}</begin><end>{}</end></TimeSpan>\
         <styleUrl>#track</styleUrl>\n<LineString><tessellate>1</tessellate><coordinates>\n",
        utc_text_from_gps_time(first.gps_time_s),
        utc_text_from_gps_time(last.gps_time_s)
    ));
    for p in points {
        out.push_str(&coordinates(p));
        out.push('\n');
    }
    out.push_str("</coordinates></LineString></Placemark>\n");
    out.push_str(&point("start", first));
    out.push_str(&point("end", last));
    out.push_str("</Document>\n</kml>\n");
    out
}
