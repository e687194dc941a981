//! memsnav's solution CSV: a header of [`super::COLUMNS`], then one line
//! per row (time to 0.1 ms, latitude and longitude to 1e-9°, height to
//! 0.1 mm, the rest to 1e-5 of their unit).

/// The header line, [`super::COLUMNS`] joined.
pub(super) const HEADER: &str = "gps_time_s,lat_deg,lon_deg,height_m,vn_m_s,ve_m_s,vd_m_s,\
roll_deg,pitch_deg,yaw_deg,sdn_m,sde_m,sdd_m,sdvn_m_s,sdve_m_s,sdvd_m_s";

/// Decimals of each column.
const DECIMALS: [usize; 16] = [4, 9, 9, 4, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5];

/// The CSV text of `columns` (as [`super::columns`] returns them).
pub(super) fn format(columns: &[Vec<f64>]) -> String {
    let rows = columns.first().map_or(0, Vec::len);
    let mut out = String::with_capacity(HEADER.len() + 1 + rows * 160);
    out.push_str(HEADER);
    out.push('\n');
    for k in 0..rows {
        for (j, (column, decimals)) in columns.iter().zip(DECIMALS).enumerate() {
            if j > 0 {
                out.push(',');
            }
            out.push_str(&format!("{:.*}", decimals, column[k]));
        }
        out.push('\n');
    }
    out
}
