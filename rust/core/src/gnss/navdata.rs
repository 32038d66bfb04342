//! Broadcast navigation records as read from RINEX navigation files (the reader converts every time to
//! GPST; the orbit and clock models are in [`crate::gnss::ephemeris`]).

use super::signal::SatId;

/// A Keplerian broadcast record of GPS, Galileo, BeiDou or QZSS (RINEX 3 navigation, SI units and
/// radians as in the file; BeiDou's BDT times converted to GPST by adding 14 s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeplerRecord {
    pub sat: SatId,
    /// Time of clock, GPST ns since the GPS epoch.
    pub toc_gpst_ns: i64,
    /// Time of ephemeris, GPST ns since the GPS epoch.
    pub toe_gpst_ns: i64,
    /// Clock bias (s), drift (s/s), drift rate (s/s^2).
    pub af: [f64; 3],
    pub crs: f64,
    pub delta_n: f64,
    pub m0: f64,
    pub cuc: f64,
    pub e: f64,
    pub cus: f64,
    pub sqrt_a: f64,
    pub cic: f64,
    pub omega0: f64,
    pub cis: f64,
    pub i0: f64,
    pub crc: f64,
    pub omega: f64,
    pub omega_dot: f64,
    pub idot: f64,
    /// The record's health word as in the file (meaning per system: see `ephemeris`).
    pub health: f64,
    /// Group delays, s: GPS/QZSS `[TGD, NaN]`; Galileo `[BGD E5a/E1, BGD E5b/E1]`; BeiDou `[TGD1, TGD2]`.
    pub tgd_s: [f64; 2],
    /// Issue of data (IODE / IODnav / AODE).
    pub iode: f64,
    /// User range accuracy or SISA, m (NaN where not given).
    pub accuracy_m: f64,
    /// Fit interval, hours (0 or NaN: the system default).
    pub fit_interval_h: f64,
    /// Galileo data-source bits (RINEX "data sources"; NaN for other systems): I/NAV vs F/NAV.
    pub data_source: f64,
}

/// A GLONASS broadcast record (PZ-90 state vector, treated as WGS-84).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlonassRecord {
    pub sat: SatId,
    /// Reference time tb, GPST ns since the GPS epoch.
    pub tb_gpst_ns: i64,
    /// RINEX `SV clock bias` = -tau_n, s.
    pub clock_bias_s: f64,
    /// Relative frequency bias gamma_n.
    pub gamma_n: f64,
    pub position_m: [f64; 3],
    pub velocity_m_s: [f64; 3],
    pub acceleration_m_s2: [f64; 3],
    /// FDMA channel number k (-7..=6).
    pub channel: i8,
    /// Health flag Bn (0 healthy).
    pub health: f64,
}

/// Everything read from the navigation files of a session.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NavData {
    pub kepler: Vec<KeplerRecord>,
    pub glonass: Vec<GlonassRecord>,
    /// GPS Klobuchar coefficients alpha0..3 and beta0..3 (`ION ALPHA`/`ION BETA` or `IONOSPHERIC CORR
    /// GPSA`/`GPSB`); `None` where the files give none.
    pub klobuchar: Option<[f64; 8]>,
    /// GPS - UTC leap seconds from the header, where given.
    pub leap_seconds: Option<i32>,
}
